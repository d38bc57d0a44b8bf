// Slice mask (1) or the run-time position map's code of frame V
// (position_code.glsl, prefixed after #version; the depth test keeps the
// largest V).
in float v_depth;
uniform int u_write_depth;
uniform float u_half_v;
out float o_value;
void main() { o_value = u_write_depth != 0 ? position_code(v_depth, u_half_v) : 1.0; }
