// Focus windows: where the sampled exit rays concentrate, a square of the
// receiver's frame drawn again at finer texels (docs/glass-focus.md, "Focus
// windows"), placed on the CPU from the table's sample and resolved on the
// GPU where it was drawn coarse.
#include "glass_impl.h"

namespace caustix::runtime {

auto GlassEngine::Impl::focus_window(const Target& t, const std::vector<SampledRay>& rays, const std::vector<bool>& skip,
                                     const std::array<float, 3>& previous, int size) -> std::array<float, 3> {
  const glm::vec3 origin(static_cast<float>(t.frame.origin[0]), static_cast<float>(t.frame.origin[1]),
                         static_cast<float>(t.frame.origin[2]));
  const glm::vec3 U(t.frame.u[0], t.frame.u[1], t.frame.u[2]), V(t.frame.v[0], t.frame.v[1], t.frame.v[2]),
      W(t.frame.w[0], t.frame.w[1], t.frame.w[2]);
  const double hu = t.frame.half[0], hw = t.frame.half[2];
  const double cell_area = (2 * hu / kFocusBins) * (2 * hw / kFocusBins);
  std::vector<double> flux(kFocusBins * kFocusBins);
  std::vector<int> count(kFocusBins * kFocusBins);
  int lo[2] = {kFocusBins, kFocusBins}, hi[2] = {-1, -1};
  for (const float plane : t.plane_v) {
    std::fill(flux.begin(), flux.end(), 0.0);
    std::fill(count.begin(), count.end(), 0);
    for (const SampledRay& r : rays) {
      if (skip[r.object]) continue;
      // As glass_geometry.comp cuts a ray with a plane.
      const float along = -glm::dot(r.direction, V);
      const glm::vec3 rel = r.exit - origin;
      const float s = (glm::dot(rel, V) - plane) / std::max(along, 1e-6f);
      if (along <= 1e-4f || s < 0.0f) continue;
      const glm::vec3 x = rel + s * r.direction;
      const double fu = std::floor((glm::dot(x, U) + hu) / (2 * hu) * kFocusBins);
      const double fw = std::floor((glm::dot(x, W) + hw) / (2 * hw) * kFocusBins);
      if (!(fu >= 0 && fw >= 0 && fu < kFocusBins && fw < kFocusBins)) continue;  // outside, or not finite
      const int i = static_cast<int>(fu), j = static_cast<int>(fw);
      flux[static_cast<std::size_t>(j * kFocusBins + i)] += r.flux;
      ++count[static_cast<std::size_t>(j * kFocusBins + i)];
    }
    for (int j = 0; j < kFocusBins; ++j) {
      for (int i = 0; i < kFocusBins; ++i) {
        const std::size_t c = static_cast<std::size_t>(j * kFocusBins + i);
        if (count[c] < kFocusMinRays || flux[c] < kFocusConcentration * cell_area) continue;
        lo[0] = std::min(lo[0], i);
        lo[1] = std::min(lo[1], j);
        hi[0] = std::max(hi[0], i);
        hi[1] = std::max(hi[1], j);
      }
    }
  }
  if (hi[0] < 0) return {0, 0, 0};
  // The concentrated cells and one more on every side, in texture
  // coordinates (cell i spans [i, i + 1] / kFocusBins).
  const float u0 = static_cast<float>(lo[0] - 1) / kFocusBins, u1 = static_cast<float>(hi[0] + 2) / kFocusBins;
  const float v0 = static_cast<float>(lo[1] - 1) / kFocusBins, v1 = static_cast<float>(hi[1] + 2) / kFocusBins;
  const float needed = std::max({0.5f * (u1 - u0), 0.5f * (v1 - v0), kFocusMinHalf});
  if (needed > kFocusMaxHalf) return {0, 0, 0};
  // Stable as the light moves (docs/glass-focus.md, "A window that holds
  // still"). The half-size is the next of the steps kFocusMinHalf x
  // 2^(k/4) at or above what is needed, so that nearby placements agree
  // on it; the last window stays while it holds the concentrated cells
  // and is not more than two steps larger, so a focus that drifts moves
  // its window rarely. A new window's corner lies on a multiple of its
  // texel, so that one moved at the same half-size keeps its texels where
  // they were on the target: the light drawn into them does not change
  // where the window went on covering it.
  const float half = std::min(kFocusMaxHalf, kFocusMinHalf * std::exp2(std::ceil(4.0f * std::log2(needed / kFocusMinHalf) - 1e-4f) / 4.0f));
  const auto holds = [&](const std::array<float, 3>& w) {
    return w[2] > 0 && w[0] - w[2] <= u0 && u1 <= w[0] + w[2] && w[1] - w[2] <= v0 && v1 <= w[1] + w[2];
  };
  if (holds(previous) && previous[2] <= half * std::sqrt(2.0f) * 1.0001f) return previous;
  const float texel = 2.0f * half / (kFocusTexels * static_cast<float>(std::max(size, 1)));
  const auto corner = [&](float lo_edge, float hi_edge) { return std::round((0.5f * (lo_edge + hi_edge) - half) / texel) * texel; };
  std::array<float, 3> w{corner(u0, u1) + half, corner(v0, v1) + half, half};
  if (!holds(w)) w = {0.5f * (u0 + u1), 0.5f * (v0 + v1), half};  // the rounding took a side out (half == needed)
  return w;
}

auto GlassEngine::Impl::window_squares(int size) -> WindowSquares {
  WindowSquares sq;
  sq.side = static_cast<int>(std::ceil(kFocusTexels * static_cast<float>(size)));
  sq.coarse_side = (sq.side + 1) / 2;
  sq.coarse = sq.side + sq.coarse_side <= size;
  return sq;
}

void GlassEngine::Impl::resolve_window(const Target& t) {
  const WindowSquares sq = window_squares(t.size);
  const gl::TimedPass timed("glass: window resolve", gl::PassKind::kCompute);
  window_resolve.use();
  window_resolve.set("u_side", sq.side);
  window_resolve.set("u_coarse", sq.side);
  window_resolve.set("u_coarse_side", sq.coarse_side);
  window_resolve.set("u_first_layer", static_cast<int>(t.planes));
  glBindImageTexture(0, t.illumination.get(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
  glDispatchCompute(static_cast<GLuint>((sq.side + 7) / 8), static_cast<GLuint>((sq.side + 7) / 8), t.planes);
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  glClearTexSubImage(t.illumination.get(), 0, sq.side, sq.side, static_cast<GLint>(t.planes), sq.coarse_side, sq.coarse_side,
                     static_cast<GLsizei>(t.planes), GL_RGBA, GL_FLOAT, nullptr);
}

}  // namespace caustix::runtime
