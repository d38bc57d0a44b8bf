#version 450 core
// causticmap_density.frag: additive blending sums the photons' weights.
in float v_weight;
out vec4 o_count;
void main() { o_count = vec4(v_weight, 0.0, 0.0, 0.0); }
