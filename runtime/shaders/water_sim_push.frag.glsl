#version 450 core
// The submerged length of a closed body along each vertical column, summed
// by additive blending: a column enters the body through upward faces and
// leaves through downward ones, so its length below the rest level L is
// sum_up min(y, L) - sum_down min(y, L). The renderer sets the front face so
// that upward faces are front-facing.
in float v_y;

uniform float u_level;

layout(location = 0) out float o_length;

void main() {
  float y = min(v_y, u_level);
  o_length = gl_FrontFacing ? y : -y;
}
