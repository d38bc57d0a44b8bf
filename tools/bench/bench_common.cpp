#include "bench_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace caustix::bench {

CsvOut::CsvOut(const std::string& path, const std::string& header) {
  if (!path.empty()) file_.open(path);
  row(header);
}

void CsvOut::row(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
  if (file_) file_ << line << "\n" << std::flush;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Result<Session> open_scene(const std::string& cxb) {
  auto scene = runtime::load_scene_file(cxb);
  if (!scene) return scene.error();
  auto ctx = runtime::HeadlessContext::create();
  if (!ctx) return ctx.error();
  auto r = sample::Renderer::create(*scene);
  if (!r) return r.error();
  return Session{std::move(*ctx), std::move(*r)};
}

Result<FrameTimes> time_frames(sample::Renderer& r, const runtime::CausticsOptions& co, int width, int height,
                               int warmup, int count, bool move_light, const runtime::WaterLook& look,
                               const std::optional<Camera>& camera, const runtime::GlassViewOptions& glass_view,
                               int supersample, std::vector<runtime::GpuTimes>* gpu, bool still, std::uint32_t out_of_view) {
  sample::FrameParams f{camera.value_or(r.default_camera()), 0.0f, width, height, co, look, glass_view, {}, supersample};
  f.out_of_view_interval = out_of_view;
  r.engine().set_gpu_timing(gpu != nullptr, gpu != nullptr);  // with the pipeline's counts per pass
  std::vector<double> ms;
  for (int i = 0; i < warmup + count; ++i) {
    f.time = still ? 0.0f : static_cast<float>(i) / 30.0f;
    const auto t = Clock::now();
    if (move_light && !r.scene().lights.empty()) {
      Light l = r.scene().lights[0];
      const float c = std::cos(0.0349f), sn = std::sin(0.0349f);
      const float x = l.direction[0], z = l.direction[2];
      l.direction[0] = c * x - sn * z;
      l.direction[2] = sn * x + c * z;
      if (Status st = r.set_light(0, l); !st) return st.error();
    }
    if (Status st = r.render(f); !st) return st.error();
    r.finish();
    if (i >= warmup) ms.push_back(ms_since(t));
    if (gpu && i > warmup) gpu->push_back(r.engine().gpu_times());  // the frame before: its queries have completed
  }
  return FrameTimes{median(ms), *std::min_element(ms.begin(), ms.end())};
}

}  // namespace caustix::bench
