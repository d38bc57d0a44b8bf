#include "caustix/sample/motion.h"

#include <cmath>
#include <optional>
#include <utility>

namespace caustix::sample {

Light turned_about_z(Light light, double degrees) {
  const double a = degrees * 3.14159265358979323846 / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  auto turn = [&](std::array<float, 3>& v) {
    const double x = v[0], y = v[1];
    v[0] = static_cast<float>(c * x - s * y);
    v[1] = static_cast<float>(s * x + c * y);
  };
  turn(light.direction);
  if (light.type == LightType::kPoint) turn(light.position);
  return light;
}

Result<std::vector<StackFrame>> render_stack(Renderer& r, const StackRequest& q, const Motion& m, double step) {
  if (m.kind == MotionKind::kLight && r.scene().lights.empty()) return make_error(ErrorCode::kUsage, "the scene has no light to turn");
  std::optional<std::uint32_t> object;
  if (m.kind == MotionKind::kObject) {
    for (std::uint32_t i = 0; i < r.scene().objects.size(); ++i) {
      if (r.scene().objects[i].name == m.object) object = i;
    }
    if (!object) return make_error(ErrorCode::kUsage, "no object named '" + m.object + "' in the scene");
  }
  const Light light0 = r.scene().lights.empty() ? Light{} : r.scene().lights[0];
  const Mat4f transform0 = object ? r.scene().objects[*object].transform : Mat4f{};
  // Back where it started, whatever happens below.
  const auto restore = [&]() -> Status {
    if (m.kind == MotionKind::kLight) return r.set_light(0, light0);
    if (object) return r.set_object_transform(*object, transform0);
    return Status::success();
  };
  std::vector<StackFrame> frames;
  for (int k = 0; k < q.frames; ++k) {
    const double at = k * step;
    float time = static_cast<float>(q.time);
    Status moved = Status::success();
    if (m.kind == MotionKind::kLight) {
      moved = r.set_light(0, turned_about_z(light0, at));
    } else if (m.kind == MotionKind::kWater) {
      time = static_cast<float>(q.time + at);
    } else {
      Mat4f t = transform0;
      t[12] += static_cast<float>(at);
      moved = r.set_object_transform(*object, t);
    }
    if (!moved.ok()) {
      (void)restore();
      return moved.error();
    }
    const auto& g = q.region;
    StackFrame f;
    if (q.inscatter) {
      InscatterRequest iq{g[0], g[1], g[2], g[3], q.size, q.size, time, q.caustics, q.pixel_samples};
      auto img = r.render_inscatter(iq);
      if (!img) {
        (void)restore();
        return img.error();
      }
      f = {img->width, img->height, std::move(img->rgb)};
    } else {
      IrradianceRequest iq{q.receiver, g[0], g[1], g[2], g[3], q.size, q.size, time, q.caustics, q.pixel_samples};
      auto img = r.render_irradiance(iq);
      if (!img) {
        (void)restore();
        return img.error();
      }
      f = {img->width, img->height, std::move(img->rgb)};
    }
    frames.push_back(std::move(f));
  }
  if (Status st = restore(); !st.ok()) return st.error();
  return frames;
}

}  // namespace caustix::sample
