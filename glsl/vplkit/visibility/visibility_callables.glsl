// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the visibility and tracing "callables" of builders and estimators on the GPU;
// mirrors include/vplkit/visibility/visibility_callables.hpp (T = float). GLSL has neither host
// callables nor templates, so vplkit_visibility and vplkit_voxel_tracer are small structs over the
// pack's voxel grid (the C++ adaptors' defaults: offset 1.75 voxels; tolerance 0 voxels two-sided,
// 2 one-sided), or route to the shader's own geometry: #define VPLKIT_USER_VISIBILITY /
// VPLKIT_USER_TRACER before the first include and define vplkit_user_visible / vplkit_user_trace
// (without the macros those kinds are not compiled in). The triangle voxel kinds (no
// self-occlusion at the ends or at junctions, docs/math.md section 7.2) are compiled in with
// #define VPLKIT_TRIANGLE_VOXELS; the shader then defines the accessors of
// visibility/triangle_voxel_grid.glsl. Their offset contract (triangle_voxel_ends::offset: exact
// visibility's, on the listed triangles) is the kind vplkit_visibility_triangle_voxels_offset and
// vplkit_make_triangle_voxel_tracer_offset; with #define VPLKIT_TRIANGLE_CORNERS and the accessors of
// triangle_corners.glsl, vplkit_tracer_with_corners shades the hits (triangle_voxel_tracer::corners).
// The C++ <-> GLSL table:
// docs/glsl/visibility.md, "Visibility and tracing for builders and estimators". ACCESSOR:
// vplkit_load_voxel_word (define it always; it may return 0u when no voxel kind is used).
#ifndef VPLKIT_VISIBILITY_VISIBILITY_CALLABLES_GLSL
#define VPLKIT_VISIBILITY_VISIBILITY_CALLABLES_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/dda.glsl"
#include "vplkit/visibility/voxel_grid.glsl"
#include "vplkit/visibility/voxel_visible.glsl"
#ifdef VPLKIT_TRIANGLE_VOXELS
#include "vplkit/visibility/triangle_voxel_near.glsl"
#include "vplkit/visibility/triangle_voxel_query.glsl"
#endif
#ifdef VPLKIT_TRIANGLE_CORNERS
#include "vplkit/visibility/triangle_corners.glsl"
#endif

const int vplkit_visibility_always = 0;             // always_visible: V = 1
const int vplkit_visibility_voxel_two_sided = 1;    // voxel_visibility<T> (recommended)
const int vplkit_visibility_voxel_one_sided = 2;    // voxel_visibility_one_sided<T> (the paper's)
const int vplkit_visibility_user = 3;               // vplkit_user_visible (VPLKIT_USER_VISIBILITY)
const int vplkit_visibility_triangle_voxels = 4;    // triangle_voxel_visibility<T> (VPLKIT_TRIANGLE_VOXELS)
const int vplkit_visibility_triangle_voxels_offset = 5;  // ... with ends = triangle_voxel_ends::offset

struct vplkit_visibility {
  int kind;                    // one of the constants above
  vplkit_voxel_grid grid;      // unused by kind always / user
  float offset_voxels;         // voxel kinds
  float tolerance_voxels;      // voxel kinds
  float end_tolerance_voxels;  // triangle voxel kind
  float offset;                // triangle voxel offset kind: the ends' offset (world units)
};

#ifdef VPLKIT_USER_VISIBILITY
bool vplkit_user_visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y);
#endif
#ifdef VPLKIT_USER_TRACER
vplkit_ray_hit vplkit_user_trace(vec3 x, vec3 n_x, vec3 dir);
#ifdef VPLKIT_USER_TRACER_WITHIN
// Optional: the first hit when it lies within reach of x (beyond: no hit or a farther one), so a
// short query (the clamp's compensation asks within dmin) can stop early; without the macro
// trace_within calls vplkit_user_trace, which traces the whole ray.
vplkit_ray_hit vplkit_user_trace_within(vec3 x, vec3 n_x, vec3 dir, float reach);
#endif
#endif

vplkit_visibility vplkit_make_always_visible() {
  return vplkit_visibility(vplkit_visibility_always,
                           vplkit_voxel_grid(vec3(0.0), vec3(0.0), ivec3(0)), 0.0, 0.0, 0.0, 0.0);
}

vplkit_visibility vplkit_make_voxel_visibility(vplkit_voxel_grid grid) {
  return vplkit_visibility(vplkit_visibility_voxel_two_sided, grid,
                           vplkit_voxel_surface_offset_default,
                           vplkit_voxel_visible_two_sided_default_tolerance, 0.0, 0.0);
}

vplkit_visibility vplkit_make_voxel_visibility_one_sided(vplkit_voxel_grid grid) {
  return vplkit_visibility(vplkit_visibility_voxel_one_sided, grid,
                           vplkit_voxel_surface_offset_default,
                           vplkit_voxel_visible_default_tolerance, 0.0, 0.0);
}

#ifdef VPLKIT_TRIANGLE_VOXELS
vplkit_visibility vplkit_make_triangle_voxel_visibility(vplkit_voxel_grid grid) {
  return vplkit_visibility(vplkit_visibility_triangle_voxels, grid, 0.0, 0.0,
                           vplkit_triangle_voxel_default_end_tolerance, 0.0);
}

// triangle_voxel_visibility<float>{grid, 0.01, triangle_voxel_ends::offset, offset}.
vplkit_visibility vplkit_make_triangle_voxel_visibility_offset(vplkit_voxel_grid grid, float offset) {
  return vplkit_visibility(vplkit_visibility_triangle_voxels_offset, grid, 0.0, 0.0,
                           vplkit_triangle_voxel_default_end_tolerance, offset);
}
#endif

// Mutual visibility of the surface points x (normal n_x) and y (normal n_y); normals any length.
bool vplkit_visibility_test(vplkit_visibility v, vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  if (v.kind == vplkit_visibility_voxel_two_sided)
    return vplkit_voxel_visible_two_sided(v.grid, x, n_x, y, n_y, v.offset_voxels, v.tolerance_voxels);
  if (v.kind == vplkit_visibility_voxel_one_sided)
    return vplkit_voxel_visible(v.grid, x, n_x, y, v.offset_voxels, v.tolerance_voxels);
#ifdef VPLKIT_TRIANGLE_VOXELS
  if (v.kind == vplkit_visibility_triangle_voxels)
    return vplkit_triangle_voxel_visible(v.grid, x, y, v.end_tolerance_voxels);
  if (v.kind == vplkit_visibility_triangle_voxels_offset)
    return vplkit_triangle_voxel_visible_offset(v.grid, x, n_x, y, n_y, v.offset);
#endif
#ifdef VPLKIT_USER_VISIBILITY
  if (v.kind == vplkit_visibility_user) return vplkit_user_visible(x, n_x, y, n_y);
#endif
  return true;  // vplkit_visibility_always
}

struct vplkit_voxel_tracer {
  vplkit_voxel_grid grid;
  float offset_voxels;
  bool user;                   // true: vplkit_user_trace (needs VPLKIT_USER_TRACER); false: the voxel DDA
  bool triangles;              // true: the triangle voxel first hit (needs VPLKIT_TRIANGLE_VOXELS)
  float end_tolerance_voxels;  // of the triangle voxel first hit
  // Gathering's lit test by a shadow ray through `light` instead of the DPRSM's shadow map
  // (tracer_with_light_visibility, visibility/light_visibility.hpp); false: the shadow map.
  bool light_exact;
  vplkit_visibility light;
  bool offset_ends;            // triangle voxels under the offset contract (vplkit_triangle_voxel_first_hit_offset)
  float offset;                // its ends' offset (world units)
  uint corner_triangles;       // > 0: hits shaded from the corners (VPLKIT_TRIANGLE_CORNERS), this many triangles
};

vplkit_voxel_tracer vplkit_make_voxel_tracer(vplkit_voxel_grid grid) {
  return vplkit_voxel_tracer(grid, vplkit_voxel_surface_offset_default, false, false, 0.0, false,
                             vplkit_make_always_visible(), false, 0.0, 0u);
}

// with_light_visibility(tracer, visibility): the lit test of gathering hits by v.
vplkit_voxel_tracer vplkit_tracer_with_light_visibility(vplkit_voxel_tracer tr, vplkit_visibility v) {
  tr.light_exact = true;
  tr.light = v;
  return tr;
}

// tracer.light_visible(y, n_y, c): does the light at c reach surface point y (normal n_y facing c)?
bool vplkit_voxel_tracer_light_visible(vplkit_voxel_tracer tr, vec3 y, vec3 n_y, vec3 c) {
  return vplkit_visibility_test(tr.light, y, n_y, c, vec3(0.0));
}

#ifdef VPLKIT_TRIANGLE_VOXELS
// triangle_voxel_tracer<float>: the first triangle met from x itself (no lift), on the triangle.
vplkit_voxel_tracer vplkit_make_triangle_voxel_tracer(vplkit_voxel_grid grid) {
  return vplkit_voxel_tracer(grid, 0.0, false, true, vplkit_triangle_voxel_default_end_tolerance, false,
                             vplkit_make_always_visible(), false, 0.0, 0u);
}

// triangle_voxel_tracer<float> with ends = triangle_voxel_ends::offset: the first triangle met from x
// moved `offset` along n_x.
vplkit_voxel_tracer vplkit_make_triangle_voxel_tracer_offset(vplkit_voxel_grid grid, float offset) {
  vplkit_voxel_tracer tr = vplkit_make_triangle_voxel_tracer(grid);
  tr.offset_ends = true;
  tr.offset = offset;
  return tr;
}
#endif

#ifdef VPLKIT_TRIANGLE_CORNERS
// triangle_voxel_tracer::corners: the triangle voxel hits carry the corners' interpolated shading
// normal (triangle_corners.glsl's accessors, triangle_count triangles).
vplkit_voxel_tracer vplkit_tracer_with_corners(vplkit_voxel_tracer tr, uint triangle_count) {
  tr.corner_triangles = triangle_count;
  return tr;
}
#endif

// tracer.surface_within(x, n_x, reach, plane_tolerance): false only when every surface point within
// reach of x lies in a plane through x; the triangle voxels look (vplkit_triangle_voxel_surface_within),
// the other kinds answer true (they cannot say).
bool vplkit_voxel_tracer_surface_within(vplkit_voxel_tracer tr, vec3 x, vec3 n_x, float reach, float plane_tolerance) {
#ifdef VPLKIT_USER_TRACER
  if (tr.user) return true;
#endif
#ifdef VPLKIT_TRIANGLE_VOXELS
  if (tr.triangles) return vplkit_triangle_voxel_surface_within(tr.grid, x, reach, plane_tolerance);
#endif
  return true;
}

// tracer.trace_within(x, n_x, dir, reach): the first hit as vplkit_voxel_tracer_trace gives it
// whenever it lies within reach of x; beyond, no hit or a farther one. The voxel kinds stop their
// march there (reach plus the lift for the voxel DDA); the user kind calls
// vplkit_user_trace_within with VPLKIT_USER_TRACER_WITHIN, else vplkit_user_trace (the whole ray).
vplkit_ray_hit vplkit_voxel_tracer_trace_within(vplkit_voxel_tracer tr, vec3 x, vec3 n_x, vec3 dir, float reach) {
#ifdef VPLKIT_USER_TRACER
#ifdef VPLKIT_USER_TRACER_WITHIN
  if (tr.user) return reach < vplkit_dda_infinity() ? vplkit_user_trace_within(x, n_x, dir, reach)
                                                    : vplkit_user_trace(x, n_x, dir);
#else
  if (tr.user) return vplkit_user_trace(x, n_x, dir);
#endif
#endif
#ifdef VPLKIT_TRIANGLE_VOXELS
  if (tr.triangles) {
    // Under the offset contract the ray runs to reach + offset from its moved origin (a hit within
    // reach of x lies within that distance of it).
    precise float offset_reach = reach + tr.offset;
    vplkit_triangle_voxel_hit t =
        tr.offset_ends ? vplkit_triangle_voxel_first_hit_offset(tr.grid, x, n_x, dir, tr.offset, offset_reach)
                       : vplkit_triangle_voxel_first_hit(tr.grid, x, dir, reach, tr.end_tolerance_voxels);
    vplkit_ray_hit th = vplkit_ray_hit(t.hit, vec3(0.0), vec3(0.0), vec3(0.0));
    if (t.hit) {
      th.position = t.point;
      th.normal = vplkit_load_voxel_triangle(4u * t.triangle).xyz;  // its plane's normal
#ifdef VPLKIT_TRIANGLE_CORNERS
      if (tr.corner_triangles > 0u)
        th.shading_normal = vplkit_triangle_corner_shading_normal(t.triangle, tr.corner_triangles, t.point);
#endif
    }
    return th;
  }
#endif
  float lift = tr.offset_voxels * vplkit_voxel_length(tr.grid);
  vplkit_dda_trace_result r = vplkit_dda_trace_hit_point(
      tr.grid, vplkit_surface_ray_origin(tr.grid, x, n_x, tr.offset_voxels), dir, reach + lift);
  vplkit_ray_hit h = vplkit_ray_hit(r.hit, vec3(0.0), vec3(0.0), vec3(0.0));
  if (r.hit) h.position = r.point;
  return h;
}

// First occupied voxel along the ray from x lifted offset_voxels along n_x, reported at the point
// where the ray enters that voxel (up to a voxel diagonal from the true surface).
vplkit_ray_hit vplkit_voxel_tracer_trace(vplkit_voxel_tracer tr, vec3 x, vec3 n_x, vec3 dir) {
  return vplkit_voxel_tracer_trace_within(tr, x, n_x, dir, vplkit_dda_infinity());
}

// Depth tolerance matching a voxel tracer: one voxel diagonal, sqrt(3) * voxel_length (the same
// float as the C++ T(1.7320508075688772) * voxel_length(g)).
float vplkit_voxel_tracer_depth_tolerance(vplkit_voxel_grid g) {
  return 1.7320508075688772 * vplkit_voxel_length(g);
}

#endif  // VPLKIT_VISIBILITY_VISIBILITY_CALLABLES_GLSL
