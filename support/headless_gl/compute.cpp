// SPDX-License-Identifier: MIT
#include "compute.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>

namespace vplkit::gl {

const char* gl_error_name(GLenum e) {
  switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: return "unknown GL error";
  }
}

void check_gl(const char* where) {
  std::string errors;
  bool out_of_memory = false;
  // glGetError returns one flag per call; bounded so a lost context cannot loop forever.
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    out_of_memory = out_of_memory || e == GL_OUT_OF_MEMORY;
    errors += std::string(errors.empty() ? "" : ", ") + gl_error_name(e);
  }
  if (out_of_memory) throw gl_out_of_memory(std::string(where) + ": " + errors, 0);
  if (!errors.empty()) throw gl_error(std::string(where) + ": " + errors);
}

std::string glsl_source_dir() {
#ifdef VPLKIT_GLSL_SOURCE_DIR
  return VPLKIT_GLSL_SOURCE_DIR;
#else
  return {};
#endif
}

// ---- program ----------------------------------------------------------------------------------
namespace {
std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, &log[0]);
  log.resize(std::strlen(log.c_str()));
  return log;
}
std::string program_log(GLuint prog) {
  GLint length = 0;
  glGetProgramiv(prog, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  glGetProgramInfoLog(prog, static_cast<GLsizei>(log.size()), nullptr, &log[0]);
  log.resize(std::strlen(log.c_str()));
  return log;
}
std::string file_table(const glsl::resolved_source* files) {
  if (files == nullptr || files->files.size() <= 1) return {};
  std::string t = "\nsource strings:";
  for (std::size_t k = 0; k < files->files.size(); ++k) {
    t += "\n  " + std::to_string(k) + ": " + files->file_label(k);
  }
  return t;
}
}  // namespace

program::~program() {
  if (id_ != 0) glDeleteProgram(id_);
}

program& program::operator=(program&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

program program::compute(const std::string& source, const glsl::resolved_source* files) {
  const std::string name = files != nullptr && !files->files.empty() ? files->file_label(0)
                                                                       : std::string("<source>");
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  if (shader == 0) throw gl_error("glCreateShader(GL_COMPUTE_SHADER) failed for " + name);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    std::string log = shader_log(shader);
    glDeleteShader(shader);
    if (files != nullptr) log = files->map_log(log);
    throw gl_error("compute shader " + name + " failed to compile:\n" + log + file_table(files));
  }
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, shader);
  glLinkProgram(prog);
  glDetachShader(prog, shader);
  glDeleteShader(shader);
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    std::string log = program_log(prog);
    glDeleteProgram(prog);
    if (files != nullptr) log = files->map_log(log);
    throw gl_error("compute program " + name + " failed to link:\n" + log + file_table(files));
  }
  check_gl(("building compute program " + name).c_str());
  return program(prog);
}

program program::compute_with_includes(const std::string& source, const std::string& name,
                                       const std::vector<std::string>& include_dirs,
                                       const std::string& preamble) {
  std::vector<std::string> dirs = include_dirs;
  if (dirs.empty()) dirs.push_back(glsl_source_dir());
  const glsl::resolved_source resolved = glsl::resolve_includes(source, name, dirs, preamble);
  return compute(resolved.text, &resolved);
}

program program::compute_from_file(const std::string& path,
                                   const std::vector<std::string>& include_dirs,
                                   const std::string& preamble) {
  std::vector<std::string> dirs = include_dirs;
  if (dirs.empty()) dirs.push_back(glsl_source_dir());
  const glsl::resolved_source resolved = glsl::resolve_include_file(path, dirs, preamble);
  return compute(resolved.text, &resolved);
}

void program::use() const { glUseProgram(id_); }

std::array<GLint, 3> program::local_size() const {
  std::array<GLint, 3> size{0, 0, 0};
  glGetProgramiv(id_, GL_COMPUTE_WORK_GROUP_SIZE, size.data());
  return size;
}

GLint program::uniform_location(const char* name) const {
  return glGetUniformLocation(id_, name);
}

// ---- program cache ----------------------------------------------------------------------------
const program& cached_kernel(const std::string& path, const std::string& preamble) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::string>, program> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(path, preamble);
  const auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const std::string file = !path.empty() && path.front() == '/' ? path : glsl_source_dir() + "/" + path;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw gl_error("cannot read " + file);
  std::ostringstream text;
  text << "#version 430\n" << in.rdbuf();
  const glsl::resolved_source resolved = glsl::resolve_includes(text.str(), file, {glsl_source_dir()}, preamble,
                                                                std::filesystem::path(file).parent_path().string());
  program p = program::compute(resolved.text, &resolved);
  return cache.emplace(key, std::move(p)).first->second;
}

// ---- GPU memory accounting --------------------------------------------------------------------
namespace {
gpu_memory& memory_counters() {
  static gpu_memory m;
  return m;
}
// A buffer holds at least one word (a zero-sized SSBO cannot be bound).
long long stored_bytes(std::size_t bytes) { return static_cast<long long>(bytes > 0 ? bytes : 4); }
}  // namespace

void track_gpu_bytes(long long delta_bytes) {
  gpu_memory& m = memory_counters();
  m.live_bytes += delta_bytes;
  if (m.live_bytes > m.peak_bytes) m.peak_bytes = m.live_bytes;
}

gpu_memory gpu_memory_usage() { return memory_counters(); }

void reset_gpu_memory_peak() { memory_counters().peak_bytes = memory_counters().live_bytes; }

// ---- buffer -----------------------------------------------------------------------------------
buffer::~buffer() {
  if (id_ != 0) {
    glDeleteBuffers(1, &id_);
    track_gpu_bytes(-stored_bytes(bytes_));
  }
}

buffer& buffer::operator=(buffer&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) {
      glDeleteBuffers(1, &id_);
      track_gpu_bytes(-stored_bytes(bytes_));
    }
    id_ = std::exchange(other.id_, 0);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

buffer buffer::from_bytes(const void* data, std::size_t bytes) {
  buffer b;
  glGenBuffers(1, &b.id_);
  b.bytes_ = bytes;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id_);
  // A zero-sized SSBO cannot be bound; keep one word so an empty input still binds.
  const std::vector<unsigned char> zero(4, 0);
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes > 0 ? bytes : 4),
               bytes > 0 ? data : zero.data(), GL_DYNAMIC_COPY);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  track_gpu_bytes(stored_bytes(bytes));  // before the check: b's destructor untracks on a throw
  try {
    check_gl("creating a shader storage buffer");
  } catch (const gl_out_of_memory& e) {
    throw gl_out_of_memory(std::string(e.what()).substr(std::strlen("vplkit gl: ")), bytes);
  }
  return b;
}

buffer buffer::filled(std::size_t bytes, unsigned char fill_byte) {
  // Filled by the GL (glClearBufferData), not uploaded from a host array: a GPU frame allocates
  // tens of MB of state and scratch, which would otherwise cross the bus every frame.
  buffer b = from_bytes(nullptr, bytes);  // storage only (an empty buffer's one word is 0 already)
  if (bytes == 0) return b;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id_);
  glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &fill_byte);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  check_gl("filling a shader storage buffer");
  return b;
}

void buffer::bind(GLuint binding) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_);
}

void buffer::read_bytes(void* out, std::size_t offset, std::size_t bytes) const {
  if (offset + bytes > bytes_) throw gl_error("buffer read past its end");
  if (bytes == 0) return;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset),
                     static_cast<GLsizeiptr>(bytes), out);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  check_gl("reading a shader storage buffer");
}

void buffer::write_bytes(const void* data, std::size_t offset, std::size_t bytes) {
  if (offset + bytes > bytes_) throw gl_error("buffer write past its end");
  if (bytes == 0) return;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset),
                  static_cast<GLsizeiptr>(bytes), data);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  check_gl("writing a shader storage buffer");
}

// ---- dispatch ---------------------------------------------------------------------------------
void memory_barrier(GLbitfield bits) { glMemoryBarrier(bits); }

void dispatch(const program& p, GLuint groups_x, GLuint groups_y, GLuint groups_z) {
  const GLuint groups[3] = {groups_x, groups_y, groups_z};
  for (GLuint axis = 0; axis < 3; ++axis) {
    const GLuint max_groups = max_work_group_count(axis);
    if (groups[axis] > max_groups) {
      throw gl_error("dispatch: " + std::to_string(groups[axis]) + " work groups on axis " +
                     std::to_string(axis) + " exceed GL_MAX_COMPUTE_WORK_GROUP_COUNT = " +
                     std::to_string(max_groups));
    }
  }
  p.use();
  glDispatchCompute(groups_x, groups_y, groups_z);
  memory_barrier();
  check_gl("glDispatchCompute");
}

group_grid split_groups(std::size_t groups, GLuint max_x, GLuint max_y, const char* what) {
  const std::size_t mx = std::max<GLuint>(max_x, 1), my = std::max<GLuint>(max_y, 1);
  const std::size_t n = std::max<std::size_t>(groups, 1);
  const std::size_t x = std::min(n, mx);
  const std::size_t y = (n + x - 1) / x;
  if (y > my) {
    throw gl_error(std::string(what) + ": " + std::to_string(groups) + " work groups exceed " + std::to_string(mx) +
                   " x " + std::to_string(my) + " (GL_MAX_COMPUTE_WORK_GROUP_COUNT on x and y)");
  }
  return {static_cast<GLuint>(x), static_cast<GLuint>(y)};
}

GLuint max_work_group_count(GLuint axis) {
  GLint max_groups = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, axis, &max_groups);
  check_gl("glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT)");
  return max_groups > 0 ? static_cast<GLuint>(max_groups) : 0u;
}

void dispatch_linear(const program& p, std::size_t groups, GLuint groups_z) {
  const group_grid g = split_groups(groups, max_work_group_count(0), max_work_group_count(1), "dispatch_linear");
  dispatch(p, g.x, g.y, groups_z);
}

// ---- timer ------------------------------------------------------------------------------------
bool is_software_renderer() {
  const GLubyte* r = glGetString(GL_RENDERER);
  const std::string renderer = r ? reinterpret_cast<const char*>(r) : "";
  return renderer.find("llvmpipe") != std::string::npos ||
         renderer.find("softpipe") != std::string::npos;
}

namespace {
double steady_ms() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

timer_query::timer_query() : software_(is_software_renderer()) {
  if (!software_) glGenQueries(1, &id_);
}

timer_query::~timer_query() {
  if (running_ && !software_) glEndQuery(GL_TIME_ELAPSED);
  if (id_ != 0) glDeleteQueries(1, &id_);
}

const char* timer_query::method() const {
  return software_ ? "glFinish + steady_clock (software renderer)" : "GL_TIME_ELAPSED";
}

void timer_query::begin() {
  if (running_) throw gl_error("timer_query::begin while running");
  if (software_) {
    glFinish();
    cpu_begin_ms_ = steady_ms();
  } else {
    glBeginQuery(GL_TIME_ELAPSED, id_);
  }
  running_ = true;
  done_ = false;
}

void timer_query::end() {
  if (!running_) throw gl_error("timer_query::end without begin");
  if (software_) {
    glFinish();
    cpu_end_ms_ = steady_ms();
  } else {
    glEndQuery(GL_TIME_ELAPSED);
  }
  running_ = false;
  done_ = true;
  check_gl("timer_query::end");
}

double timer_query::milliseconds() const {
  if (!done_) throw gl_error("timer_query::milliseconds before begin/end");
  if (software_) return cpu_end_ms_ - cpu_begin_ms_;
  GLuint64 ns = 0;
  glGetQueryObjectui64v(id_, GL_QUERY_RESULT, &ns);  // waits for the result
  return static_cast<double>(ns) * 1e-6;
}

}  // namespace vplkit::gl
