// SPDX-License-Identifier: MIT
#include "raster/gl_raster.hpp"

#include <headless_gl/compute.hpp>
#include <vplkit/glsl/include_resolver.hpp>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

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

GLuint compile_stage(GLenum kind, const std::string& source, const std::string& name) {
  const vplkit::glsl::resolved_source src =
      vplkit::glsl::resolve_includes(source, name, {vplkit::gl::glsl_source_dir()});
  const GLuint sh = glCreateShader(kind);
  const char* text = src.text.c_str();
  glShaderSource(sh, 1, &text, nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetShaderInfoLog(sh, len, nullptr, log.data());
    glDeleteShader(sh);
    throw gl_error(name + " does not compile:\n" + src.map_log(log));
  }
  return sh;
}

GLuint link_program(const std::string& vs, const std::string& fs, const std::string& name) {
  const GLuint v = compile_stage(GL_VERTEX_SHADER, vs, name + ".vert");
  const GLuint f = compile_stage(GL_FRAGMENT_SHADER, fs, name + ".frag");
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetProgramInfoLog(p, len, nullptr, log.data());
    glDeleteProgram(p);
    throw gl_error(name + " does not link:\n" + log);
  }
  return p;
}

// ---- shaders ---------------------------------------------------------------------------------
// Vertex layout shared by both passes: position, shading normal, texcoord, and the plane of the
// (parent) triangle (unit geometric normal n, n . p), the same at all three corners.
const char* const common_vs_inputs = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_plane;
)";

const char* const material_fs = R"(
uniform vec3 u_kd;
uniform int u_textured;
uniform sampler2D u_texture;  // GL_SRGB8, GL_LINEAR, GL_REPEAT, no mipmaps: texture.cpp's lookup
vec3 material_albedo(vec2 uv) { return u_textured != 0 ? texture(u_texture, uv).rgb : u_kd; }
)";

std::string gbuffer_vs() {
  return std::string("#version 430 core\n") + common_vs_inputs + R"(
uniform mat4 u_view_projection;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out vec4 v_plane;
void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_plane = a_plane;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
)";
}

// Depth = distance to the eye / u_far, written per fragment (as the DPRSM pass does). The
// projection's own depth, with znear = 1e-5 zfar, resolves only about 1e-5 z^2 / znear in float:
// millimetres in the Cornell box, so where a closed box's top face lies just behind its front face
// (the camera a little below the top) the back face won the test along the front face's top row.
// Linear depth resolves 2^-24 u_far everywhere.
std::string gbuffer_fs() {
  return std::string("#version 430 core\n") + material_fs + R"(
uniform vec3 u_eye;
uniform float u_far;
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in vec4 v_plane;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
layout(location = 3) out vec4 o_shading_normal;
void main() {
  // Geometric normal: the triangle's plane, turned to the camera's side of it (two-sided). The
  // side is decided by the plane equation at the eye, exact for the whole triangle; an
  // interpolated normal against the interpolated position can pick the wrong side.
  vec3 ng = v_plane.xyz;
  if (dot(ng, u_eye) - v_plane.w < 0.0) ng = -ng;
  // Shading normal: the interpolated vertex normal, on the geometric normal's side.
  vec3 ns = v_normal;
  float len = length(ns);
  ns = len > 0.0 ? ns / len : ng;
  if (dot(ns, ng) < 0.0) ns = -ns;
  // A flat triangle's vertex normal and its plane's normal differ by rounding only: one vector
  // for both then (the shading one, as before), so flat scenes keep their G-buffer bit for bit.
  if (dot(ns, ng) >= 1.0 - 1e-6) ng = ns;
  if (dot(ng, ng) == 0.0) ng = ns;  // a degenerate triangle has no plane
  gl_FragDepth = clamp(length(v_position - u_eye) / u_far, 0.0, 1.0);
  o_position = vec4(v_position, 1.0);
  o_normal = vec4(ng, 1.0);
  o_albedo = vec4(material_albedo(v_uv), 1.0);
  o_shading_normal = vec4(ns, 1.0);
}
)";
}

// Paraboloid projection in the vertex shader, homogeneous form: with d the unit light-space
// direction and z' = d.z on the front face, -d.z on the back face, clip = (d.x, d.y, 0, 1 + z')
// divides to uv = d.xy / (1 + z') = vplkit_paraboloid_from_direction's uv on that face. The other
// hemisphere is cut by gl_ClipDistance[0] = z' + m >= 0, so a triangle straddling the rim is
// clipped just past it (w ~ 1 there, finite everywhere it is kept; the back pole, where w = 0, is
// always clipped). The margin m = 4/R (two rim texels in angle) exists because the clipped edge is
// a straight chord in uv between two points of the circle: clipping exactly at z' = 0 left the
// valid texels between chord and rim empty (measured: 1.7% of the texels at R = 64, all with
// r2 > 0.98). Texels outside the unit disk are cleared after read-back. Depth is written per
// fragment.
std::string dprsm_vs() {
  return std::string("#version 430 core\n") + common_vs_inputs + R"(
uniform vec3 u_light;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_face;
uniform float u_rim_margin;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out vec4 v_plane;
out float gl_ClipDistance[1];
void main() {
  vec3 q = a_position - u_light;
  vec3 l = vec3(dot(q, u_axis_x), dot(q, u_axis_y), dot(q, u_axis_z));
  float len = length(l);
  vec3 d = len > 0.0 ? l / len : vec3(0.0, 0.0, 1.0);
  float z = u_face == 0 ? d.z : -d.z;
  gl_ClipDistance[0] = z + u_rim_margin;
  gl_Position = vec4(d.x, d.y, 0.0, 1.0 + z);
  v_position = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_plane = a_plane;
}
)";
}

// Per fragment (= texel centre, gl_FragCoord.xy = (x + 0.5, y + 0.5)): the texel's exact light
// ray (vplkit_paraboloid_to_direction) meets the triangle's plane; that point, not the
// interpolated one, is stored, so inside a triangle the map equals a ray cast exactly up to float
// rounding. Attributes (normal, texcoord) are interpolated across the (small, tessellated)
// triangle. Depth = distance to the light / u_far.
std::string dprsm_fs() {
  return std::string("#version 430 core\n#include \"vplkit/paraboloid/paraboloid.glsl\"\n") + material_fs + R"(
uniform vec3 u_light;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_face;
uniform float u_resolution;
uniform float u_far;
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in vec4 v_plane;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
void main() {
  vec2 uv = gl_FragCoord.xy / u_resolution * 2.0 - 1.0;
  vec3 dl = vplkit_paraboloid_to_direction(u_face, uv);
  vec3 dir = u_axis_x * dl.x + u_axis_y * dl.y + u_axis_z * dl.z;
  vec3 p = v_position;
  float denom = dot(v_plane.xyz, dir);
  if (abs(denom) > 1e-6) {
    float t = (v_plane.w - dot(v_plane.xyz, u_light)) / denom;
    // The texel's ray meets the plane behind the light: this triangle cannot be what the texel
    // sees (a triangle whose interpolation wrapped across the face, see tessellate.hpp).
    if (!(t > 0.0)) discard;
    p = u_light + t * dir;
  }
  vec3 n = v_normal;
  float len = length(n);
  n = len > 0.0 ? n / len : v_plane.xyz;
  if (dot(n, u_light - p) < 0.0) n = -n;  // two-sided: the lit side reflects
  gl_FragDepth = clamp(length(p - u_light) / u_far, 0.0, 1.0);
  o_position = vec4(p, 1.0);
  o_normal = vec4(n, 1.0);
  o_albedo = vec4(material_albedo(v_uv), 1.0);
}
)";
}

struct vertex {
  float p[3], n[3], uv[2], plane[4];
};

struct mesh {
  GLuint vao = 0, vbo = 0;
  long long bytes = 0;  // vbo storage, for vplkit::gl::track_gpu_bytes
  // Ranges of vertices per material (triangles sorted by material).
  struct range {
    std::uint32_t material;
    GLint first;
    GLsizei count;
  };
  std::vector<range> ranges;
  void release() {
    if (vbo) glDeleteBuffers(1, &vbo);
    if (vao) glDeleteVertexArrays(1, &vao);
    vao = vbo = 0;
    vplkit::gl::track_gpu_bytes(-bytes);
    bytes = 0;
    ranges.clear();
  }
};

void upload(mesh& m, const std::vector<triangle>& tris_in) {
  std::vector<std::size_t> order(tris_in.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return tris_in[a].material < tris_in[b].material; });
  std::vector<vertex> verts;
  verts.reserve(tris_in.size() * 3);
  m.ranges.clear();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const triangle& t = tris_in[order[k]];
    const glm::dvec3 e1 = glm::dvec3(t.p[1]) - glm::dvec3(t.p[0]), e2 = glm::dvec3(t.p[2]) - glm::dvec3(t.p[0]);
    glm::dvec3 g = glm::cross(e1, e2);
    const double gl = glm::length(g);
    g = gl > 0.0 ? g / gl : glm::dvec3(0.0);
    const double w = glm::dot(g, (glm::dvec3(t.p[0]) + glm::dvec3(t.p[1]) + glm::dvec3(t.p[2])) / 3.0);
    if (m.ranges.empty() || m.ranges.back().material != t.material)
      m.ranges.push_back({t.material, static_cast<GLint>(verts.size()), 0});
    for (int c = 0; c < 3; ++c) {
      const std::size_t ci = static_cast<std::size_t>(c);
      vertex v{};
      for (int a = 0; a < 3; ++a) {
        v.p[a] = t.p[ci][a];
        v.n[a] = t.n[ci][a];
        v.plane[a] = static_cast<float>(g[a]);
      }
      v.uv[0] = t.uv[ci].x;
      v.uv[1] = t.uv[ci].y;
      v.plane[3] = static_cast<float>(w);
      verts.push_back(v);
    }
    m.ranges.back().count += 3;
  }
  if (!m.vao) glGenVertexArrays(1, &m.vao);
  if (!m.vbo) glGenBuffers(1, &m.vbo);
  glBindVertexArray(m.vao);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(vertex)), verts.data(), GL_STATIC_DRAW);
  const long long vbo_bytes = static_cast<long long>(verts.size() * sizeof(vertex));
  vplkit::gl::track_gpu_bytes(vbo_bytes - m.bytes);
  m.bytes = vbo_bytes;
  const GLsizei stride = sizeof(vertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(vertex, p)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(vertex, n)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(vertex, uv)));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(vertex, plane)));
  glBindVertexArray(0);
  check_gl("vplrender: mesh upload");
}

// `attachments` (3: DPRSM, 4: G-buffer) RGBA32F colour targets + a 32-bit float depth buffer.
struct target {
  GLuint fbo = 0, depth = 0;
  GLuint color[4] = {0, 0, 0, 0};
  int attachments = 0;
  int w = 0, h = 0;
  void create(int width, int height, int count) {
    release();
    w = width;
    h = height;
    attachments = count;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenTextures(attachments, color);
    for (int i = 0; i < attachments; ++i) {
      glBindTexture(GL_TEXTURE_2D, color[i]);
      glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, h);
      // Read by texelFetch in surfels_from_targets.comp: one level, no filtering.
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D, color[i], 0);
    }
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    vplkit::gl::track_gpu_bytes(bytes());
    const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    glDrawBuffers(attachments, bufs);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw gl_error("vplrender: float render target " + std::to_string(w) + "x" + std::to_string(h) +
                     " is incomplete (status 0x" + std::to_string(status) + ")");
    check_gl("vplrender: render target");
  }
  void clear() {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < attachments; ++i) glClearBufferfv(GL_COLOR, i, zero);
    const float one = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &one);
  }
  // Attachment i as w*h RGBA floats, GL row order (bottom row first).
  std::vector<float> read(int i) const {
    std::vector<float> px(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4u);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, px.data());
    check_gl("vplrender: read-back");
    return px;
  }
  // The RGBA32F targets and a 32-bit depth buffer.
  long long bytes() const { return static_cast<long long>(w) * h * (attachments * 16 + 4); }
  void release() {
    if (fbo) vplkit::gl::track_gpu_bytes(-bytes());
    if (depth) glDeleteRenderbuffers(1, &depth);
    if (color[0]) glDeleteTextures(attachments, color);
    if (fbo) glDeleteFramebuffers(1, &fbo);
    fbo = depth = 0;
    color[0] = color[1] = color[2] = color[3] = 0;
  }
};

}  // namespace

struct gl_rasterizer::impl {
  const scene* s = nullptr;
  GLuint gbuffer_program = 0, dprsm_program = 0;
  std::vector<GLuint> textures;  // per scene texture
  mesh scene_mesh;               // the scene as is (G-buffer)
  mesh light_mesh;               // the scene tessellated for the last DPRSM's light
  long long texture_bytes = 0;   // RGB8 is padded to 4 bytes per texel by most drivers
  target gbuffer_rt, dprsm_rt;   // kept for the next call of the same size
  ~impl() {
    gbuffer_rt.release();
    dprsm_rt.release();
    light_mesh.release();
    scene_mesh.release();
    if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
    vplkit::gl::track_gpu_bytes(-texture_bytes);
    if (gbuffer_program) glDeleteProgram(gbuffer_program);
    if (dprsm_program) glDeleteProgram(dprsm_program);
  }

  void draw(GLuint prog, const mesh& m) {
    const GLint kd = glGetUniformLocation(prog, "u_kd");
    const GLint textured = glGetUniformLocation(prog, "u_textured");
    const GLint sampler = glGetUniformLocation(prog, "u_texture");
    glUniform1i(sampler, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(m.vao);
    for (const mesh::range& r : m.ranges) {
      const material& mat = s->materials[r.material];
      glUniform3f(kd, mat.kd.x, mat.kd.y, mat.kd.z);
      glUniform1i(textured, mat.texture >= 0 ? 1 : 0);
      glBindTexture(GL_TEXTURE_2D, mat.texture >= 0 ? textures[static_cast<std::size_t>(mat.texture)] : 0);
      glDrawArrays(GL_TRIANGLES, r.first, r.count);
    }
    glBindVertexArray(0);
  }

  void draw_gbuffer(const camera& cam, int width, int height);
  void tessellate_for(const vplkit::point_light<float>& light, const tessellation_params& tess, tessellation_stats* ts);
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
  impl_->gbuffer_program = link_program(gbuffer_vs(), gbuffer_fs(), "vplrender_gbuffer");
  impl_->dprsm_program = link_program(dprsm_vs(), dprsm_fs(), "vplrender_dprsm");
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
  upload(impl_->scene_mesh, s.triangles);
  check_gl("vplrender: rasteriser setup");
}

gl_rasterizer::~gl_rasterizer() = default;


namespace {

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

// The same render target as last time when the size matches (frames reuse them), else a new one.
void ensure_target(target& rt, int width, int height, int attachments) {
  if (rt.fbo != 0 && rt.w == width && rt.h == height && rt.attachments == attachments) return;
  rt.create(width, height, attachments);
}

// tessellate_for_light over the triangles in chunks on all cores, concatenated in order: each
// triangle is split on its own, so this is the serial output, once min_edge is fixed from the
// whole mesh as the serial call fixes it. A moving light re-tessellates every frame (cornell at
// R = 512: 36 -> 22,742 triangles), which one core does in milliseconds.
std::vector<triangle> tessellate_on_all_cores(const std::vector<triangle>& tris, vec3 light, tessellation_params tess,
                                              tessellation_stats* ts) {
  if (!(tess.min_edge > 0.0)) tess.min_edge = tessellation_min_edge(tris);
  const std::size_t threads = std::max(1u, std::thread::hardware_concurrency());
  // Several chunks per thread (the split is uneven: triangles near the light yield the most),
  // taken in turn; a scene of few large triangles (cornell: 36) goes one triangle per chunk.
  const std::size_t chunk = tris.size() / (4 * threads) + 1;
  const std::size_t chunks = (tris.size() + chunk - 1) / chunk;
  if (chunks <= 1 || threads == 1) return tessellate_for_light(tris, light, tess, ts);
  std::vector<std::vector<triangle>> parts(chunks);
  std::vector<tessellation_stats> stats(chunks);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    for (std::size_t c = next++; c < chunks; c = next++) {
      try {
        const std::vector<triangle> in(tris.begin() + std::ptrdiff_t(c * chunk),
                                       tris.begin() + std::ptrdiff_t(std::min(tris.size(), (c + 1) * chunk)));
        parts[c] = tessellate_for_light(in, light, tess, &stats[c]);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t k = 1; k < std::min(threads, chunks); ++k) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  std::vector<triangle> out;
  tessellation_stats total;
  for (std::size_t c = 0; c < chunks; ++c) {
    out.insert(out.end(), parts[c].begin(), parts[c].end());
    total.input += stats[c].input;
    total.output += stats[c].output;
    total.capped += stats[c].capped;
  }
  if (ts) *ts = total;
  return out;
}

// surfels_from_targets.comp over `rt`: kind 0 the G-buffer (rows flipped, four targets), kind 1 a
// DPRSM face (three targets, surfels from `first`).
void copy_to_surfels(const target& rt, int kind, std::uint32_t first, const vplkit::gl::buffer& surfels) {
  const std::size_t texels = static_cast<std::size_t>(rt.w) * static_cast<std::size_t>(rt.h);
  if (surfels.size_bytes() < 48 * (first + texels))
    throw gl_error("vplrender: the surfel buffer holds fewer than " + std::to_string(first + texels) + " surfels");
  const vplkit::gl::program& prog =
      vplkit::gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/surfels_from_targets.comp");
  prog.use();
  glUniform1i(prog.uniform_location("u_width"), rt.w);
  glUniform1i(prog.uniform_location("u_height"), rt.h);
  glUniform1i(prog.uniform_location("u_kind"), kind);
  glUniform1ui(prog.uniform_location("u_first"), first);
  for (int i = 0; i < 4; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    // The DPRSM has no fourth target: its sampler is never read, bind the first one.
    glBindTexture(GL_TEXTURE_2D, rt.color[i < rt.attachments ? i : 0]);
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
  ensure_target(gbuffer_rt, width, height, 4);
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
  glUseProgram(gbuffer_program);
  glUniformMatrix4fv(glGetUniformLocation(gbuffer_program, "u_view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
  glUniform3f(glGetUniformLocation(gbuffer_program, "u_eye"), cam.eye.x, cam.eye.y, cam.eye.z);
  glUniform1f(glGetUniformLocation(gbuffer_program, "u_far"), zfar);
  draw(gbuffer_program, scene_mesh);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("vplrender: G-buffer pass");
}

void gl_rasterizer::impl::tessellate_for(const vplkit::point_light<float>& light, const tessellation_params& tess,
                                         tessellation_stats* ts) {
  upload(light_mesh, tessellate_on_all_cores(s->triangles, light.position, tess, ts));
}

void gl_rasterizer::impl::draw_dprsm_face(const vplkit::point_light<float>& light, int R, int f) {
  ensure_target(dprsm_rt, R, R, 3);
  const GLuint prog = dprsm_program;
  dprsm_rt.clear();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glEnable(GL_CLIP_DISTANCE0);
  glUseProgram(prog);
  glUniform3f(glGetUniformLocation(prog, "u_light"), light.position.x, light.position.y, light.position.z);
  const vplkit::light_frame<float>& fr = light.frame;
  glUniform3f(glGetUniformLocation(prog, "u_axis_x"), fr.axis_x.x, fr.axis_x.y, fr.axis_x.z);
  glUniform3f(glGetUniformLocation(prog, "u_axis_y"), fr.axis_y.x, fr.axis_y.y, fr.axis_y.z);
  glUniform3f(glGetUniformLocation(prog, "u_axis_z"), fr.axis_z.x, fr.axis_z.y, fr.axis_z.z);
  glUniform1i(glGetUniformLocation(prog, "u_face"), f);
  glUniform1f(glGetUniformLocation(prog, "u_resolution"), static_cast<float>(R));
  glUniform1f(glGetUniformLocation(prog, "u_rim_margin"), 4.0f / static_cast<float>(R));
  glUniform1f(glGetUniformLocation(prog, "u_far"), far_from(light.position));
  draw(prog, light_mesh);
  glDisable(GL_CLIP_DISTANCE0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("vplrender: DPRSM pass");
}

gbuffer_data gl_rasterizer::render_gbuffer(const camera& cam, int width, int height, raster_timing* timing) {
  ensure_target(impl_->gbuffer_rt, width, height, 4);  // allocated outside the timed draws
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
  ensure_target(impl_->gbuffer_rt, width, height, 4);  // allocated outside the timed draws
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
  impl_->tessellate_for(light, tess, ts);
  const double tess_ms = ms_since(tess_start);
  ensure_target(impl_->dprsm_rt, R, R, 3);
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
  }
  return d;
}

void gl_rasterizer::render_dprsm_surfels(const vplkit::point_light<float>& light, int R, const tessellation_params& tess,
                                         const vplkit::gl::buffer& surfels, raster_timing* timing,
                                         tessellation_stats* ts) {
  const auto tess_start = std::chrono::steady_clock::now();
  impl_->tessellate_for(light, tess, ts);
  const double tess_ms = ms_since(tess_start);
  ensure_target(impl_->dprsm_rt, R, R, 3);
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
  }
}

}  // namespace vplrender
