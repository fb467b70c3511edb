// SPDX-License-Identifier: MIT
#include "render/frames.hpp"

#include <algorithm>
#include <chrono>
#include <map>

namespace vplrender {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 == 1 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

nlohmann::json position(const vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); }

}  // namespace

frames_run run_frames(const scene& s, const frame_settings& f, const render_settings& rs, const light_path& path,
                      stage_timer& setup, const frame_image_fn& each_frame) {
  frames_run out;
  nlohmann::json setup_det;
  frame_pipeline pipe(s, f, setup, setup_det);
  out.gl_renderer = pipe.buffers().gl_renderer;
  const auto light_at = [&](int k) {
    return vplkit::make_point_light<float>(path.at(k), s.light.intensity, vec3(0.0f, -1.0f, 0.0f));  // dprsm_light's frame
  };
  {
    auto t = setup.scoped("warm-up frame");
    stage_timer discard;
    nlohmann::json det;
    const frame_buffers& b = pipe.render(light_at(0), discard, det);
    pipe.split_ahead(light_at(0));  // the first timed frame's light: as every later frame finds it
    run_estimator(b, rs, discard, {}, det);
  }
  for (int k = 0; k < path.count; ++k) {
    stage_timer timer;
    nlohmann::json det = setup_det;
    const auto start = std::chrono::steady_clock::now();
    const frame_buffers& b = pipe.render(light_at(k), timer, det);
    if (k + 1 < path.count) pipe.split_ahead(light_at(k + 1));  // beside this frame's GPU work
    render_result r = run_estimator(b, rs, timer, {}, det);
    out.frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    out.stages.push_back(timer.stages());
    if (each_frame) each_frame(k, r.image);
    if (k + 1 == path.count) {
      out.last_image = std::move(r.image);
      out.last_details = std::move(det);
    }
  }
  return out;
}

nlohmann::json frames_report(const frames_run& r, const light_path& path) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> ms;
  std::map<std::string, std::string> clock;
  for (const std::vector<stage_time>& frame : r.stages)
    for (const stage_time& st : frame) {
      if (!ms.count(st.name)) order.push_back(st.name);
      ms[st.name].push_back(st.ms);
      clock[st.name] = st.clock;
    }
  nlohmann::json stages = nlohmann::json::array();
  for (const std::string& name : order)
    stages.push_back({{"name", name}, {"median_ms", median(ms[name])}, {"clock", clock[name]}});
  const double med = median(r.frame_ms);
  nlohmann::json j;
  j["count"] = r.frame_ms.size();
  j["median_ms"] = med;
  j["min_ms"] = r.frame_ms.empty() ? 0.0 : *std::min_element(r.frame_ms.begin(), r.frame_ms.end());
  j["max_ms"] = r.frame_ms.empty() ? 0.0 : *std::max_element(r.frame_ms.begin(), r.frame_ms.end());
  j["fps"] = med > 0.0 ? 1000.0 / med : 0.0;
  j["frame_time"] = "wall time from a frame's G-buffer to its image on the host (no output written)";
  j["warmup_frames"] = 1;
  j["stages"] = stages;
  j["light_path"] = {{"rule", path.rule()},
                     {"start", position(path.start)},
                     {"radius", path.radius},
                     {"last_position", position(path.at(path.count - 1))}};
  j["image"] = "the last frame's (frame " + std::to_string(path.count - 1) + "); no other frame is written";
  return j;
}

}  // namespace vplrender
