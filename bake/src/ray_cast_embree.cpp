// Embree 3 behind the plain interface of ray_cast.h.

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <limits>
#include <mutex>
#include <set>
#include <thread>

#include "caustix/bake/ray_cast.h"

namespace caustix::bake {

struct EmbreeCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Vec3d centre{0, 0, 0};  // subtracted from every position and origin
  std::mutex mutex;
  std::set<std::thread::id> builders;  // threads that took part in the build
  RTCRayHit ray(const Vec3d& o, const Vec3d& d) const {
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(o[0] - centre[0]);
    rh.ray.org_y = static_cast<float>(o[1] - centre[1]);
    rh.ray.org_z = static_cast<float>(o[2] - centre[2]);
    rh.ray.dir_x = static_cast<float>(d[0]);
    rh.ray.dir_y = static_cast<float>(d[1]);
    rh.ray.dir_z = static_cast<float>(d[2]);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return rh;
  }
};

EmbreeCaster::EmbreeCaster(const std::vector<Vec3d>& p, const std::vector<std::array<std::uint32_t, 3>>& tris)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  // One build thread: Embree's parallel builders may order a BVH's nodes by
  // which thread finished first, and with it which of two equally near
  // triangles (a ray through a shared edge) answers. Not by "threads=1":
  // with TBB tasking Embree turns that into a process-wide
  // tbb::global_control(max_allowed_parallelism, 1) for the device's life
  // (common/tasking/taskschedulertbb.cpp), which made every table trace on
  // one core and would cap an embedding application's TBB as well. Instead
  // the device is made inside a one-thread arena: Embree sizes the arena it
  // builds in by the concurrency it sees then (Device::initTaskingSystem).
  // Queries do not use it.
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { s.device = rtcNewDevice("verbose=0"); });
  if (!s.device) return;
  Vec3d lo = p.empty() ? Vec3d{0, 0, 0} : p[0], hi = lo;
  for (const Vec3d& q : p) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], q[k]);
      hi[k] = std::max(hi[k], q[k]);
    }
  }
  for (std::size_t k = 0; k < 3; ++k) s.centre[k] = 0.5 * (lo[k] + hi[k]);
  s.scene = rtcNewScene(s.device);
  rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris.size()));
  if (!v || !idx) {
    rtcReleaseGeometry(g);
    rtcReleaseScene(s.scene);
    rtcReleaseDevice(s.device);
    s.scene = nullptr;
    s.device = nullptr;
    return;
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(p[i][k] - s.centre[k]);
  }
  for (std::size_t i = 0; i < tris.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) idx[3 * i + k] = tris[i][k];
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(s.scene, g);
  rtcReleaseGeometry(g);
  // The threads that build it, counted by the progress monitor (Embree calls
  // it from each build task).
  rtcSetSceneProgressMonitorFunction(
      s.scene,
      [](void* self, double) {
        auto& impl = *static_cast<Impl*>(self);
        const std::lock_guard<std::mutex> lock(impl.mutex);
        impl.builders.insert(std::this_thread::get_id());
        return true;
      },
      &s);
  one_thread.execute([&] { rtcCommitScene(s.scene); });
  rtcSetSceneProgressMonitorFunction(s.scene, nullptr, nullptr);
  if (rtcGetDeviceError(s.device) != RTC_ERROR_NONE) {
    rtcReleaseScene(s.scene);
    rtcReleaseDevice(s.device);
    s.scene = nullptr;
    s.device = nullptr;
  }
}

EmbreeCaster::~EmbreeCaster() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

bool EmbreeCaster::ok() const { return impl_->scene != nullptr; }

std::size_t EmbreeCaster::build_threads() const { return impl_->builders.size(); }

std::optional<RayCaster::Hit> EmbreeCaster::first_hit_triangle(const Vec3d& o, const Vec3d& d) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = impl_->ray(o, d);
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return RayCaster::Hit{rh.ray.tfar, rh.hit.primID};
}

bool EmbreeCaster::occluded(const Vec3d& o, const Vec3d& d) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = impl_->ray(o, d);
  rtcOccluded1(impl_->scene, &context, &rh.ray);
  return rh.ray.tfar < 0;  // Embree sets tfar to -inf for a blocked ray
}

}  // namespace caustix::bake
