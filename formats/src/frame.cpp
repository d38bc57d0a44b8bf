#include "caustix/formats/frame.h"

#include <algorithm>
#include <cmath>

namespace caustix {
namespace {

double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d normalize(const Vec3d& v) {
  const double n = std::sqrt(dot(v, v));
  return {v[0] / n, v[1] / n, v[2] / n};
}
Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3f to_f(const Vec3d& v) { return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])}; }

}  // namespace

std::vector<Vec3d> world_points(const Mat4f& t, const std::vector<Vec3f>& points) {
  std::vector<Vec3d> out;
  out.reserve(points.size());
  for (const Vec3f& p : points) {
    Vec3d w{};
    for (std::size_t k = 0; k < 3; ++k) {
      w[k] = double{t[k]} * p[0] + double{t[4 + k]} * p[1] + double{t[8 + k]} * p[2] + double{t[12 + k]};
    }
    out.push_back(w);
  }
  return out;
}

std::vector<Vec3d> world_normals(const Mat4f& m, const std::vector<Vec3f>& normals) {
  const Vec3d c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
  const Vec3d k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);  // cofactor columns
  const double sign = dot(c0, k0) < 0 ? -1.0 : 1.0;
  std::vector<Vec3d> out;
  out.reserve(normals.size());
  for (const Vec3f& n : normals) {
    Vec3d w{};
    for (std::size_t k = 0; k < 3; ++k) w[k] = sign * (k0[k] * n[0] + k1[k] * n[1] + k2[k] * n[2]);
    const double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (l > 0) {
      for (double& c : w) c /= l;
    }
    out.push_back(w);
  }
  return out;
}

std::vector<std::optional<std::uint32_t>> receiver_inside_glass(const SceneDesc& scene) {
  std::vector<std::array<Vec3d, 2>> boxes;
  for (const Object& o : scene.objects) {
    const MeshInfo& m = scene.meshes[o.mesh_index];
    std::vector<Vec3f> corners;
    for (int c = 0; c < 8; ++c) {
      corners.push_back({(c & 1) ? m.bounds_max[0] : m.bounds_min[0], (c & 2) ? m.bounds_max[1] : m.bounds_min[1],
                         (c & 4) ? m.bounds_max[2] : m.bounds_min[2]});
    }
    std::array<Vec3d, 2> b{Vec3d{1e300, 1e300, 1e300}, Vec3d{-1e300, -1e300, -1e300}};
    for (const Vec3d& w : world_points(o.transform, corners)) {
      for (std::size_t k = 0; k < 3; ++k) {
        b[0][k] = std::min(b[0][k], w[k]);
        b[1][k] = std::max(b[1][k], w[k]);
      }
    }
    boxes.push_back(b);
  }
  const auto holds = [](const std::array<Vec3d, 2>& a, const std::array<Vec3d, 2>& b) {
    for (std::size_t k = 0; k < 3; ++k) {
      if (b[0][k] < a[0][k] || b[1][k] > a[1][k]) return false;
    }
    return true;
  };
  std::vector<std::optional<std::uint32_t>> out(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!is_transparent(scene.objects[i].role)) continue;
    for (std::uint32_t j = 0; !out[i] && j < scene.objects.size(); ++j) {
      if (j != i && scene.objects[j].role == Role::kReceiver && holds(boxes[i], boxes[j])) out[i] = j;
    }
  }
  return out;
}

std::optional<Vec3d> refract(const Vec3d& i, const Vec3d& n, double eta) {
  const double cos_i = std::clamp(-dot(i, n), 0.0, 1.0);
  const double sin2_r = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_r > 1.0) return std::nullopt;  // total internal reflection
  const double cos_r = std::sqrt(1.0 - sin2_r);
  const double a = eta * cos_i - cos_r;  // eq. 2-8
  return normalize({a * n[0] + eta * i[0], a * n[1] + eta * i[1], a * n[2] + eta * i[2]});
}

double fresnel_transmittance(double cos_i, double eta) {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return 0.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  // Fresnel amplitudes with n1 / n2 = eta (divide through by n2).
  const double rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const double rp = (eta * cos_t - cos_i) / (eta * cos_t + cos_i);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

std::optional<LightDirection> light_direction(const Light& light, const std::optional<Water>& water,
                                              const Vec3d& origin, double min_y, double max_y,
                                              std::string* why_not) {
  auto fail = [&](const std::string& why) -> std::optional<LightDirection> {
    if (why_not) *why_not = why;
    return std::nullopt;
  };
  Vec3d incident{};
  if (light.type == LightType::kDirectional) {
    incident = normalize({light.direction[0], light.direction[1], light.direction[2]});
  } else {
    // Fig. 4-7: the ray from the point light to the object's origin.
    const Vec3d d = sub(origin, {light.position[0], light.position[1], light.position[2]});
    if (dot(d, d) < 1e-24) return fail("the point light sits at the object's origin");
    incident = normalize(d);
  }
  if (!water || min_y >= water->level) return LightDirection{incident, false};  // no water, or above it
  if (light.type == LightType::kPoint && light.position[1] <= water->level) {
    if (max_y > water->level) return fail("the point light is under water and the object reaches above it");
    return LightDirection{incident, false};  // both under water: no surface in between
  }
  if (incident[1] >= 0) {
    return fail(incident[1] == 0 ? "the light travels parallel to the water surface and never enters it"
                                 : "the light travels upward and never enters the water");
  }
  // Air -> water through the flat surface (normal +y on the incident side);
  // for a flat surface T does not depend on where the ray crosses it.
  const auto t = refract(incident, {0, 1, 0}, 1.0 / water->ior);
  if (!t) return fail("total internal reflection at the water surface");
  return LightDirection{*t, true};
}

BoundingFrame make_frame(const Vec3d& travel, const std::vector<Vec3d>& pts, const Vec3d& object_origin) {
  const Vec3d v = normalize({-travel[0], -travel[1], -travel[2]});
  // N: the world axis least aligned with V (never parallel to it).
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::fabs(v[static_cast<std::size_t>(k)]) < std::fabs(v[static_cast<std::size_t>(axis)])) axis = k;
  }
  Vec3d n{0, 0, 0};
  n[static_cast<std::size_t>(axis)] = 1;
  const Vec3d u = normalize(cross(v, n));  // eq. 4-1
  const Vec3d w = cross(u, v);
  const std::array<Vec3d, 3> axes{u, v, w};

  Vec3d lo{}, hi{}, sym{};
  for (std::size_t k = 0; k < 3; ++k) {
    lo[k] = hi[k] = dot(pts.at(0), axes[k]);
  }
  for (const Vec3d& p : pts) {
    const Vec3d rel = sub(p, object_origin);
    for (std::size_t k = 0; k < 3; ++k) {
      const double c = dot(p, axes[k]);
      lo[k] = std::min(lo[k], c);
      hi[k] = std::max(hi[k], c);
      sym[k] = std::max(sym[k], 2.0 * std::fabs(dot(rel, axes[k])));
    }
  }
  BoundingFrame f;
  Vec3d half{};
  for (std::size_t k = 0; k < 3; ++k) half[k] = 0.5 * (hi[k] - lo[k]);
  const double floor_extent = 1e-6 * std::max({half[0], half[1], half[2], 1e-9});
  for (std::size_t k = 0; k < 3; ++k) {
    const double mid = 0.5 * (lo[k] + hi[k]);
    for (std::size_t j = 0; j < 3; ++j) f.origin[j] += mid * axes[k][j];
    half[k] = std::max(half[k], floor_extent);
  }
  f.u = to_f(u);
  f.v = to_f(v);
  f.w = to_f(w);
  f.half = to_f(half);
  f.symmetric_size = to_f(sym);
  return f;
}

std::optional<Vec3d> plane_normal(const std::vector<Vec3d>& p) {
  if (p.size() < 3) return std::nullopt;
  const auto farthest = [&](auto&& measure) {
    std::size_t best = 0;
    double most = -1;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double m = measure(p[i]);
      if (m > most) most = m, best = i;
    }
    return best;
  };
  const Vec3d a = p[0];
  const Vec3d ab = sub(p[farthest([&](const Vec3d& x) { return dot(sub(x, a), sub(x, a)); })], a);
  const Vec3d c = p[farthest([&](const Vec3d& x) { const Vec3d n = cross(ab, sub(x, a)); return dot(n, n); })];
  const Vec3d n = cross(ab, sub(c, a));
  const double len = std::sqrt(dot(n, n)), extent = std::sqrt(dot(ab, ab));
  if (extent <= 0 || len <= 1e-12 * extent * extent) return std::nullopt;
  const Vec3d u = normalize(n);
  for (const Vec3d& x : p) {
    if (std::fabs(dot(sub(x, a), u)) > 1e-6 * extent) return std::nullopt;
  }
  return u;
}

}  // namespace caustix
