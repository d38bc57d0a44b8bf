#version 450 core
// Slice mask (1) or the run-time position map's code of frame V
// (position_code.glsl: an R16 target stores round(t 65534) of
// t = (half_v - v) / (2 half_v), as the baker does; the depth test keeps
// the largest V).
in float v_depth;
uniform int u_write_depth;
uniform float u_half_v;
out float o_value;
// Clamped as the baker clamps: a flat receiver's frame is a few
// micrometres tall, and a surface point's V rounded past its side must not
// come out as 65535, no surface.
void main() {
  o_value = u_write_depth != 0 ? clamp((u_half_v - v_depth) / (2.0 * u_half_v), 0.0, 1.0) * (65534.0 / 65535.0) : 1.0;
}
