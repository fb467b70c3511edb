// SPDX-License-Identifier: MIT
#include "scene/obj_loader.hpp"

#include "io/errors.hpp"
#include "io/text_file.hpp"
#include "scene/mtl_scan.hpp"
#include "scene/obj_scan.hpp"
#include "scene/texture.hpp"
#include "scene/triangulate.hpp"

#include <tiny_obj_loader.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace vplrender {

namespace {

namespace fs = std::filesystem;

std::string fmt3(const float* v) {
  std::ostringstream s;
  s << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return s.str();
}

// tinyobjloader's warnings, one per line, without the ones our scan already reports better.
void forward_tinyobj_warnings(const std::string& warn, const std::string& file, std::vector<std::string>& out) {
  std::istringstream in(warn);
  std::string line;
  std::set<std::string> seen;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty() || line == ".") continue;
    if (line.find("Failed to load material file") != std::string::npos) continue;  // reported per mtllib
    if (line.find("Material file [") != std::string::npos) continue;
    if (!seen.insert(line).second) continue;
    out.push_back(file + ": " + line);
  }
}

// Where a map_Kd name may live: beside the OBJ, beside each MTL, and with Windows separators fixed.
// Returns the first regular file; else "" and, in *problem, why the first candidate that exists
// cannot be read (a FIFO, a device, a directory), or "" when none exists.
std::string find_texture(const std::string& name, const fs::path& obj_dir, const std::vector<fs::path>& mtl_dirs,
                         std::string* problem) {
  std::string fixed = name;
  std::replace(fixed.begin(), fixed.end(), '\\', '/');
  std::vector<fs::path> candidates;
  for (const std::string& n : {name, fixed}) {
    if (fs::path(n).is_absolute()) candidates.emplace_back(n);
    candidates.push_back(obj_dir / n);
    for (const fs::path& d : mtl_dirs) candidates.push_back(d / n);
  }
  problem->clear();
  for (const fs::path& c : candidates) {
    const std::string why = file_problem(c.string());
    if (why.empty()) return c.string();
    if (problem->empty() && why != "does not exist") *problem = c.string() + " " + why;
  }
  return {};
}

// Serves tinyobjloader the MTL libraries we already read, validated and cleaned (mtl_scan.hpp),
// from memory: tinyobjloader never opens an MTL itself (it would wait on a FIFO, read /dev/zero
// until memory runs out, and take 'Kd abc' for black).
class validated_mtl_reader : public tinyobj::MaterialReader {
public:
  void add(const std::string& name, std::string cleaned) { texts_.emplace(name, std::move(cleaned)); }
  bool has(const std::string& name) const { return texts_.count(name) > 0; }
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* material_map, std::string* warn, std::string* err) override {
    const auto it = texts_.find(name);
    if (it == texts_.end()) return false;
    std::istringstream in(it->second);
    tinyobj::LoadMtl(material_map, materials, &in, warn, err);
    return true;
  }

private:
  std::map<std::string, std::string> texts_;
};

}  // namespace

scene load_obj_scene(const std::string& path) {
  const fs::path dir = fs::path(path).parent_path();
  return load_obj_text(read_file_bytes(path), path, dir.empty() ? std::string(".") : dir.string());
}

scene load_obj_text(const std::string& bytes, const std::string& path, const std::string& base_dir) {
  scene s;
  s.name = path;
  obj_scan_result scan = scan_obj(bytes, path);
  s.warnings = scan.warnings;
  if (scan.face_lines.empty())
    throw input_error(path + ": empty scene (no faces" +
                      (scan.vertices ? ", " + std::to_string(scan.vertices) + " vertices)" : ")"));

  const fs::path obj_dir = base_dir.empty() ? fs::path(".") : fs::path(base_dir);
  std::vector<fs::path> mtl_dirs;
  validated_mtl_reader reader;
  for (const auto& lib : scan.mtllibs) {
    if (reader.has(lib.name)) continue;
    const fs::path p = obj_dir / lib.name;
    const std::string where = path + ":" + std::to_string(lib.line) + ": material library '" + lib.name + "' ";
    const std::string fallback = "; its materials fall back to the default (Kd 0.8)";
    const std::string problem = file_problem(p.string());
    if (problem == "does not exist") {
      s.warnings.push_back(where + "not found" + fallback);
      continue;
    }
    if (!problem.empty()) {
      s.warnings.push_back(where + "(" + p.string() + ") " + problem + fallback);
      continue;
    }
    std::string text;
    try {
      text = read_file_bytes(p.string());
    } catch (const input_error& e) {
      s.warnings.push_back(where + "cannot be read (" + e.what() + ")" + fallback);
      continue;
    }
    mtl_scan_result mtl = scan_mtl(text, p.string());  // malformed content: input_error naming file:line
    s.warnings.insert(s.warnings.end(), mtl.warnings.begin(), mtl.warnings.end());
    reader.add(lib.name, std::move(mtl.cleaned));
    mtl_dirs.push_back(p.parent_path());
  }

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> mats;
  std::string warn, err;
  std::istringstream in(scan.cleaned);
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &mats, &warn, &err, &in, &reader, /*triangulate=*/false);
  forward_tinyobj_warnings(warn, path, s.warnings);
  if (!ok) {
    std::string first = err.substr(0, err.find('\n'));
    throw input_error(path + ": " + (first.empty() ? std::string("tinyobjloader failed") : first));
  }
  if (!err.empty()) forward_tinyobj_warnings(err, path, s.warnings);  // MTL complaints arrive here

  // Belt and braces: the scan admits only finite float literals, but check what tinyobj produced.
  for (float v : attrib.vertices)
    if (!std::isfinite(v)) throw input_error(path + ": non-finite vertex coordinate after parsing");

  // ---- materials ----
  std::map<std::string, int> texture_index;
  for (const tinyobj::material_t& m : mats) {
    material out;
    out.name = m.name;
    const float* kd = m.diffuse;
    if (!(std::isfinite(kd[0]) && std::isfinite(kd[1]) && std::isfinite(kd[2]))) {
      s.warnings.push_back(path + ": material '" + m.name + "' has a non-finite Kd; using 0.8");
      out.kd = vec3(0.8f);
    } else {
      out.kd = vec3(kd[0], kd[1], kd[2]);
      const vec3 c = glm::clamp(out.kd, vec3(0.0f), vec3(1.0f));
      if (c != out.kd)
        s.warnings.push_back(path + ": material '" + m.name + "' has Kd " + fmt3(kd) +
                             " outside [0,1]; clamped (a diffuse albedo above 1 creates energy)");
      out.kd = c;
    }
    const float* ke = m.emission;
    if (std::isfinite(ke[0]) && std::isfinite(ke[1]) && std::isfinite(ke[2]))
      out.ke = glm::max(vec3(ke[0], ke[1], ke[2]), vec3(0.0f));
    if (!m.diffuse_texname.empty()) {
      std::string problem;
      const std::string found = find_texture(m.diffuse_texname, obj_dir, mtl_dirs, &problem);
      if (found.empty()) {
        s.warnings.push_back(path + ": texture '" + m.diffuse_texname + "' of material '" + m.name + "' " +
                             (problem.empty() ? std::string("not found") : "unreadable: " + problem) + "; using Kd");
      } else {
        auto it = texture_index.find(found);
        if (it != texture_index.end()) {
          out.texture = it->second;
        } else {
          try {
            s.textures.push_back(load_texture(found));
            out.texture = static_cast<int>(s.textures.size() - 1);
            texture_index.emplace(found, out.texture);
          } catch (const input_error& e) {
            s.warnings.push_back(std::string(e.what()) + "; material '" + m.name + "' uses Kd");
            texture_index.emplace(found, -1);
          }
        }
      }
    }
    s.materials.push_back(out);
  }
  const std::uint32_t n_file_materials = static_cast<std::uint32_t>(s.materials.size());
  int default_material = -1;
  std::map<std::uint32_t, std::uint32_t> untextured_clone;  // textured material -> copy without texture
  std::size_t untextured_faces = 0;

  // ---- faces ----
  std::size_t face_number = 0, dropped = 0, fanned = 0, degenerate_polygons = 0;
  std::size_t first_dropped_line = 0, first_fanned_line = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++face_number) {
      const std::size_t nv = shape.mesh.num_face_vertices[f];
      const std::size_t line = face_number < scan.face_lines.size() ? scan.face_lines[face_number] : 0;
      std::vector<glm::dvec3> poly(nv);
      for (std::size_t k = 0; k < nv; ++k) {
        const int vi = shape.mesh.indices[offset + k].vertex_index;
        if (vi < 0 || static_cast<std::size_t>(vi) * 3 + 2 >= attrib.vertices.size())
          throw file_error(path, line, "vertex index out of range");  // the scan makes this unreachable
        const float* p = &attrib.vertices[static_cast<std::size_t>(vi) * 3];
        poly[k] = glm::dvec3(p[0], p[1], p[2]);
      }
      const triangulation tr = triangulate_polygon(poly);
      if (tr.triangles.empty()) {
        ++degenerate_polygons;
        if (!first_dropped_line) first_dropped_line = line;
      }
      if (tr.fan_fallback && ++fanned == 1) first_fanned_line = line;

      int mat_id = shape.mesh.material_ids.empty() ? -1 : shape.mesh.material_ids[f];
      std::uint32_t mat;
      if (mat_id < 0 || static_cast<std::uint32_t>(mat_id) >= n_file_materials) {
        if (default_material < 0) {
          material d;
          d.name = "default";
          s.materials.push_back(d);
          default_material = static_cast<int>(s.materials.size() - 1);
        }
        mat = static_cast<std::uint32_t>(default_material);
      } else {
        mat = static_cast<std::uint32_t>(mat_id);
      }
      const tinyobj::texture_option_t* texopt =
          (mat < mats.size() && s.materials[mat].texture >= 0) ? &mats[mat].diffuse_texopt : nullptr;

      for (const auto& idx : tr.triangles) {
        triangle t;
        bool has_uv = true;
        for (int c = 0; c < 3; ++c) {
          const tinyobj::index_t& ix = shape.mesh.indices[offset + idx[static_cast<std::size_t>(c)]];
          t.p[static_cast<std::size_t>(c)] = vec3(poly[idx[static_cast<std::size_t>(c)]]);
          vec3 n(tr.normal);  // flat normal of the whole polygon, following its winding
          if (ix.normal_index >= 0) {
            const float* vn = &attrib.normals[static_cast<std::size_t>(ix.normal_index) * 3];
            const glm::dvec3 g(vn[0], vn[1], vn[2]);
            const double len = glm::length(g);
            if (len > 0.0 && std::isfinite(len)) n = vec3(g / len);
          }
          t.n[static_cast<std::size_t>(c)] = n;
          if (ix.texcoord_index >= 0) {
            const float* vt = &attrib.texcoords[static_cast<std::size_t>(ix.texcoord_index) * 2];
            vec2 uv(vt[0], vt[1]);
            if (texopt) {
              uv = uv * vec2(static_cast<float>(texopt->scale[0]), static_cast<float>(texopt->scale[1])) +
                   vec2(static_cast<float>(texopt->origin_offset[0]), static_cast<float>(texopt->origin_offset[1]));
            }
            t.uv[static_cast<std::size_t>(c)] = uv;
          } else {
            has_uv = false;
          }
        }
        // Height below 1e-9 of the longest edge: nothing a float rasteriser or normal can use.
        double longest = 0.0;
        for (int c = 0; c < 3; ++c)
          longest = std::max(longest, glm::length(glm::dvec3(t.p[static_cast<std::size_t>((c + 1) % 3)]) -
                                                  glm::dvec3(t.p[static_cast<std::size_t>(c)])));
        if (!(triangle_double_area(t) > 1e-9 * longest * longest)) {
          if (++dropped == 1 && !first_dropped_line) first_dropped_line = line;
          continue;
        }
        std::uint32_t m = mat;
        if (!has_uv && s.materials[mat].texture >= 0) {
          ++untextured_faces;
          auto it = untextured_clone.find(mat);
          if (it == untextured_clone.end()) {
            material copy = s.materials[mat];
            copy.name += " (no texcoords)";
            copy.texture = -1;
            s.materials.push_back(copy);
            it = untextured_clone.emplace(mat, static_cast<std::uint32_t>(s.materials.size() - 1)).first;
          }
          m = it->second;
        }
        t.material = m;
        s.triangles.push_back(t);
      }
      offset += nv;
    }
  }

  const std::size_t faces = scan.face_lines.size();
  if (s.triangles.empty())
    throw input_error(path + ": degenerate scene: all " + std::to_string(faces) + " faces have zero area");
  if (dropped + degenerate_polygons > 0)
    s.warnings.push_back(path + ":" + std::to_string(first_dropped_line) + ": dropped " +
                         std::to_string(dropped + degenerate_polygons) +
                         " zero-area triangle(s)/polygon(s) (first at this line)");
  if (fanned > 0)
    s.warnings.push_back(path + ":" + std::to_string(first_fanned_line) + ": " + std::to_string(fanned) +
                         " self-intersecting or very large polygon(s) fanned from their first vertex");
  if (untextured_faces > 0)
    s.warnings.push_back(path + ": " + std::to_string(untextured_faces) +
                         " triangle(s) with a textured material have no texcoords; they use Kd");
  validate_geometry(s);
  return s;
}

}  // namespace vplrender
