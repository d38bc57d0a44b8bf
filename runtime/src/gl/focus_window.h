#pragma once
// Focus windows: finer texels where light concentrates. Shared by
// the glass tables' windows (glass.cpp, placed from the CPU sample of the
// tables' exit rays) and the caustic maps' (causticmap.cpp and
// causticmap_focus.comp, placed on the GPU from the landed photons).
// Internal to the runtime.

namespace caustix::runtime::focus {

// Cells a side over the target's frame or the caustic map, in which the
// light landing is counted (causticmap_focus.comp's and
// causticmap_splat.vert's kBins).
constexpr int kBins = 128;
// A cell is concentrated where the light landing in it is at least this
// many times what its area would catch straight from the light...
constexpr double kConcentration = 4.0;
// ...from at least this many rays or photons.
constexpr int kMinSamples = 4;
// The window is the square around the concentrated cells and one cell
// more: none larger than this half-size of the frame (the main texture does
// nearly as well there), none smaller than kMinHalf.
constexpr float kMaxHalf = 0.25f;
constexpr float kMinHalf = 0.5f / 64.0f;
// The window's texels a side, as a fraction of the main texture's.
constexpr float kTexels = 0.5f;

}  // namespace caustix::runtime::focus
