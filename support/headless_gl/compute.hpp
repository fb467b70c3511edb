// SPDX-License-Identifier: MIT
#pragma once
// Small RAII helpers for compute work on the current GL context (see context.hpp): programs
// compiled from source with readable errors, shader storage buffers from std::vector, dispatch,
// barriers, read-back and GL_TIME_ELAPSED timer queries. GL calls go through libepoxy.
#include <epoxy/gl.h>

#include <vplkit/glsl/include_resolver.hpp>

#include <array>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vplkit::gl {

// A GL call failed or a shader did not compile/link; what() carries the (file-mapped) log.
class gl_error : public std::runtime_error {
public:
  explicit gl_error(const std::string& what) : std::runtime_error("vplkit gl: " + what) {}
};

// GL_OUT_OF_MEMORY: the driver could not allocate; `bytes` is the size asked for (0 = unknown).
class gl_out_of_memory : public gl_error {
public:
  gl_out_of_memory(const std::string& what, std::size_t bytes) : gl_error(what), bytes_(bytes) {}
  std::size_t bytes() const { return bytes_; }

private:
  std::size_t bytes_;
};

const char* gl_error_name(GLenum e);
// Throws gl_error naming `where` when glGetError() reports anything (drains all pending errors);
// gl_out_of_memory when one of them is GL_OUT_OF_MEMORY.
void check_gl(const char* where);

// Include root of the GLSL pack in the source tree (CMake passes VPLKIT_GLSL_SOURCE_DIR).
std::string glsl_source_dir();

// ---- programs -------------------------------------------------------------------------------
class program {
public:
  program() = default;
  ~program();
  program(program&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  program& operator=(program&& other) noexcept;
  program(const program&) = delete;
  program& operator=(const program&) = delete;

  // Compiles and links a compute shader from text that glShaderSource accepts as is (no
  // #include). `files` maps #line source-string numbers to names for the error message.
  static program compute(const std::string& source, const glsl::resolved_source* files = nullptr);
  // The same after resolving #include against `include_dirs` (default: the pack root);
  // `preamble` lands after #version/#extension (see include_resolver.hpp). `name` labels the
  // source in errors.
  static program compute_with_includes(const std::string& source, const std::string& name,
                                       const std::vector<std::string>& include_dirs = {},
                                       const std::string& preamble = {});
  static program compute_from_file(const std::string& path,
                                   const std::vector<std::string>& include_dirs = {},
                                   const std::string& preamble = {});

  GLuint id() const { return id_; }
  void use() const;
  // layout(local_size_x, _y, _z) as linked.
  std::array<GLint, 3> local_size() const;
  GLint uniform_location(const char* name) const;

private:
  explicit program(GLuint id) : id_(id) {}
  GLuint id_ = 0;
};

// ---- program cache ----------------------------------------------------------------------------
// A compute kernel compiled once and kept for the life of the process: the one cache of every
// host that dispatches kernels repeatedly (the renderer's builders, CDFs and estimator). The key
// is the kernel file and the preamble (defines, placed after #version). Kernel files are
// #version-free (docs/glsl.md): "#version 430" is put first. A relative `path` is looked up under
// the pack root (glsl_source_dir()), an absolute one is used as it is. Its #includes resolve
// against the pack root, and quoted ones first in the kernel's own folder (glslang's rule), so a
// host's kernel may include its own files beside it. The programs belong to the
// context current at their first use: vplkit's tools keep one context per process. Thread-safe.
// Throws gl_error when the file cannot be read or the kernel does not compile.
const program& cached_kernel(const std::string& path, const std::string& preamble = {});

// ---- GPU memory accounting --------------------------------------------------------------------
// GL has no portable query for what a context holds, so the allocations are counted where they are
// made: every `buffer` below, plus what other code reports with track_gpu_bytes (render targets,
// vertex buffers, textures). Process-wide (one context per process in vplkit's tools); the peak is
// what the results' memory table reports per method.
struct gpu_memory {
  long long live_bytes = 0;
  long long peak_bytes = 0;  // largest live_bytes since the last reset_gpu_memory_peak()
};
void track_gpu_bytes(long long delta_bytes);
gpu_memory gpu_memory_usage();
void reset_gpu_memory_peak();  // peak = live

// ---- shader storage buffers -------------------------------------------------------------------
class buffer {
public:
  buffer() = default;
  ~buffer();
  buffer(buffer&& other) noexcept
      : id_(std::exchange(other.id_, 0)), bytes_(std::exchange(other.bytes_, 0)) {}
  buffer& operator=(buffer&& other) noexcept;
  buffer(const buffer&) = delete;
  buffer& operator=(const buffer&) = delete;

  // `bytes` of storage filled with `fill_byte` (0xFF makes unwritten floats NaN and uints ~0u, so
  // a kernel that skips an element is caught).
  static buffer filled(std::size_t bytes, unsigned char fill_byte = 0);
  static buffer from_bytes(const void* data, std::size_t bytes);  // data null: storage only, contents undefined
  // The element type must match the GLSL std430 layout: scalars, vec2/vec4-sized structs, or
  // structs padded by hand (a vec3 array element has a 16-byte stride in std430).
  template <class T>
  static buffer from_vector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
    return from_bytes(v.data(), v.size() * sizeof(T));
  }

  GLuint id() const { return id_; }
  std::size_t size_bytes() const { return bytes_; }
  // glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id).
  void bind(GLuint binding) const;
  void read_bytes(void* out, std::size_t offset, std::size_t bytes) const;
  void write_bytes(const void* data, std::size_t offset, std::size_t bytes);

  template <class T>
  std::vector<T> read(std::size_t count = std::size_t(-1)) const {
    static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
    if (count == std::size_t(-1)) count = bytes_ / sizeof(T);
    std::vector<T> out(count);
    read_bytes(out.data(), 0, count * sizeof(T));
    return out;
  }
  template <class T>
  void write(const std::vector<T>& v, std::size_t offset_bytes = 0) {
    static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
    write_bytes(v.data(), offset_bytes, v.size() * sizeof(T));
  }

private:
  GLuint id_ = 0;
  std::size_t bytes_ = 0;
};

// ---- dispatch -------------------------------------------------------------------------------
// Number of work groups covering `invocations` with groups of `local_size` (at least 1).
inline GLuint groups_for(std::size_t invocations, GLint local_size) {
  const std::size_t l = local_size > 0 ? static_cast<std::size_t>(local_size) : 1;
  const std::size_t g = (invocations + l - 1) / l;
  return static_cast<GLuint>(g > 0 ? g : 1);
}

// A 1D range of work groups laid out on two axes, x * y >= the range, for ranges past
// GL_MAX_COMPUTE_WORK_GROUP_COUNT on x (a 2048^2 DPRSM holds 8.4M texels: 131072 groups of 64,
// and the GL minimum is 65535 per axis). Kernels read their linear group as
// gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x and return past the end of the range.
struct group_grid {
  GLuint x = 1, y = 1;
};
// Pure (tested without GL): x = min(groups, max_x), y = ceil(groups / x); a range that fits on x
// stays (groups, 1), so dispatches that fit are unchanged. Throws gl_error naming `what` when even
// max_x * max_y groups cannot cover the range.
group_grid split_groups(std::size_t groups, GLuint max_x, GLuint max_y, const char* what = "dispatch");
// GL_MAX_COMPUTE_WORK_GROUP_COUNT on `axis` (0, 1, 2) of the current context.
GLuint max_work_group_count(GLuint axis);

// glMemoryBarrier with the bits a compute -> read-back or compute -> compute chain needs.
void memory_barrier(GLbitfield bits = GL_SHADER_STORAGE_BARRIER_BIT |
                                      GL_BUFFER_UPDATE_BARRIER_BIT);
// use(), glDispatchCompute, memory_barrier(), check_gl. Throws when a group count exceeds
// GL_MAX_COMPUTE_WORK_GROUP_COUNT.
void dispatch(const program& p, GLuint groups_x, GLuint groups_y = 1, GLuint groups_z = 1);
// `groups` work groups as a group_grid over x and y (split_groups against the context's limits),
// times `groups_z` on z (regions, faces, distributions). Same barrier and checks as dispatch().
void dispatch_linear(const program& p, std::size_t groups, GLuint groups_z = 1);

// ---- GPU timing ---------------------------------------------------------------------------------
// Device time of the GL work between begin() and end(); milliseconds() waits for the result.
// On a GPU this is a GL_TIME_ELAPSED query (one active at a time: timers cannot nest).
// On Mesa's software renderers (llvmpipe, softpipe) GL_TIME_ELAPSED does not cover compute
// dispatches (measured with Mesa 22.3: 1 ns for seconds of compute under EGL, a raw timestamp
// under OSMesa), and there the "device" is the CPU anyway, so the timer brackets the work with
// glFinish() and std::chrono::steady_clock instead. method() says which one is in use.
class timer_query {
public:
  timer_query();
  ~timer_query();
  timer_query(const timer_query&) = delete;
  timer_query& operator=(const timer_query&) = delete;
  void begin();
  void end();
  double milliseconds() const;
  const char* method() const;

private:
  GLuint id_ = 0;
  bool software_ = false;
  bool running_ = false;
  bool done_ = false;
  double cpu_begin_ms_ = 0, cpu_end_ms_ = 0;
};

// True for Mesa's CPU renderers (GL_RENDERER names llvmpipe or softpipe).
bool is_software_renderer();

}  // namespace vplkit::gl
