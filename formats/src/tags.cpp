#include "caustix/formats/tags.h"

#include <cstdio>

namespace caustix::cxb {

std::string Tag::str() const {
  std::string s;
  for (char ch : c) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x20 && u < 0x7f) {
      s += ch;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      s += buf;
    }
  }
  return s;
}

bool is_known_tag(Tag tag) {
  for (Tag known : {kTagScene, kTagObjects, kTagLights, kTagWater, kTagCamera, kTagRender, kTagMesh, kTagMedia, kTagMirrors, kTagDispersion, kTagSpots, kTagTint, kTagTextures, kTagSurfaces, kTagSurfaceMaps, kTagLevelMap, kTagObjectBoxes, kTagTransport, kTagSpectralTransport, kTagTransportShared, kTagTransportSwitches, kTagIndexGrid}) {
    if (tag == known) return true;
  }
  return false;
}

}  // namespace caustix::cxb
