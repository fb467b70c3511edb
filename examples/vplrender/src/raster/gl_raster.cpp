// SPDX-License-Identifier: MIT
#include "raster/gl_raster.hpp"

#include "raster/dprsm_mesh.hpp"
#include "raster/gl_mesh.hpp"
#include "raster/gl_target.hpp"

#include <headless_gl/compute.hpp>
#include <headless_gl/raster_program.hpp>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

namespace vplrender {

std::size_t gbuffer_data::valid_count() const {
  std::size_t n = 0;
  for (const vec3& v : normal) n += (v.x != 0.0f || v.y != 0.0f || v.z != 0.0f) ? 1u : 0u;
  return n;
}

vplkit::point_light<float> dprsm_light(const scene& s) {
  return vplkit::make_point_light<float>(s.light.position, s.light.intensity, vec3(0.0f, -1.0f, 0.0f));
}

namespace {

using vplkit::gl::check_gl;
using vplkit::gl::gl_error;

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

struct gl_rasterizer::impl {
  const scene* s = nullptr;
  // shaders/gbuffer.{vert,frag} and shaders/dprsm.{vert,frag}, compiled once per process.
  const vplkit::gl::program* gbuffer_program = nullptr;
  const vplkit::gl::program* dprsm_program = nullptr;
  std::vector<GLuint> textures;    // per scene texture
  gl_mesh scene_mesh;              // the scene as is (G-buffer)
  std::unique_ptr<dprsm_mesh> light_mesh;  // the scene split for the last DPRSM's light
  long long texture_bytes = 0;     // RGB8 is padded to 4 bytes per texel by most drivers
  gl_target gbuffer_rt, dprsm_rt;  // kept for the next call of the same size
  ~impl() {
    if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
    vplkit::gl::track_gpu_bytes(-texture_bytes);
  }

  void draw(const vplkit::gl::program& prog, const gl_mesh& m) {
    const GLint kd = prog.uniform_location("u_kd");
    const GLint textured = prog.uniform_location("u_textured");
    const GLint sampler = prog.uniform_location("u_texture");
    glUniform1i(sampler, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(m.vertex_array());
    for (const gl_mesh::range& r : m.ranges()) {
      const material& mat = s->materials[r.material];
      glUniform3f(kd, mat.kd.x, mat.kd.y, mat.kd.z);
      glUniform1i(textured, mat.texture >= 0 ? 1 : 0);
      glBindTexture(GL_TEXTURE_2D, mat.texture >= 0 ? textures[static_cast<std::size_t>(mat.texture)] : 0);
      glDrawArrays(GL_TRIANGLES, r.first, r.count);
    }
    glBindVertexArray(0);
  }

  void draw_gbuffer(const camera& cam, int width, int height);
  // The DPRSM mesh for the light; the split ahead's wall ms when it was ready ahead, else -1.
  double tessellate_for(const vplkit::point_light<float>& light, const tessellation_params& tess, tessellation_stats* ts);
  void draw_dprsm_face(const vplkit::point_light<float>& light, int R, int face);  // light_mesh into dprsm_rt

  // Distance beyond every vertex from p (depth range of the DPRSM).
  float far_from(vec3 p) const {
    const aabb b = bounds(*s);
    double far = 0.0;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
      far = std::max(far, glm::length(corner - glm::dvec3(p)));
    }
    return static_cast<float>(far * 1.01 + 1e-6);
  }
};

gl_rasterizer::gl_rasterizer(const scene& s) : impl_(std::make_unique<impl>()) {
  impl_->s = &s;
  const std::string dir = VPLRENDER_SHADER_DIR;
  impl_->gbuffer_program = &vplkit::gl::cached_raster_program(dir + "/gbuffer.vert", dir + "/gbuffer.frag");
  impl_->dprsm_program = &vplkit::gl::cached_raster_program(dir + "/dprsm.vert", dir + "/dprsm.frag");
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (const texture_rgb8& t : s.textures) {
    GLuint id = 0;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, t.width, t.height, 0, GL_RGB, GL_UNSIGNED_BYTE, t.texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    impl_->textures.push_back(id);
    const long long tb = 4LL * t.width * t.height;
    impl_->texture_bytes += tb;
    vplkit::gl::track_gpu_bytes(tb);
  }
  impl_->scene_mesh.upload(s.triangles);
  check_gl("vplrender: rasteriser setup");
}

gl_rasterizer::~gl_rasterizer() = default;

namespace {

// surfels_from_targets.comp over `rt`: kind 0 the G-buffer (rows flipped, four targets), kind 1 a
// DPRSM face (three targets, surfels from `first`).
void copy_to_surfels(const gl_target& rt, int kind, std::uint32_t first, const vplkit::gl::buffer& surfels) {
  const std::size_t texels = static_cast<std::size_t>(rt.width()) * static_cast<std::size_t>(rt.height());
  if (surfels.size_bytes() < 48 * (first + texels))
    throw gl_error("vplrender: the surfel buffer holds fewer than " + std::to_string(first + texels) + " surfels");
  const vplkit::gl::program& prog =
      vplkit::gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/surfels_from_targets.comp");
  prog.use();
  glUniform1i(prog.uniform_location("u_width"), rt.width());
  glUniform1i(prog.uniform_location("u_height"), rt.height());
  glUniform1i(prog.uniform_location("u_kind"), kind);
  glUniform1ui(prog.uniform_location("u_first"), first);
  for (int i = 0; i < 4; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    // The DPRSM has no fourth target: its sampler is never read, bind the first one.
    glBindTexture(GL_TEXTURE_2D, rt.color(i < rt.attachments() ? i : 0));
  }
  surfels.bind(0);
  vplkit::gl::dispatch(prog, vplkit::gl::groups_for(texels, 64));
  for (int i = 3; i >= 0; --i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  check_gl("vplrender: surfels_from_targets.comp");
}

}  // namespace

void gl_rasterizer::impl::draw_gbuffer(const camera& cam, int width, int height) {
  gbuffer_rt.ensure(width, height, 4);
  const aabb b = bounds(*s);
  double far = 0.0;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
    far = std::max(far, glm::length(corner - glm::dvec3(cam.eye)));
  }
  const float zfar = static_cast<float>(far * 1.01 + 1e-6);
  const float znear = std::max(zfar * 1e-5f, 1e-6f);
  const glm::mat4 proj = glm::perspective(glm::radians(cam.vfov_deg), float(width) / float(height), znear, zfar);
  const glm::mat4 view = glm::lookAt(cam.eye, cam.target, cam.up);
  const glm::mat4 vp = proj * view;
  gbuffer_rt.clear();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  const vplkit::gl::program& prog = *gbuffer_program;
  prog.use();
  glUniformMatrix4fv(prog.uniform_location("u_view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
  glUniform3f(prog.uniform_location("u_eye"), cam.eye.x, cam.eye.y, cam.eye.z);
  glUniform1f(prog.uniform_location("u_far"), zfar);
  draw(prog, scene_mesh);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("vplrender: G-buffer pass");
}

double gl_rasterizer::impl::tessellate_for(const vplkit::point_light<float>& light, const tessellation_params& tess,
                                           tessellation_stats* ts) {
  if (!light_mesh) light_mesh = std::make_unique<dprsm_mesh>(s->triangles);
  const dprsm_mesh::build_report r = light_mesh->build(light.position, tess, ts);
  return r.ahead ? r.ahead_ms : -1.0;
}

void gl_rasterizer::split_dprsm_ahead(const vplkit::point_light<float>& light, const tessellation_params& tess) {
  if (!impl_->light_mesh) impl_->light_mesh = std::make_unique<dprsm_mesh>(impl_->s->triangles);
  impl_->light_mesh->split_ahead(light.position, tess);
}

void gl_rasterizer::impl::draw_dprsm_face(const vplkit::point_light<float>& light, int R, int f) {
  dprsm_rt.ensure(R, R, 3);
  const vplkit::gl::program& prog = *dprsm_program;
  dprsm_rt.clear();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glEnable(GL_CLIP_DISTANCE0);
  prog.use();
  glUniform3f(prog.uniform_location("u_light"), light.position.x, light.position.y, light.position.z);
  const vplkit::light_frame<float>& fr = light.frame;
  glUniform3f(prog.uniform_location("u_axis_x"), fr.axis_x.x, fr.axis_x.y, fr.axis_x.z);
  glUniform3f(prog.uniform_location("u_axis_y"), fr.axis_y.x, fr.axis_y.y, fr.axis_y.z);
  glUniform3f(prog.uniform_location("u_axis_z"), fr.axis_z.x, fr.axis_z.y, fr.axis_z.z);
  glUniform1i(prog.uniform_location("u_face"), f);
  glUniform1f(prog.uniform_location("u_resolution"), static_cast<float>(R));
  glUniform1f(prog.uniform_location("u_rim_margin"), 4.0f / static_cast<float>(R));
  glUniform1f(prog.uniform_location("u_far"), far_from(light.position));
  draw(prog, light_mesh->mesh());
  glDisable(GL_CLIP_DISTANCE0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("vplrender: DPRSM pass");
}

gbuffer_data gl_rasterizer::render_gbuffer(const camera& cam, int width, int height, raster_timing* timing) {
  impl_->gbuffer_rt.ensure(width, height, 4);  // allocated outside the timed draws
  vplkit::gl::timer_query tq;
  tq.begin();
  impl_->draw_gbuffer(cam, width, height);
  tq.end();

  const auto read_start = std::chrono::steady_clock::now();
  gbuffer_data g;
  g.width = width;
  g.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  g.position.assign(n, vec3(0.0f));
  g.normal.assign(n, vec3(0.0f));
  g.albedo.assign(n, vec3(0.0f));
  g.shading_normal.assign(n, vec3(0.0f));
  std::vector<vec3>* outs[4] = {&g.position, &g.normal, &g.albedo, &g.shading_normal};
  for (int a = 0; a < 4; ++a) {
    const std::vector<float> px = impl_->gbuffer_rt.read(a);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t src = (static_cast<std::size_t>(height - 1 - y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4u;
        const std::size_t dst = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
        if (px[src + 3] > 0.0f) (*outs[a])[dst] = vec3(px[src], px[src + 1], px[src + 2]);
      }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (timing) {
    timing->ms = tq.milliseconds();
    timing->clock = "gpu";
    timing->readback_ms = ms_since(read_start);
  }
  return g;
}

void gl_rasterizer::render_gbuffer_surfels(const camera& cam, int width, int height, const vplkit::gl::buffer& surfels,
                                           raster_timing* timing) {
  impl_->gbuffer_rt.ensure(width, height, 4);  // allocated outside the timed draws
  vplkit::gl::timer_query tq;
  tq.begin();
  impl_->draw_gbuffer(cam, width, height);
  copy_to_surfels(impl_->gbuffer_rt, 0, 0u, surfels);
  tq.end();
  if (timing) {
    timing->ms = tq.milliseconds();
    timing->clock = "gpu";
    timing->readback_ms = 0.0;
  }
}

dprsm_data gl_rasterizer::render_dprsm(const vplkit::point_light<float>& light, int R, const tessellation_params& tess,
                                       raster_timing* timing, tessellation_stats* ts) {
  const auto tess_start = std::chrono::steady_clock::now();
  const double ahead_ms = impl_->tessellate_for(light, tess, ts);
  const double tess_ms = ms_since(tess_start);
  impl_->dprsm_rt.ensure(R, R, 3);
  dprsm_data d;
  d.resolution = R;
  d.light = light;
  const std::size_t face = static_cast<std::size_t>(R) * static_cast<std::size_t>(R);
  d.position.assign(2 * face, vec3(0.0f));
  d.normal.assign(2 * face, vec3(0.0f));
  d.albedo.assign(2 * face, vec3(0.0f));
  double ms = 0.0, read_ms = 0.0;
  for (int f = 0; f < 2; ++f) {
    vplkit::gl::timer_query tq;
    tq.begin();
    impl_->draw_dprsm_face(light, R, f);
    tq.end();
    ms += tq.milliseconds();
    const auto read_start = std::chrono::steady_clock::now();
    std::vector<vec3>* outs[3] = {&d.position, &d.normal, &d.albedo};
    for (int a = 0; a < 3; ++a) {
      const std::vector<float> px = impl_->dprsm_rt.read(a);
      for (std::size_t i = 0; i < face; ++i)
        if (px[i * 4 + 3] > 0.0f) (*outs[a])[static_cast<std::size_t>(f) * face + i] = vec3(px[i * 4], px[i * 4 + 1], px[i * 4 + 2]);
    }
    read_ms += ms_since(read_start);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // Texels outside the unit disk carry no VPL: keep them exactly empty.
  for (int i = 0; i < 2 * R * R; ++i) {
    const glm::ivec2 xy = vplkit::texel_coords(i, R);
    if (!vplkit::texel_is_valid(xy.x, xy.y, R)) {
      d.position[static_cast<std::size_t>(i)] = d.normal[static_cast<std::size_t>(i)] = d.albedo[static_cast<std::size_t>(i)] = vec3(0.0f);
    }
  }
  if (timing) {
    timing->ms = ms;
    timing->clock = "gpu";
    timing->readback_ms = read_ms;
    timing->tessellation_ms = tess_ms;
    timing->split_ahead_ms = ahead_ms;
  }
  return d;
}

void gl_rasterizer::render_dprsm_surfels(const vplkit::point_light<float>& light, int R, const tessellation_params& tess,
                                         const vplkit::gl::buffer& surfels, raster_timing* timing,
                                         tessellation_stats* ts) {
  const auto tess_start = std::chrono::steady_clock::now();
  const double ahead_ms = impl_->tessellate_for(light, tess, ts);
  const double tess_ms = ms_since(tess_start);
  impl_->dprsm_rt.ensure(R, R, 3);
  const std::uint32_t face = static_cast<std::uint32_t>(R) * static_cast<std::uint32_t>(R);
  vplkit::gl::timer_query tq;
  tq.begin();
  for (int f = 0; f < 2; ++f) {
    impl_->draw_dprsm_face(light, R, f);
    copy_to_surfels(impl_->dprsm_rt, 1, static_cast<std::uint32_t>(f) * face, surfels);
  }
  tq.end();
  if (timing) {
    timing->ms = tq.milliseconds();
    timing->clock = "gpu";
    timing->readback_ms = 0.0;
    timing->tessellation_ms = tess_ms;
    timing->split_ahead_ms = ahead_ms;
  }
}

}  // namespace vplrender
