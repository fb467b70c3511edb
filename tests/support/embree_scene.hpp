// SPDX-License-Identifier: MIT
#pragma once
// Embree 3 (Debian's libembree-dev) as the reference the BVH tests and benchmarks compare
// against: one scene with one triangle mesh built from the same arrays vplkit's builder takes.
// Not part of the library. Link the imported target `embree` (find_package(embree 3 CONFIG)).
//
// Embree's conventions match bvh_closest_hit's: dir of any length, t in units of |dir|, u and v
// the barycentric weights of v1 and v2, primID the triangle's index. Embree accepts
// tnear <= t <= tfar where vplkit accepts tnear < t <= tfar; rays with a hit exactly at tnear are
// measure-zero in the random tests. RTC_SCENE_FLAG_ROBUST selects Embree's robust (watertight,
// Pluecker) triangle test and robust traversal, the closest match to vplkit's.
#include <vplkit/core/vector.hpp>

#include <embree3/rtcore.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace vplkit_test {

struct embree_hit {
  bool hit = false;
  float t = 0.0f;
  std::uint32_t triangle = ~0u;
  float u = 0.0f, v = 0.0f;
  vplkit::vec3<float> ng{0.0f};  // Embree's unnormalised geometric normal
};

// One Embree device (its thread pool): config is rtcNewDevice's string, e.g. "threads=1".
class embree_device {
 public:
  explicit embree_device(const char* config = nullptr) : device_(rtcNewDevice(config)) {
    if (device_ == nullptr) throw std::runtime_error("embree: rtcNewDevice failed");
  }
  embree_device(const embree_device&) = delete;
  embree_device& operator=(const embree_device&) = delete;
  ~embree_device() { rtcReleaseDevice(device_); }
  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_;
};

class embree_scene {
 public:
  // A scene on its own device (default configuration), medium build quality (Embree's default).
  embree_scene(const vplkit::vec3<float>* positions, std::size_t vertex_count, const std::uint32_t* indices,
               std::size_t index_count, bool robust = true)
      : own_device_(new embree_device()) {
    build(own_device_->get(), positions, vertex_count, indices, index_count, robust, RTC_BUILD_QUALITY_MEDIUM);
  }
  // A scene on a shared device (building many scenes: the benchmark).
  embree_scene(const embree_device& device, const vplkit::vec3<float>* positions, std::size_t vertex_count,
               const std::uint32_t* indices, std::size_t index_count, bool robust,
               RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM) {
    build(device.get(), positions, vertex_count, indices, index_count, robust, quality);
  }
  embree_scene(const embree_scene&) = delete;
  embree_scene& operator=(const embree_scene&) = delete;
  ~embree_scene() { rtcReleaseScene(scene_); }

  embree_hit intersect(vplkit::vec3<float> o, vplkit::vec3<float> d, float tnear = 0.0f,
                       float tfar = std::numeric_limits<float>::infinity()) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    set_ray(rh.ray, o, d, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    embree_hit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.hit = true;
    h.t = rh.ray.tfar;
    h.triangle = rh.hit.primID;
    h.u = rh.hit.u;
    h.v = rh.hit.v;
    h.ng = vplkit::vec3<float>(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    return h;
  }

  bool occluded(vplkit::vec3<float> o, vplkit::vec3<float> d, float tnear = 0.0f,
                float tfar = std::numeric_limits<float>::infinity()) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    set_ray(r, o, d, tnear, tfar);
    rtcOccluded1(scene_, &ctx, &r);
    return r.tfar == -std::numeric_limits<float>::infinity();  // Embree's mark for "occluded"
  }

 private:
  void build(RTCDevice device, const vplkit::vec3<float>* positions, std::size_t vertex_count,
             const std::uint32_t* indices, std::size_t index_count, bool robust, RTCBuildQuality quality) {
    scene_ = rtcNewScene(device);
    rtcSetSceneFlags(scene_, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene_, quality);
    if (index_count >= 3) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetGeometryBuildQuality(g, quality);
      // Embree allocates (and pads) its own buffers; the data is copied.
      auto* v = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertex_count));
      auto* i = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(std::uint32_t), index_count / 3));
      if (v == nullptr || i == nullptr) throw std::runtime_error("embree: buffer allocation failed");
      for (std::size_t k = 0; k < vertex_count; ++k) {
        v[3 * k] = positions[k].x;
        v[3 * k + 1] = positions[k].y;
        v[3 * k + 2] = positions[k].z;
      }
      std::memcpy(i, indices, (index_count / 3) * 3 * sizeof(std::uint32_t));
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene_, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene_);
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error("embree: error " + std::to_string(int(e)) + " building the scene");
  }

  static void set_ray(RTCRay& r, vplkit::vec3<float> o, vplkit::vec3<float> d, float tnear, float tfar) {
    r.org_x = o.x;
    r.org_y = o.y;
    r.org_z = o.z;
    r.tnear = tnear;
    r.dir_x = d.x;
    r.dir_y = d.y;
    r.dir_z = d.z;
    r.time = 0.0f;
    r.tfar = tfar;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
  }

  std::unique_ptr<embree_device> own_device_;
  RTCScene scene_ = nullptr;
};

}  // namespace vplkit_test
