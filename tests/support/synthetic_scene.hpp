// SPDX-License-Identifier: MIT
#pragma once
// A small closed test scene with real occluders, shared by the builder and estimator tests (not
// part of the library). Header-only, namespace vplkit_test, T = double or float.
//
// Geometry (world units, y up), 24 triangles:
//   room  [-2, 2] x [0, 3] x [-2, 2], six walls with inward normals and different albedos:
//         floor y = 0 grey, ceiling y = 3 light grey, x = -2 red, x = +2 green, z = -2 bluish,
//         z = +2 dark grey. Closed: every ray from inside hits something.
//   block [-1.0, 0.4] x [0.8, 1.2] x [-0.8, 0.6], a floating slab with outward normals and a
//         yellowish albedo, between the light and the middle of the floor: the floor under it is
//         in shadow (no direct light) and receives only indirect light.
//   light point light at (0.3, 2.6, 0.2), intensity (8, 7, 6) W/sr, DPRSM front axis (0, -1, 0)
//         (front paraboloid looks down at the floor, back paraboloid at the ceiling).
// Per triangle: geometric normal (unit, the side facing the room's air) and albedo.
//
// Exact ray casting: brute-force Moller-Trumbore over all triangles (inclusive edges, so no
// cracks along the quads' diagonals). Surface points are lifted by surface_epsilon() along their
// normal before rays leave them, so a surface never occludes itself.
//
// What the fixture offers (interface kept stable for the builder and estimator tests):
//   synthetic_scene<T> s;                     // default scene above
//   s.positions, s.indices, s.tri_normal, s.tri_albedo, s.light, s.triangle_count()
//   s.intersect(origin, dir, t_max)           -> scene_hit<T> (dir any length; t = world distance)
//   s.trace_from_light(origin, dir)           -> std::optional<dprsm_hit<T>> (render_dprsm's tracer)
//   s.visible(x, n_x, y, n_y)                 exact mutual visibility of two surface points
//   s.trace(x, n_x, dir)                      -> vplkit::ray_hit<T>, first hit leaving surface x
//                                                (with the triangle's geometric normal)
//   s.lit(y, n_y)                             exact shadow ray from y to the light
//   s.make_dprsm(R)                           -> dprsm_data<T> (owns arrays; .view())
//   s.make_voxel_grid(res = 32)               -> vplkit::voxel_grid<T> over fit_voxel_bounds
//   s.make_gbuffer(w = 16, h = 16)            -> gbuffer_data<T> (owns arrays; .view())
//   s.gather_points()                         -> std::vector<named_gather_point<T>>
//   exact_visibility<T>{&s}, exact_tracer<T>{&s}: the callables estimators / builders take.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace vplkit_test {

using vplkit::vec3;

template <class T>
struct scene_hit {
  bool hit = false;
  T t = T(0);                   // world distance along the normalised direction
  int triangle = -1;
  vec3<T> position{T(0)};
  vec3<T> normal{T(0)};         // unit geometric normal of the triangle hit
  vec3<T> albedo{T(0)};
};

template <class T>
struct named_gather_point {
  std::string name;
  vplkit::gather_point<T> gp;
  bool in_shadow;  // no direct light from the point light (for documentation and tests)
};

// Owns the 2 R^2 texel arrays of a DPRSM; view() points into them (valid while this lives; the
// vectors' storage survives a move, not a copy -- rebuild the view after copying).
template <class T>
struct dprsm_data {
  int resolution = 0;
  vplkit::point_light<T> light{};
  std::vector<vec3<T>> position, normal, albedo;
  vplkit::dprsm_view<T> view() const {
    return vplkit::dprsm_view<T>{resolution, position.data(), normal.data(), albedo.data(), light};
  }
};

// The DPRSM of `light` at resolution R, each texel's point found by trace(origin, direction) (an
// optional dprsm_hit: nothing seen when empty).
template <class T, class Trace>
dprsm_data<T> render_dprsm_data(const vplkit::point_light<T>& light, int R, Trace&& trace) {
  dprsm_data<T> d;
  d.resolution = R;
  d.light = light;
  vplkit::render_dprsm(light, R, trace, d.position, d.normal, d.albedo);
  return d;
}

// Row-major w x h G-buffer of a pinhole camera (owns the arrays; view() as for dprsm_data).
// Every pixel of the closed room hits a surface; set a pixel's normal to 0 to make background.
template <class T>
struct gbuffer_data {
  int width = 0, height = 0;
  std::vector<vec3<T>> position, normal, albedo;
  std::vector<vec3<T>> shading_normal;  // empty: none (the geometric normals shade)
  vplkit::gbuffer_view<T> view() const {
    vplkit::gbuffer_view<T> v;
    v.width = width;
    v.height = height;
    v.position = position.data();
    v.normal = normal.data();
    v.albedo = albedo.data();
    v.shading_normal = shading_normal.size() == position.size() ? shading_normal.data() : nullptr;
    return v;
  }
};

template <class T>
class synthetic_scene {
public:
  std::vector<vec3<T>> positions;
  std::vector<std::uint32_t> indices;
  std::vector<vec3<T>> tri_normal;  // per triangle, unit
  std::vector<vec3<T>> tri_albedo;  // per triangle
  vplkit::point_light<T> light;

  // Room and block bounds, public so tests can reason about the geometry.
  static vec3<T> room_min() { return vec3<T>(T(-2), T(0), T(-2)); }
  static vec3<T> room_max() { return vec3<T>(T(2), T(3), T(2)); }
  static vec3<T> block_min() { return vec3<T>(T(-1.0), T(0.8), T(-0.8)); }
  static vec3<T> block_max() { return vec3<T>(T(0.4), T(1.2), T(0.6)); }

  synthetic_scene()
      : light(vplkit::make_point_light(vec3<T>(T(0.3), T(2.6), T(0.2)), vec3<T>(T(8), T(7), T(6)),
                                       vec3<T>(T(0), T(-1), T(0)))) {
    const vec3<T> albedo_floor(T(0.7), T(0.7), T(0.7)), albedo_ceiling(T(0.8), T(0.8), T(0.8)),
        albedo_xneg(T(0.8), T(0.2), T(0.2)), albedo_xpos(T(0.2), T(0.8), T(0.2)),
        albedo_zneg(T(0.5), T(0.5), T(0.8)), albedo_zpos(T(0.4), T(0.4), T(0.4)),
        albedo_block(T(0.9), T(0.8), T(0.3));
    add_box(room_min(), room_max(), /*inward=*/true,
            {albedo_xneg, albedo_xpos, albedo_floor, albedo_ceiling, albedo_zneg, albedo_zpos});
    add_box(block_min(), block_max(), /*inward=*/false,
            {albedo_block, albedo_block, albedo_block, albedo_block, albedo_block, albedo_block});
  }

  int triangle_count() const { return int(indices.size() / 3); }

  // Scale-aware offset for rays leaving a surface (the scene is ~4 units across).
  static T surface_epsilon() { return std::is_same<T, float>::value ? T(2e-4) : T(1e-7); }

  // Nearest hit with 0 < t <= t_max along normalize(dir); a zero / non-finite dir misses.
  scene_hit<T> intersect(vec3<T> origin, vec3<T> dir,
                         T t_max = std::numeric_limits<T>::infinity()) const {
    scene_hit<T> best;
    const T len = std::sqrt(glm::dot(dir, dir));
    if (!(len > T(0)) || !std::isfinite(len)) return best;
    const vec3<T> d = dir / len;
    T best_t = t_max;
    for (int tri = 0; tri < triangle_count(); ++tri) {
      const vec3<T> p0 = positions[indices[3 * tri]], p1 = positions[indices[3 * tri + 1]],
                    p2 = positions[indices[3 * tri + 2]];
      const vec3<T> e1 = p1 - p0, e2 = p2 - p0;
      const vec3<T> pv = glm::cross(d, e2);
      const T det = glm::dot(e1, pv);
      if (std::abs(det) < std::numeric_limits<T>::min() * T(16)) continue;  // parallel
      const T inv = T(1) / det;
      const vec3<T> tv = origin - p0;
      const T u = glm::dot(tv, pv) * inv;
      if (u < T(0) || u > T(1)) continue;
      const vec3<T> qv = glm::cross(tv, e1);
      const T v = glm::dot(d, qv) * inv;
      if (v < T(0) || u + v > T(1)) continue;
      const T t = glm::dot(e2, qv) * inv;
      if (t > T(0) && t <= best_t) {
        best_t = t;
        best.hit = true;
        best.t = t;
        best.triangle = tri;
      }
    }
    if (best.hit) {
      best.position = origin + best.t * d;
      best.normal = tri_normal[std::size_t(best.triangle)];
      best.albedo = tri_albedo[std::size_t(best.triangle)];
    }
    return best;
  }

  // render_dprsm's trace_fn: the first surface seen from the light.
  std::optional<vplkit::dprsm_hit<T>> trace_from_light(vec3<T> origin, vec3<T> dir) const {
    const scene_hit<T> h = intersect(origin, dir);
    if (!h.hit) return std::nullopt;
    return vplkit::dprsm_hit<T>{h.position, h.normal, h.albedo};
  }

  // Exact mutual visibility of surface points x and y (normals any length; a zero normal means
  // "no offset" at that end): the segment between the lifted points is free of triangles.
  bool visible(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    const vec3<T> a = x + surface_epsilon() * unit(n_x);
    const vec3<T> b = y + surface_epsilon() * unit(n_y);
    const vec3<T> ab = b - a;
    const T dist = std::sqrt(glm::dot(ab, ab));
    if (!(dist > surface_epsilon())) return true;
    return !intersect(a, ab, dist - surface_epsilon()).hit;
  }

  // First surface hit by the ray leaving surface point x (normal n_x) along dir.
  vplkit::ray_hit<T> trace(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    const scene_hit<T> h = intersect(x + surface_epsilon() * unit(n_x), dir);
    vplkit::ray_hit<T> r;
    r.hit = h.hit;
    if (h.hit) {
      r.position = h.position;
      r.normal = h.normal;
    }
    return r;
  }

  // Exact direct-light test of surface point y: shadow ray to the light.
  bool lit(vec3<T> y, vec3<T> n_y) const {
    const vec3<T> a = y + surface_epsilon() * unit(n_y);
    const vec3<T> to_light = light.position - a;
    const T dist = std::sqrt(glm::dot(to_light, to_light));
    if (!(dist > surface_epsilon())) return true;
    return !intersect(a, to_light, dist - surface_epsilon()).hit;
  }

  dprsm_data<T> make_dprsm(int R) const {
    return render_dprsm_data(light, R, [this](vec3<T> o, vec3<T> dir) { return trace_from_light(o, dir); });
  }

  vplkit::voxel_grid<T> make_voxel_grid(int res = 32) const {
    const vplkit::voxel_bounds<T> b = vplkit::fit_voxel_bounds(positions.data(), positions.size());
    vplkit::voxel_grid<T> g(b.min, b.max, vplkit::ivec3(res));
    vplkit::voxelize(g, positions.data(), positions.size(), indices.data(), indices.size());
    return g;
  }

  // Pinhole camera at (0, 1.6, 1.95) looking at (0, 1.0, -2), vertical field of view 75 degrees,
  // square pixels; pixel (px, py) looks through its centre, py = 0 the top row.
  gbuffer_data<T> make_gbuffer(int w = 16, int h = 16) const {
    gbuffer_data<T> g;
    g.width = w;
    g.height = h;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    g.position.assign(n, vec3<T>(T(0)));
    g.normal.assign(n, vec3<T>(T(0)));
    g.albedo.assign(n, vec3<T>(T(0)));
    const vec3<T> eye(T(0), T(1.6), T(1.95)), target(T(0), T(1.0), T(-2));
    const vec3<T> fwd = glm::normalize(target - eye);
    const vec3<T> right = glm::normalize(glm::cross(fwd, vec3<T>(T(0), T(1), T(0))));
    const vec3<T> up = glm::cross(right, fwd);
    const T tan_half = T(std::tan(0.5 * 75.0 * 3.14159265358979323846 / 180.0));
    const T aspect = T(w) / T(h);
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        const T sx = ((T(px) + T(0.5)) / T(w) * T(2) - T(1)) * tan_half * aspect;
        const T sy = (T(1) - (T(py) + T(0.5)) / T(h) * T(2)) * tan_half;
        const scene_hit<T> hit = intersect(eye, fwd + sx * right + sy * up);
        if (!hit.hit) continue;
        const std::size_t i = std::size_t(py) * std::size_t(w) + std::size_t(px);
        g.position[i] = hit.position;
        g.normal[i] = hit.normal;
        g.albedo[i] = hit.albedo;
      }
    return g;
  }

  // Hand-placed gather points on surfaces of the scene (normals unit, albedo of that surface).
  std::vector<named_gather_point<T>> gather_points() const {
    auto gp = [this](const char* name, vec3<T> p, vec3<T> n) {
      const scene_hit<T> h = intersect(p + T(0.01) * n, -n);  // albedo of the surface under p
      return named_gather_point<T>{name, vplkit::gather_point<T>{p, n, h.albedo}, !lit(p, n)};
    };
    const vec3<T> up(T(0), T(1), T(0)), down(T(0), T(-1), T(0)), xpos(T(1), T(0), T(0)),
        xneg(T(-1), T(0), T(0));
    return {
        gp("floor_open", vec3<T>(T(1.2), T(0), T(1.0)), up),
        gp("floor_shadow", vec3<T>(T(-0.3), T(0), T(-0.1)), up),  // under the block
        gp("floor_corner", vec3<T>(T(1.9), T(0), T(-1.9)), up),   // 0.1 from two walls
        gp("wall_red", vec3<T>(T(-2), T(1.5), T(0.5)), xpos),
        gp("ceiling_near_light", vec3<T>(T(0.3), T(3), T(0.2)), down),  // 0.4 above the light
        gp("block_bottom", vec3<T>(T(-0.3), T(0.8), T(-0.1)), down),    // faces the shadowed floor
        gp("block_side", vec3<T>(T(-1.0), T(1.0), T(0.0)), xneg),       // faces away from the light
    };
  }

private:
  static vec3<T> unit(vec3<T> n) {
    const T l2 = glm::dot(n, n);
    return (l2 > T(0) && std::isfinite(l2)) ? n / std::sqrt(l2) : vec3<T>(T(0));
  }

  void add_quad(vec3<T> a, vec3<T> b, vec3<T> c, vec3<T> d, vec3<T> normal, vec3<T> albedo) {
    const std::uint32_t base = std::uint32_t(positions.size());
    positions.push_back(a);
    positions.push_back(b);
    positions.push_back(c);
    positions.push_back(d);
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(base + i);
    for (int k = 0; k < 2; ++k) {
      tri_normal.push_back(normal);
      tri_albedo.push_back(albedo);
    }
  }

  // Six faces of an axis-aligned box, albedos ordered -x, +x, -y, +y, -z, +z; normals point into
  // the box (room) or out of it (block).
  void add_box(vec3<T> lo, vec3<T> hi, bool inward, const std::vector<vec3<T>>& albedo) {
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const T c = side == 0 ? lo[axis] : hi[axis];
        vec3<T> q[4];
        const T us[4] = {lo[u], hi[u], hi[u], lo[u]}, vs[4] = {lo[v], lo[v], hi[v], hi[v]};
        for (int k = 0; k < 4; ++k) {
          q[k][axis] = c;
          q[k][u] = us[k];
          q[k][v] = vs[k];
        }
        vec3<T> n(T(0));
        n[axis] = (side == 0) == inward ? T(1) : T(-1);
        add_quad(q[0], q[1], q[2], q[3], n, albedo[std::size_t(2 * axis + side)]);
      }
  }
};

// The callables builders and estimators take, backed by the exact ray tracer.
template <class T>
struct exact_visibility {
  const synthetic_scene<T>* scene;
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    return scene->visible(x, n_x, y, n_y);
  }
};

template <class T>
struct exact_tracer {
  const synthetic_scene<T>* scene;
  vplkit::ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    return scene->trace(x, n_x, dir);
  }
};

// The room lit by its DPRSM of resolution R, with the gather points and the exact callables: what
// an estimator test starts from. Not copyable: `view` points into `d`.
template <class T>
struct lit_room {
  synthetic_scene<T> scene;
  dprsm_data<T> d;
  vplkit::dprsm_view<T> view;
  std::vector<named_gather_point<T>> gps = scene.gather_points();
  exact_visibility<T> vis{&scene};
  exact_tracer<T> tracer{&scene};
  explicit lit_room(int R) : d(scene.make_dprsm(R)), view(d.view()) {}
  lit_room(const lit_room&) = delete;
  lit_room& operator=(const lit_room&) = delete;
};

// lit_room with a w x h G-buffer of it: what a builder test starts from.
template <class T>
struct lit_room_gbuffer : lit_room<T> {
  gbuffer_data<T> gb;
  lit_room_gbuffer(int R, int w, int h) : lit_room<T>(R), gb(this->scene.make_gbuffer(w, h)) {}
};

}  // namespace vplkit_test
