#pragma once
// Chunk tags of the .cxb format: the one registry, shared by the baker, the
// runtime and the inspector. Adding a tag is a minor change; changing what a
// tag's payload means needs a new tag or a format version bump (SPEC.md).

#include <array>
#include <cstdint>
#include <string>

namespace caustix::cxb {

struct Tag {
  std::array<char, 4> c{};
  constexpr bool operator==(const Tag&) const = default;
  // Printable form: the four characters, or \xNN escapes for other bytes.
  std::string str() const;
};

constexpr Tag make_tag(const char (&s)[5]) { return Tag{{s[0], s[1], s[2], s[3]}}; }

// Scene description (formats/scene.h documents each payload).
inline constexpr Tag kTagScene = make_tag("SCNE");    // required, once
inline constexpr Tag kTagObjects = make_tag("OBJS");  // required, once
inline constexpr Tag kTagLights = make_tag("LGHT");   // required, once
inline constexpr Tag kTagWater = make_tag("WATR");    // required if present, at most once
inline constexpr Tag kTagCamera = make_tag("CAMR");   // optional, at most once
inline constexpr Tag kTagRender = make_tag("RNDR");   // optional, at most once: runtime defaults of a preset
inline constexpr Tag kTagMesh = make_tag("MESH");     // required, one per mesh, in mesh order
inline constexpr Tag kTagMedia = make_tag("MDIA");    // required if present, at most once: media and scattering
inline constexpr Tag kTagMirrors = make_tag("MIRR");  // required if present, at most once: mirrors' reflectance
inline constexpr Tag kTagDispersion = make_tag("DISP");  // required if present, at most once: dispersion
inline constexpr Tag kTagSpots = make_tag("SPOT");       // required if present, at most once: spot lights' cones
inline constexpr Tag kTagTint = make_tag("TINT");        // required if present, at most once: transparent objects' tints
inline constexpr Tag kTagTextures = make_tag("TEXR");    // optional, at most once: receivers' albedo textures
inline constexpr Tag kTagSurfaces = make_tag("SURF");    // optional, at most once: receivers' metallic, roughness, emission
inline constexpr Tag kTagSurfaceMaps = make_tag("TEXM");  // optional, at most once: receivers' maps beyond the base colour, alpha modes and images' alpha
// Level maps (formats/level_map.h).
inline constexpr Tag kTagLevelMap = make_tag("LMAP");     // required, one per (receiver, light) baked
inline constexpr Tag kTagObjectBoxes = make_tag("OBBS");  // optional (culling), at most once
// Light-transport tables (formats/light_transport.h).
inline constexpr Tag kTagTransport = make_tag("LTTB");  // required, one per transparent object
inline constexpr Tag kTagSpectralTransport = make_tag("LTTS");  // required if present: tables at other wavelengths
inline constexpr Tag kTagTransportSwitches = make_tag("LTTW");  // optional, at most one per table: where its path class switches
inline constexpr Tag kTagTransportShared = make_tag("LTTR");  // required if present, at most once: objects that use another's tables
// Index grids for media (formats/index_grid.h).
inline constexpr Tag kTagIndexGrid = make_tag("IGRD");  // required, one per transparent object of a scattering scene

// Whether this build knows a tag. Unknown optional chunks are skipped;
// unknown required chunks make the reader refuse the file.
bool is_known_tag(Tag tag);

}  // namespace caustix::cxb
