// SPDX-License-Identifier: MIT
#include "app/report.hpp"

#include "render/method_traits.hpp"

#include <vplkit/core/version.hpp>

#include <sys/resource.h>

namespace vplrender {

namespace {

nlohmann::json j3(const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

nlohmann::json options_to_json(const options& o) {
  nlohmann::json j;
  j["scene"] = o.scene;
  j["method"] = to_string(o.meth);
  j["backend"] = to_string(o.back);
  j["width"] = o.width;
  j["height"] = o.height;
  j["vpls"] = o.vpls;
  j["seed"] = o.seed;
  j["out"] = o.out;
  j["regions"] = o.regions;
  j["regions_grid"] = nlohmann::json::array({o.regions_x, o.regions_y});
  j["dirs"] = o.dirs;
  j["eps"] = o.eps;
  j["local_combination"] = to_string(o.local_combination);
  j["gbg_accumulator"] = to_string(o.gbg_accumulator);
  j["cdf_search"] = to_string(o.cdf_search);
  j["face_selection"] = to_string(o.face_selection);
  j["sampler"] = to_string(resolved_sampler(o));
  j["visibility"] = to_string(o.visibility);
  j["vpl_mode"] = to_string(o.vpl_mode);
  j["voxels"] = o.voxels;
  j["dprsm"] = o.dprsm;
  j["paper"] = o.paper;
  j["direct"] = o.direct;
  j["window"] = o.window;
  j["frames"] = o.frames;
  j["exposure"] = o.exposure;
  j["progress"] = to_string(o.progress);
  j["camera"] = nullptr;
  if (o.cam)
    j["camera"] = {{"eye", j3(o.cam->eye)}, {"target", j3(o.cam->target)}, {"up", j3(o.cam->up)}, {"vfov_deg", o.cam->vfov_deg}};
  j["light"] = nullptr;
  if (o.light) {
    j["light"] = {{"position", j3(o.light->position)}, {"intensity", nullptr}};
    if (o.light->intensity) j["light"]["intensity"] = j3(*o.light->intensity);
  }
  return j;
}

long long host_peak_rss_bytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return -1;
  return static_cast<long long>(u.ru_maxrss) * 1024;  // Linux reports kibibytes
}

nlohmann::json make_report(const options& o, const prepared_scene& p, const run_info& run) {
  const scene& s = p.s;
  const aabb b = bounds(s);
  nlohmann::json j;
  j["program"] = "vplrender";
  j["vplkit_version"] = std::to_string(VPLKIT_VERSION_MAJOR) + "." + std::to_string(VPLKIT_VERSION_MINOR) + "." +
                        std::to_string(VPLKIT_VERSION_PATCH);
  j["parameters"] = options_to_json(o);
  j["scene"] = {{"name", s.name},
                {"triangles", s.triangles.size()},
                {"materials", s.materials.size()},
                {"textures", s.textures.size()},
                {"bounds", {{"min", j3(b.lo)}, {"max", j3(b.hi)}}},
                {"camera",
                 {{"eye", j3(s.cam.eye)}, {"target", j3(s.cam.target)}, {"up", j3(s.cam.up)}, {"vfov_deg", s.cam.vfov_deg},
                  {"rule", p.camera_rule}}},
                {"light",
                 {{"position", j3(s.light.position)}, {"intensity", j3(s.light.intensity)}, {"rule", p.light_rule},
                  {"outside_bounds", p.light_outside_bounds}}}};
  j["gl_renderer"] = run.gl_renderer.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.gl_renderer);
  nlohmann::json stages = nlohmann::json::array();
  double total = 0.0;
  for (const stage_time& st : run.stages) {
    stages.push_back({{"name", st.name}, {"ms", st.ms}, {"clock", st.clock}});
    total += st.ms;
  }
  j["stages"] = stages;
  j["total_ms"] = total;
  j["warnings"] = run.warnings;
  j["outputs"] = run.outputs;
  return j;
}

}  // namespace vplrender
