// SPDX-License-Identifier: MIT
#pragma once
// --method exact: the one-bounce diffuse indirect light at a gather point with exact visibility
// and no VPLs, the renderer's ground truth. For each of n_dirs cosine-distributed directions
// around the gather point's geometric normal the ray is traced (Embree, ray_scene) to its first
// hit y; y reflects the point light's direct light, decided by an exact shadow ray:
//
//   L(x) = integral over the hemisphere of (rho_x / pi) L_o(y(w)) cos(n_s, w) dw
//   L_o(y) = rho_y I cos(alpha) / (pi |c - y|^2) V(y, c)      (vplkit::reflected_radiance)
//   estimate = (1/N) sum_k rho_x L_o(y_k) cos(n_s, w_k) / cos(n_g, w_k)
//
// with p(w) = cos(n_g, w) / pi. The conventions are those of the renderer's direct light
// (include/vplkit/vpl/direct_light.hpp) and of the gathering estimator: the light and its
// intensity are the DPRSM's, y reflects from the side facing the light only (a hit seen from its
// unlit side gives 0, as the DPRSM's texel normal does for gathering; the side is the one x lies
// on, not the lifted ray origin's), the albedo is the material's at y (texture included).
// Geometric normals place the hemisphere and move ray origins
// off their surfaces (ray_scene::surface_offset); shading normals give the cosines (the gather
// point's: vplkit::gather_point_shading_normal). A hit whose plane passes through x (within the
// coordinates' rounding: x on a crease, coincident surfaces) sends nothing, the rule of the
// library's gathering estimators (vplkit::vpl_point_on_plane): x sees that surface edge-on, and
// only the lifted origin meets it, at distance ~0. The gather point's geometric normal is the
// G-buffer's (gp.normal: the plane of the triangle that was rasterised at the pixel), the one the
// gathering estimators use. Where a pixel centre lies on an edge, the camera ray may meet the other
// triangle: taking that one's normal with the rasterised triangle's shading normal put the two
// cosines in different hemispheres (a sponza pixel on an arch's edge read 0 where every gathering
// method read 0.45-0.56; hard case in tests/renderer/renderer_exact_test.cpp).
// Random numbers: make_counter_rng(seed, pixel), per direction u0 then u1 (the gathering
// estimator's stream).
#include "render/cpu/ray_scene.hpp"

#include <vplkit/core/gather_point.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

namespace vplrender {

// One direction's value, local = its coordinates in the frame of n_g (z up): rho_x L_o(y) cos_s /
// cos_g, 0 at or below either horizon. Exposed for the tests.
vec3 exact_sample(const ray_scene& rs, const vplkit::point_light<float>& light, const vplkit::gather_point<float>& gp,
                  vec3 n_g, vec3 dir);

// The estimate with n_dirs directions around unit_or_zero(gp.normal); 0 for an invalid gather
// point (nothing drawn).
vec3 estimate_exact(const ray_scene& rs, const vplkit::point_light<float>& light, const vplkit::gather_point<float>& gp,
                    vplkit::counter_rng& rng, int n_dirs);

}  // namespace vplrender
