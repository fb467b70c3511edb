// SPDX-License-Identifier: MIT
#include "render/cpu/ray_scene.hpp"

#include "scene/texture.hpp"

#include <vplkit/visibility/bvh_visibility.hpp>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vplrender {

namespace {

bool finite3(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Embree counts hits at t >= tnear, the pack BVH at t > 0: tnear = FLT_MIN makes Embree's range
// (0, t_max] too. It matters where a moved-off origin lies exactly on another surface (a point on
// the edge where floor and wall meet, moved along the floor's normal, is still on the wall):
// with tnear = 0 Embree reports that wall at t = 0 and the ray goes nowhere.
void set_ray(RTCRay& r, vec3 o, vec3 d, float t_max) {
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.tnear = std::numeric_limits<float>::min();
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.time = 0.0f;
  r.tfar = t_max;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
}

}  // namespace

struct ray_scene::embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~embree() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

ray_scene::ray_scene(const scene& s) : source_(s), rt_(std::make_unique<embree>()) {
  rt_->device = rtcNewDevice(nullptr);
  if (rt_->device == nullptr) throw std::runtime_error("embree: rtcNewDevice failed");
  rt_->scene = rtcNewScene(rt_->device);
  // Robust: Embree's watertight triangle test and conservative traversal (the pack BVH's
  // guarantees: no ray slips between triangles that share an edge).
  rtcSetSceneFlags(rt_->scene, RTC_SCENE_FLAG_ROBUST);
  const std::size_t n = source_.triangles.size();
  if (n > 0) {
    RTCGeometry g = rtcNewGeometry(rt_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), n));
    if (v == nullptr || idx == nullptr) throw std::runtime_error("embree: buffer allocation failed");
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const vec3& p = source_.triangles[i].p[c];
        v[9 * i + 3 * c] = p.x;
        v[9 * i + 3 * c + 1] = p.y;
        v[9 * i + 3 * c + 2] = p.z;
        idx[3 * i + c] = static_cast<std::uint32_t>(3 * i + c);
      }
    rtcCommitGeometry(g);
    rtcAttachGeometry(rt_->scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(rt_->scene);
  const RTCError e = rtcGetDeviceError(rt_->device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error("embree: error " + std::to_string(int(e)) + " building the scene");

  // vplkit::bvh_surface_offset over the root box, which is the triangles' exact box.
  const aabb box = bounds(source_.triangles);
  const vec3 ext = box.hi - box.lo;
  const float d = std::fmax(ext.x, std::fmax(ext.y, ext.z));
  const vec3 m3(std::fmax(std::abs(box.lo.x), std::abs(box.hi.x)), std::fmax(std::abs(box.lo.y), std::abs(box.hi.y)),
                std::fmax(std::abs(box.lo.z), std::abs(box.hi.z)));
  const float m = std::fmax(m3.x, std::fmax(m3.y, m3.z));
  size_ = n == 0 ? 0.0f : d;
  offset_ = n == 0 ? 0.0f
                   : float(vplkit::bvh_offset_relative_default) * d + float(vplkit::bvh_offset_coordinate_scale) * m;
}

ray_scene::~ray_scene() = default;

ray_scene::hit ray_scene::intersect(vec3 origin, vec3 dir, float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  set_ray(rh.ray, origin, dir, t_max);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rt_->scene, &ctx, &rh);
  hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.triangle = rh.hit.primID;
  h.u = rh.hit.u;
  h.v = rh.hit.v;
  const triangle& tri = source_.triangles[h.triangle];
  h.position = (1.0f - h.u - h.v) * tri.p[0] + h.u * tri.p[1] + h.v * tri.p[2];
  const vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float len = std::sqrt(ng.x * ng.x + ng.y * ng.y + ng.z * ng.z);
  h.geometric_normal = len > 0.0f && std::isfinite(len) ? ng / len : vec3(0.0f);
  return h;
}

bool ray_scene::occluded(vec3 origin, vec3 dir, float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  set_ray(r, origin, dir, t_max);
  rtcOccluded1(rt_->scene, &ctx, &r);
  return r.tfar == -std::numeric_limits<float>::infinity();  // Embree's mark for "occluded"
}

bool ray_scene::visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y) const {
  if (!finite3(x) || !finite3(y)) return false;
  const vec3 o = vplkit::bvh_offset_point(x, n_x, offset_);
  const vec3 p = vplkit::bvh_offset_point(y, n_y, offset_);
  return !occluded(o, p - o, 1.0f);
}

vplkit::ray_hit<float> ray_scene::trace(vec3 x, vec3 n_x, vec3 dir, float reach) const {
  vplkit::ray_hit<float> r;
  if (!finite3(x) || !finite3(dir) || !(reach >= 0.0f)) return r;
  // A hit within reach of x lies within reach + offset of the moved origin (t in units of |dir|).
  const float t_max = std::isinf(reach) ? reach : (reach + offset_) / std::sqrt(glm::dot(dir, dir));
  const hit h = intersect(vplkit::bvh_offset_point(x, n_x, offset_), dir, t_max);
  r.hit = h.hit;
  if (h.hit) {
    r.position = h.position;
    // Both normals (the estimate kernels' exact tracer gives the same): the library shades the hit as its
    // own surface with the shading normal's cosine, as the exact method does (on sponza's smoothed
    // arches the geometric normal lights 2.2 % of the one-bounce light that the shading normal
    // turns away from the light).
    r.normal = h.geometric_normal;
    r.shading_normal = shading_normal(h);
  }
  return r;
}

vec3 ray_scene::shading_normal(const hit& h) const {
  const triangle& tri = source_.triangles[h.triangle];
  const vec3 n = (1.0f - h.u - h.v) * tri.n[0] + h.u * tri.n[1] + h.v * tri.n[2];
  const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  return len > 0.0f && std::isfinite(len) ? n / len : h.geometric_normal;
}

vec3 ray_scene::albedo_at(const hit& h) const {
  const triangle& tri = source_.triangles[h.triangle];
  const vec2 uv = (1.0f - h.u - h.v) * tri.uv[0] + h.u * tri.uv[1] + h.v * tri.uv[2];
  return albedo(source_, source_.materials[tri.material], uv);
}

}  // namespace vplrender
