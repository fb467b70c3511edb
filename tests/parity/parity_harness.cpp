// SPDX-License-Identifier: MIT
// Listeners need Catch2's external interfaces, declared before catch.hpp is first included.
#define CATCH_CONFIG_EXTERNAL_INTERFACES
#include <fp_mode_listener.hpp>

#include "parity_harness.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

// Every test case runs its C++ reference in the mode the environment asked for (fp_mode.hpp); the
// harness itself, the GL driver included, runs in IEEE mode (ieee_scope below).
CATCH_REGISTER_LISTENER(reference_mode_listener)

namespace vplkit::parity {

namespace {

// How many distinct kernel programs this process compiled through run_kernel, and the seconds
// spent compiling them. A real GPU driver spends tens of seconds per distinct source on a cold
// shader cache, so this count, not the dispatches, sets the parity suite's time there.
struct compile_stats {
  std::size_t programs = 0;
  double seconds = 0;
};
compile_stats& stats() {
  static compile_stats s;
  return s;
}

// VPLKIT_PARITY_PROGRAM_LOG=1: one line per compiled program and a total at the end of the run.
bool program_log() {
  static const bool on = [] {
    const char* v = std::getenv("VPLKIT_PARITY_PROGRAM_LOG");
    return v != nullptr && *v != '\0' && std::strcmp(v, "0") != 0;
  }();
  return on;
}

class program_count_listener : public Catch::TestEventListenerBase {
public:
  using TestEventListenerBase::TestEventListenerBase;
  void testRunEnded(Catch::TestRunStats const& run) override {
    if (program_log()) {
      std::cout << "parity: compiled " << stats().programs << " harness programs in " << std::fixed
                << std::setprecision(2) << stats().seconds << " s" << std::endl;
    }
    TestEventListenerBase::testRunEnded(run);
  }
};

}  // namespace

}  // namespace vplkit::parity

using program_count_listener = vplkit::parity::program_count_listener;
CATCH_REGISTER_LISTENER(program_count_listener)

namespace vplkit::parity {

gl::headless_context& context() {
  // Created in IEEE mode: the driver's shader threads inherit the mode of the thread that starts
  // them, and llvmpipe must stay the IEEE device it is.
  vplkit_test::ieee_scope ieee;
  static gl::headless_context* const ctx = [] {
    auto* c = new gl::headless_context();
    std::cout << "parity: " << c->describe() << std::endl;
    return c;
  }();
  return *ctx;
}

bool software_renderer() {
  context();
  static const bool sw = gl::is_software_renderer();
  return sw;
}

const gl::program& pack_kernel(const std::string& file, const std::string& defines) {
  context();
  vplkit_test::ieee_scope ieee;
  return vplkit_test::pack_kernel(file, defines);
}

namespace {

std::map<std::string, gl::program>& program_cache() {
  static auto* cache = new std::map<std::string, gl::program>();  // lives as long as the context
  return *cache;
}

void check_call(const kernel_call& call) {
  for (unsigned l : call.local_size) {
    if (l == 0) throw std::invalid_argument("run_compute: local_size components must be >= 1");
  }
  std::istringstream lines(call.source);
  std::string line;
  while (std::getline(lines, line)) {
    const auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#version") == 0) {
      throw std::invalid_argument("run_compute: " + call.name +
                                  " has a #version line; the harness writes it (kernel_call::version)");
    }
  }
  std::vector<unsigned> bindings = {call.output_binding};
  for (const auto& o : call.more_outputs) bindings.push_back(o.binding);
  for (const auto& in : call.inputs) bindings.push_back(in.binding);
  for (std::size_t a = 0; a < bindings.size(); ++a) {
    for (std::size_t b = a + 1; b < bindings.size(); ++b) {
      if (bindings[a] == bindings[b]) {
        throw std::invalid_argument("run_compute: two buffers of " + call.name + " at binding " +
                                    std::to_string(bindings[a]));
      }
    }
  }
}

std::string buffer_declaration(const std::string& access, unsigned binding, const std::string& glsl) {
  if (glsl.empty()) return {};
  const std::string b = std::to_string(binding);
  return "layout(std430, binding = " + b + ") " + access + " buffer parity_buffer_" + b + " { " + glsl +
         "[]; };\n";
}

// The kernel text after the harness's preamble: the source, the declared buffers, main().
std::string kernel_text(const kernel_call& call) {
  std::string text = call.version + "\n" + call.source + "\n";
  for (const auto& in : call.inputs) text += buffer_declaration("readonly", in.binding, in.glsl);
  text += buffer_declaration("writeonly", call.output_binding, call.output_glsl);
  for (const auto& o : call.more_outputs) text += buffer_declaration("writeonly", o.binding, o.glsl);
  for (const auto& u : call.uniforms) {
    if (!u.glsl.empty()) text += "layout(std140, binding = " + std::to_string(u.binding) + ") uniform " + u.glsl + ";\n";
  }
  if (!call.body.empty()) {
    text += "void main() {\n  uint i = gl_GlobalInvocationID.x;\n  if (i >= VPLKIT_PARITY_COUNT) return;\n" +
            call.body + "\n}\n";
  }
  return text;
}

}  // namespace

kernel_outputs run_kernel(const kernel_call& call, std::size_t count, std::size_t out_element_size) {
  context();
  vplkit_test::ieee_scope ieee;
  check_call(call);
  if (count > 0xFFFFFFFFu) throw std::invalid_argument("run_compute: " + call.name + ": more than 2^32 - 1 items");
  // The count is a uniform, not part of the text: one program per kernel source, whatever the
  // number of items of each call (a GPU driver compiles every distinct text anew).
  const std::string preamble =
      "#define VPLKIT_PARITY_COUNT vplkit_parity_count\nuniform uint vplkit_parity_count;\n" + call.defines +
      (call.defines.empty() || call.defines.back() == '\n' ? "" : "\n") +
      "layout(local_size_x = " + std::to_string(call.local_size[0]) +
      ", local_size_y = " + std::to_string(call.local_size[1]) +
      ", local_size_z = " + std::to_string(call.local_size[2]) + ") in;\n";
  const std::string source = kernel_text(call);
  const std::string key = preamble + '\x01' + source;
  auto& cache = program_cache();
  auto it = cache.find(key);
  if (it == cache.end()) {
    const auto start = std::chrono::steady_clock::now();
    it = cache
             .emplace(key, gl::program::compute_with_includes(source, call.name,
                                                              {gl::glsl_source_dir()}, preamble))
             .first;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++stats().programs;
    stats().seconds += seconds;
    if (program_log()) {
      std::cout << "parity: compiled program " << stats().programs << " (" << call.name << ", " << std::fixed
                << std::setprecision(3) << seconds << " s)" << std::endl;
    }
  }

  // Inputs, outputs (0xFF-filled) and uniform blocks, each at its binding.
  std::vector<gl::buffer> buffers;
  std::vector<std::pair<unsigned, std::size_t>> outputs = {{call.output_binding, count * out_element_size}};
  for (const auto& o : call.more_outputs) outputs.push_back({o.binding, (o.count ? o.count : count) * o.element_size});
  buffers.reserve(call.inputs.size() + outputs.size() + call.uniforms.size());
  for (const auto& in : call.inputs) {
    buffers.push_back(gl::buffer::from_bytes(in.bytes.data(), in.bytes.size()));
    vplkit_test::bind({vplkit_test::storage_at(in.binding, buffers.back())});
  }
  const std::size_t first_output = buffers.size();
  for (const auto& o : outputs) {
    buffers.push_back(gl::buffer::filled(o.second, 0xFF));
    vplkit_test::bind({vplkit_test::storage_at(o.first, buffers.back())});
  }
  for (const auto& u : call.uniforms) {
    buffers.push_back(gl::buffer::from_bytes(u.bytes.data(), u.bytes.size()));
    vplkit_test::bind({vplkit_test::uniform_at(u.binding, buffers.back())});
  }

  std::array<unsigned, 3> groups = call.groups;
  if (groups[0] == 0 && groups[1] == 0 && groups[2] == 0) {
    groups = {gl::groups_for(count, static_cast<GLint>(call.local_size[0])), 1, 1};
  }
  // -1 where the kernel never reads the count (the compiler drops the uniform).
  const GLint count_location = it->second.uniform_location("vplkit_parity_count");
  if (count_location >= 0) {
    it->second.use();
    glUniform1ui(count_location, static_cast<GLuint>(count));
    gl::check_gl("glUniform1ui(vplkit_parity_count)");
  }
  gl::dispatch(it->second, groups[0], groups[1], groups[2]);
  kernel_outputs result;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    std::vector<unsigned char>& bytes = result.bytes[outputs[k].first];
    bytes.resize(outputs[k].second);
    buffers[first_output + k].read_bytes(bytes.data(), 0, bytes.size());
  }
  return result;
}

// ---- formatting ---------------------------------------------------------------------------------
std::string float_bound::text() const {
  std::ostringstream s;
  s << std::setprecision(3);
  std::string sep;
  if (ulps >= 0) { s << sep << "<= " << ulps << " ulps"; sep = " or "; }
  if (rel >= 0) { s << sep << "rel <= " << rel; sep = " or "; }
  if (abs >= 0) { s << sep << "abs <= " << abs; sep = " or "; }
  if (sep.empty()) s << "exact";
  return s.str();
}

namespace {

std::string title(const std::string& what) { return what.empty() ? "values" : what; }

// Vulkan "Precision and Operation of SPIR-V Instructions", ULP: where the range a bound allows
// reaches beyond the largest finite float, a device may return either the infinity of that sign or
// +-FLT_MAX. So an infinity on one side matches a finite value of the same sign on the other when
// the value's distance to FLT_MAX, counted as one more ulp for the infinity, is within the bound.
bool overflow_agrees(float g, double ref, const float_bound& bound) {
  if (std::isinf(g) == std::isinf(ref) || std::isnan(g) || std::isnan(ref)) return false;
  if ((g < 0) != (ref < 0)) return false;
  const float finite = std::isinf(g) ? static_cast<float>(ref) : g;
  if (std::isinf(finite)) return false;  // a double beyond FLT_MAX
  const float big = std::numeric_limits<float>::max();
  const double ulps = ulp_distance(std::fabs(finite), big) + 1.0;
  const double rel = (static_cast<double>(big) - std::fabs(static_cast<double>(finite))) / static_cast<double>(big);
  return (bound.ulps >= 0 && ulps <= bound.ulps) || (bound.rel >= 0 && rel <= bound.rel);
}

template <class R>
comparison compare_floats_impl(const std::vector<float>& gpu, const std::vector<R>& cpu,
                               const float_bound& bound, const describe_fn& describe,
                               const std::string& what) {
  vplkit_test::ieee_scope ieee;  // the comparison is not the reference
  comparison c;
  c.count = cpu.size();
  std::ostringstream r;
  r << "parity " << title(what) << ": " << cpu.size() << " floats, bound " << bound.text() << "\n";
  if (gpu.size() != cpu.size()) {
    r << "  FAIL: gpu gave " << gpu.size() << " values, cpu " << cpu.size() << "\n";
    c.report = r.str();
    return c;
  }
  auto input_of = [&](std::size_t i) { return describe ? "  input: " + describe(i) : std::string(); };
  std::vector<std::string> first;
  std::size_t worst_rel_index = 0;
  bool any = false;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const float g = gpu[i];
    const double ref = static_cast<double>(cpu[i]);
    const double ulps = ulp_distance(g, static_cast<float>(cpu[i]));
    const bool both_nan = std::isnan(g) && std::isnan(ref);
    const double diff = both_nan || static_cast<double>(g) == ref
                            ? 0.0
                            : std::fabs(static_cast<double>(g) - ref);
    const double rel = diff == 0.0 ? 0.0
                       : ref != 0.0 ? diff / std::fabs(ref)
                                    : std::numeric_limits<double>::infinity();
    const bool pass = diff == 0.0 || (bound.ulps >= 0 && ulps <= bound.ulps) ||
                      (bound.rel >= 0 && rel <= bound.rel) || (bound.abs >= 0 && diff <= bound.abs) ||
                      overflow_agrees(g, ref, bound);
    // NaN differences compare false everywhere above; make them the worst explicitly.
    const double ulps_key = std::isnan(diff) ? std::numeric_limits<double>::infinity() : ulps;
    if (!any || ulps_key > c.worst_ulps) {
      c.worst_index = i;
      c.worst_ulps = ulps_key;
      c.worst_abs = diff;
    }
    if (!any || rel > c.worst_rel || std::isnan(rel)) {
      worst_rel_index = i;
      c.worst_rel = std::isnan(rel) ? std::numeric_limits<double>::infinity() : rel;
    }
    any = true;
    if (!pass) {
      if (first.size() < 10) {
        std::ostringstream f;
        f << "    [" << i << "] gpu=" << show(g) << " cpu=" << show(cpu[i]) << " (" << ulps
          << " ulps, rel " << std::setprecision(3) << rel << ")" << input_of(i);
        first.push_back(f.str());
      }
      ++c.failures;
    }
  }
  c.ok = c.failures == 0;
  if (any) {
    const std::size_t w = c.worst_index;
    r << "  worst ulps: " << c.worst_ulps << " at [" << w << "] gpu=" << show(gpu[w])
      << " cpu=" << show(cpu[w]) << std::setprecision(3) << " (abs " << c.worst_abs << ")"
      << input_of(w) << "\n";
    r << "  worst rel:  " << std::setprecision(3) << c.worst_rel << " at [" << worst_rel_index
      << "] gpu=" << show(gpu[worst_rel_index]) << " cpu=" << show(cpu[worst_rel_index])
      << input_of(worst_rel_index) << "\n";
  }
  if (c.ok) {
    r << "  PASS: all " << c.count << " within the bound\n";
  } else {
    r << "  FAIL: " << c.failures << " of " << c.count << " outside the bound; first ones:\n";
    for (const auto& f : first) r << f << "\n";
  }
  c.report = r.str();
  return c;
}

}  // namespace

comparison compare_floats(const std::vector<float>& gpu, const std::vector<float>& cpu,
                          const float_bound& bound, const describe_fn& describe,
                          const std::string& what) {
  return compare_floats_impl(gpu, cpu, bound, describe, what);
}

comparison compare_floats(const std::vector<float>& gpu, const std::vector<double>& cpu,
                          const float_bound& bound, const describe_fn& describe,
                          const std::string& what) {
  return compare_floats_impl(gpu, cpu, bound, describe, what);
}

namespace {

template <class R>
comparison with_worst_abs(comparison c, const std::vector<float>& gpu, const std::vector<R>& cpu) {
  vplkit_test::ieee_scope ieee;
  double worst = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < gpu.size() && i < cpu.size(); ++i) {
    const double d = std::fabs(double(gpu[i]) - double(cpu[i]));
    if (d > worst) {
      worst = d;
      at = i;
    }
  }
  if (!gpu.empty() && gpu.size() == cpu.size()) {
    c.report += "  worst abs:  " + show(worst) + " at [" + std::to_string(at) + "] gpu=" + show(gpu[at]) +
                " cpu=" + show(cpu[at]) + "\n";
  }
  return c;
}

}  // namespace

comparison compare_floats_abs(const std::vector<float>& gpu, const std::vector<float>& cpu,
                              const float_bound& bound, const describe_fn& describe, const std::string& what) {
  return with_worst_abs(compare_floats(gpu, cpu, bound, describe, what), gpu, cpu);
}

comparison compare_floats_abs(const std::vector<float>& gpu, const std::vector<double>& cpu,
                              const float_bound& bound, const describe_fn& describe, const std::string& what) {
  return with_worst_abs(compare_floats(gpu, cpu, bound, describe, what), gpu, cpu);
}

comparison compare_constants(const std::string& source, const std::vector<glsl_constant>& constants,
                             const std::string& what) {
  kernel_call call;
  call.source = source;
  call.local_size = {1, 1, 1};
  call.output_glsl = "uint result";
  std::vector<std::uint32_t> cpu;
  for (std::size_t k = 0; k < constants.size(); ++k) {
    call.body += "  if (i == 0u) result[" + std::to_string(k) + "] = " + constants[k].glsl + ";\n";
    cpu.push_back(constants[k].cpu);
  }
  const auto gpu = run_compute<std::uint32_t>(call, constants.size());
  return compare_exact(gpu, cpu, [&](std::size_t k) { return constants[k].glsl; }, what);
}

namespace detail {
std::string exact_report(const std::string& what, std::size_t count, std::size_t failures,
                         const std::vector<std::string>& first_failures, bool size_mismatch,
                         std::size_t gpu_size, std::size_t cpu_size) {
  std::ostringstream r;
  r << "parity " << title(what) << ": " << count << " integers, exact\n";
  if (size_mismatch) {
    r << "  FAIL: gpu gave " << gpu_size << " values, cpu " << cpu_size << "\n";
  } else if (failures == 0) {
    r << "  PASS: all " << count << " equal\n";
  } else {
    r << "  FAIL: " << failures << " of " << count << " differ; first ones:\n";
    for (const auto& f : first_failures) r << "    " << f << "\n";
  }
  return r.str();
}
}  // namespace detail

}  // namespace vplkit::parity
