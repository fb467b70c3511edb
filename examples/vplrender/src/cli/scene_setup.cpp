// SPDX-License-Identifier: MIT
#include "cli/scene_setup.hpp"

#include "io/errors.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/framing.hpp"
#include "scene/obj_loader.hpp"
#include "scene/raycast.hpp"

#include <sstream>

namespace vplrender {

namespace {

std::string v3(const vec3& v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

}  // namespace

void check_light_position(const scene& s, const std::string& who) {
  const double diag = static_cast<double>(bounds(s).diagonal());
  const point_classification c = classify_point(s.triangles, glm::dvec3(s.light.position), 1e-4 * diag);
  if (c.kind == point_class::on_surface) {
    std::ostringstream m;
    m << who << ": light position " << v3(s.light.position) << " lies on a surface (" << c.nearest
      << " from the nearest triangle); move it off the geometry";
    throw input_error(m.str());
  }
  if (c.kind == point_class::inside_solid) {
    std::ostringstream m;
    m << who << ": light position " << v3(s.light.position) << " is inside geometry (" << c.back_hits << " of "
      << c.hits << " rays from it first hit the back of a surface)";
    throw input_error(m.str());
  }
}

prepared_scene prepare_scene(const options& o) {
  prepared_scene p;
  const bool builtin = is_builtin_scene_name(o.scene);
  p.s = builtin ? make_builtin_scene(o.scene) : load_obj_scene(o.scene);
  validate_geometry(p.s);

  if (o.cam) {
    p.s.cam = camera{o.cam->eye, o.cam->target, o.cam->up, o.cam->vfov_deg};
    p.camera_rule = "--camera";
  } else if (builtin) {
    p.camera_rule = "built-in";
  } else {
    p.s.cam = auto_camera(bounds(p.s), o.width, o.height);
    p.camera_rule = "automatic: frames the bounding sphere from +Z, 45 degree vertical fov";
  }

  std::string light_source = "built-in light";
  if (builtin) {
    p.light_rule = "built-in";
  } else if (!o.light) {
    const auto_light_result a = auto_light(p.s);
    p.s.light = a.light;
    p.light_rule = "automatic: " + a.rule;
    light_source = "automatic light";
  } else if (!o.light->intensity) {
    p.s.light.intensity = auto_light_intensity(p.s);
  }
  if (o.light) {
    p.s.light.position = o.light->position;
    if (o.light->intensity) p.s.light.intensity = *o.light->intensity;
    p.light_rule = o.light->intensity ? std::string("--light")
                                      : std::string("--light position, ") + (builtin ? "built-in" : "automatic") + " intensity";
    light_source = "--light";
  }
  validate_scene(p.s);
  check_light_position(p.s, light_source);
  const aabb b = bounds(p.s);
  const vec3 l = p.s.light.position;
  p.light_outside_bounds = l.x < b.lo.x || l.y < b.lo.y || l.z < b.lo.z || l.x > b.hi.x || l.y > b.hi.y || l.z > b.hi.z;
  return p;
}

std::string describe(const prepared_scene& p, const options& o) {
  const scene& s = p.s;
  const aabb b = bounds(s);
  std::ostringstream m;
  m << "scene     " << s.name << ": " << s.triangles.size() << " triangles, " << s.materials.size() << " materials, "
    << s.textures.size() << " textures\n"
    << "bounds    " << v3(b.lo) << " .. " << v3(b.hi) << "\n"
    << "camera    eye " << v3(s.cam.eye) << " target " << v3(s.cam.target) << " up " << v3(s.cam.up) << " fov "
    << s.cam.vfov_deg << " [" << p.camera_rule << "]\n"
    << "light     at " << v3(s.light.position) << " intensity " << v3(s.light.intensity) << " W/sr [" << p.light_rule
    << "]" << (p.light_outside_bounds ? " (outside the scene bounds)" : "") << "\n"
    << "method    " << to_string(o.meth) << " on " << to_string(o.back) << ", " << o.width << "x" << o.height << ", "
    << o.vpls << " VPLs, " << o.dirs << " dirs, " << o.regions << " regions (" << o.regions_x << "x" << o.regions_y
    << "), eps " << o.eps << ", voxels " << o.voxels << "^3, DPRSM 2x" << o.dprsm << "x" << o.dprsm << ", seed "
    << o.seed << (o.direct ? ", with direct light" : ", indirect only") << "\n"
    << "output    " << o.out << ", " << o.png_path() << ", " << o.json_path() << "\n";
  return m.str();
}

}  // namespace vplrender
