// SPDX-License-Identifier: MIT
#pragma once
// Adaptors that turn a voxel grid (or nothing) into the callables the estimators take, so a host
// with only a voxel grid needs one line. The estimators accept any callable of these shapes:
//   visibility(x, n_x, y, n_y) -> bool        mutual visibility of two surface points
//   tracer(x, n_x, dir)        -> ray_hit<T>  first surface hit by the ray leaving surface x
// Normals may have any length. A host with an exact ray tracer writes its own (the tests do).
// A tracer may also offer trace_within(x, n_x, dir, reach) -> ray_hit<T>: the same first hit
// whenever it lies within `reach` of x, and no hit or some hit beyond reach otherwise, at the cost
// of a ray of about that length; and surface_within(x, n_x, reach, plane_tolerance) -> bool, false
// only when every surface point within reach of x lies in a plane through x (within
// plane_tolerance): then no ray from x meets anything else within reach. Both serve the clamp
// compensation's short rays (clamp_compensation.hpp).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/triangle_corners.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/triangle_voxel_near.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_visible.hpp>

#include <limits>

namespace vplkit {

// V = 1 everywhere: the unoccluded VPL sum (what the global weights assume).
struct always_visible {
  template <class T>
  bool operator()(vec3<T>, vec3<T>, vec3<T>, vec3<T>) const {
    return true;
  }
};

// Two-sided voxel test (voxel_visible_two_sided: both ends lifted by offset_voxels along their
// normals, tolerance 0): the recommended one, it neither self-occludes at y nor leaks through
// walls near y (see visibility/voxel_visible.hpp for the measurements).
template <class T>
struct voxel_visibility {
  voxel_grid_view<T> grid;
  T offset_voxels = T(voxel_surface_offset_default);
  T tolerance_voxels = T(voxel_visible_two_sided_default_tolerance);
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    return voxel_visible_two_sided(grid, x, n_x, y, n_y, offset_voxels, tolerance_voxels);
  }
};

// The paper's one-sided test (Alg. 6 lines 8-10: x lifted, y reached within psi voxels).
template <class T>
struct voxel_visibility_one_sided {
  voxel_grid_view<T> grid;
  T offset_voxels = T(voxel_surface_offset_default);
  T tolerance_voxels = T(voxel_visible_default_tolerance);
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T>) const {
    return voxel_visible(grid, x, n_x, y, offset_voxels, tolerance_voxels);
  }
};

// First occupied voxel along the ray from x lifted offset_voxels along n_x (surface_ray_origin),
// reported at the point where the ray enters that voxel (dda_trace_hit_point). That point is up
// to a voxel diagonal from the true surface: a DPRSM depth test on it needs a tolerance of at
// least sqrt(3) * voxel_length (plus the texel's own depth spread, see gathering_estimator.hpp).
template <class T>
struct voxel_tracer {
  voxel_grid_view<T> grid;
  T offset_voxels = T(voxel_surface_offset_default);
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    return trace_within(x, n_x, dir, std::numeric_limits<T>::infinity());
  }
  // The march stops reach + the lift beyond the lifted origin: a hit within reach of x lies
  // within that distance of the origin.
  ray_hit<T> trace_within(vec3<T> x, vec3<T> n_x, vec3<T> dir, T reach) const {
    const T lift = offset_voxels * voxel_length(grid);
    const dda_trace_result<T> r =
        dda_trace_hit_point(grid, surface_ray_origin(grid, x, n_x, offset_voxels), dir, reach + lift);
    ray_hit<T> h;
    h.hit = r.hit;
    if (r.hit) h.position = r.point;
    return h;
  }
};

// Depth tolerance matching a voxel_tracer: one voxel diagonal, sqrt(3) * voxel_length.
template <class T>
inline T voxel_tracer_depth_tolerance(const voxel_grid_view<T>& g) {
  return T(1.7320508075688772) * voxel_length(g);
}

// ---- Triangle voxels (triangle_voxel_query.hpp): no self-occlusion at the ends or at junctions ----

// How the triangle voxel adaptors treat a segment's ends (triangle_voxel_query.hpp):
// - plane_rule: the ends stay where they are; triangles whose planes pass within
//   end_tolerance_voxels of an end are ignored (the default; docs/math.md section 7.2);
// - offset: exact visibility's contract (bvh_visibility.hpp): the ends moved `offset` along their
//   normals, every listed triangle counts. It answers what a ray tracer over the same triangles
//   answers, where the plane rule lets segments through at junctions that graze a surface an end
//   lies on.
enum class triangle_voxel_ends { plane_rule, offset };

// Mutual visibility decided by the triangles a triangle_voxel_grid lists, with the ends as `ends`
// says (the plane rule needs no normals).
template <class T>
struct triangle_voxel_visibility {
  triangle_voxel_view<T> grid;
  T end_tolerance_voxels = T(triangle_voxel_default_end_tolerance);
  triangle_voxel_ends ends = triangle_voxel_ends::plane_rule;
  T offset = T(0);  // world units, for triangle_voxel_ends::offset (triangle_voxel_surface_offset)
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    if (ends == triangle_voxel_ends::offset) return triangle_voxel_visible_offset(grid, x, n_x, y, n_y, offset);
    return triangle_voxel_visible(grid, x, y, end_tolerance_voxels);
  }
};

// First triangle met by the ray leaving x along dir: triangle_voxel_first_hit from x itself under
// the plane rule, triangle_voxel_first_hit_offset from x moved `offset` along n_x under the offset
// contract. The hit lies on the triangle: a DPRSM depth test on it needs no tracer term, only the
// texel's own depth spread. Its normal is the triangle's plane normal; its shading normal the
// corners' interpolated one where `corners` has them (triangle_corners.hpp), else none.
template <class T>
struct triangle_voxel_tracer {
  triangle_voxel_view<T> grid;
  T end_tolerance_voxels = T(triangle_voxel_default_end_tolerance);
  triangle_voxel_ends ends = triangle_voxel_ends::plane_rule;
  T offset = T(0);  // world units, for triangle_voxel_ends::offset
  triangle_corner_view<T> corners{};  // optional: the shading normals of the hits
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    return trace_within(x, n_x, dir, std::numeric_limits<T>::infinity());
  }
  // triangle_voxel_surface_within (triangle_voxel_near.hpp) over the listed triangles.
  bool surface_within(vec3<T> x, vec3<T>, T reach, T plane_tolerance) const {
    return triangle_voxel_surface_within(grid, x, reach, plane_tolerance);
  }
  // Under the offset contract the ray runs to reach + offset from its moved origin: a hit within
  // reach of x lies within that distance of it (bvh_trace's rule).
  ray_hit<T> trace_within(vec3<T> x, vec3<T> n_x, vec3<T> dir, T reach) const {
    const triangle_voxel_hit<T> r = ends == triangle_voxel_ends::offset
                                        ? triangle_voxel_first_hit_offset(grid, x, n_x, dir, offset, reach + offset)
                                        : triangle_voxel_first_hit(grid, x, dir, reach, end_tolerance_voxels);
    ray_hit<T> h;
    h.hit = r.hit;
    if (r.hit) {
      h.position = r.point;
      h.normal = grid.triangles[r.triangle].plane.normal;
      h.shading_normal = triangle_corner_shading_normal(corners, r.triangle, r.point);
    }
    return h;
  }
};

}  // namespace vplkit
