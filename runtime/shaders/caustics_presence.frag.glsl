#version 450 core
// The caustics map's alpha: 1 where the receiver has a first
// surface seen from the light (its position map holds a depth), 0 where the
// frame is empty. Written after the irradiance (colour mask: alpha only)
// and before the mip chain, whose levels then hold the covered fraction;
// caustix.glsl divides the filtered irradiance by it, so filtering at the
// receiver's outline seen from the light (a sphere's terminator) does not
// mix in empty texels. A texel coarser than the position map's is
// judged by the same samples as caustics_levelmap.frag, which gives it the
// irradiance of the surface samples it holds (their windows' fractions sum
// to 1): present where any of them is, so that the division gives back
// that irradiance; photon splatting and the volumetric baseline give a
// texel the light over its whole area instead, so there it holds the
// fraction of the samples present (u_fraction). (Judged by its centre
// alone, an outline texel whose centre misses the surface held the full
// irradiance at alpha 0, and the division made its filtered neighbourhood
// too bright: +31 % at a 1 m sphere's terminator with 7.8 mm texels over
// 2 mm position texels.) The level maps' windows pass writes the same
// presence as it goes (caustics_windows.frag); this pass serves the other
// methods and maps summed over wavelengths.
layout(binding = 0) uniform sampler2D u_position;  // nearest (position_code.glsl)
uniform vec2 u_map_scale;                          // position-map texels per caustics-map texel
uniform int u_samples;                             // per axis, as caustics_levelmap.frag's
#define PRESENT(at) !position_empty(texelFetch(u_position, at, 0).r)
uniform int u_fraction;                            // 1: the fraction of samples present; 0: whether any is
out vec4 o_irradiance;
void main() {
  float present = 0.0;
  for (int j = 0; j < u_samples; ++j) {
    for (int i = 0; i < u_samples; ++i) {
      if (PRESENT(texel_sample(gl_FragCoord.xy, i, j, u_samples, u_map_scale))) present += 1.0;
    }
  }
  present /= float(u_samples * u_samples);
  o_irradiance = vec4(0.0, 0.0, 0.0, u_fraction != 0 ? present : (present > 0.0 ? 1.0 : 0.0));
}
