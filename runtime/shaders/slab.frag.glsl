#version 450 core
// Slice mask (1) or the run-time position map's frame depth (largest V wins
// by depth test).
in float v_depth;
uniform int u_write_depth;
out float o_value;
void main() { o_value = u_write_depth != 0 ? v_depth : 1.0; }
