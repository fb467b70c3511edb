#include "parity_harness.hpp"

#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

namespace vplkit::parity {

gl::headless_context& context() {
  static gl::headless_context* const ctx = [] {
    auto* c = new gl::headless_context();
    std::cout << "parity: " << c->describe() << std::endl;
    return c;
  }();
  return *ctx;
}

namespace {

std::map<std::string, gl::program>& program_cache() {
  static auto* cache = new std::map<std::string, gl::program>();  // lives as long as the context
  return *cache;
}

}  // namespace

std::vector<unsigned char> run_compute_bytes(const kernel_call& call, std::size_t count,
                                             std::size_t out_bytes) {
  context();
  for (unsigned l : call.local_size) {
    if (l == 0) throw std::invalid_argument("run_compute: local_size components must be >= 1");
  }
  {
    std::istringstream lines(call.source);
    std::string line;
    while (std::getline(lines, line)) {
      const auto first = line.find_first_not_of(" \t");
      if (first != std::string::npos && line.compare(first, 8, "#version") == 0) {
        throw std::invalid_argument("run_compute: " + call.name +
                                    " has a #version line; the harness writes it (kernel_call::version)");
      }
    }
  }
  for (std::size_t a = 0; a < call.inputs.size(); ++a) {
    if (call.inputs[a].binding == call.output_binding) {
      throw std::invalid_argument("run_compute: input binding " +
                                  std::to_string(call.inputs[a].binding) +
                                  " is also the output binding");
    }
    for (std::size_t b = a + 1; b < call.inputs.size(); ++b) {
      if (call.inputs[a].binding == call.inputs[b].binding) {
        throw std::invalid_argument("run_compute: two inputs at binding " +
                                    std::to_string(call.inputs[a].binding));
      }
    }
  }

  const std::string preamble =
      "#define VPLKIT_PARITY_COUNT " + std::to_string(count) + "u\n" + call.defines +
      (call.defines.empty() || call.defines.back() == '\n' ? "" : "\n") +
      "layout(local_size_x = " + std::to_string(call.local_size[0]) +
      ", local_size_y = " + std::to_string(call.local_size[1]) +
      ", local_size_z = " + std::to_string(call.local_size[2]) + ") in;\n";
  const std::string source = call.version + "\n" + call.source;
  const std::string key = preamble + '\x01' + source;
  auto& cache = program_cache();
  auto it = cache.find(key);
  if (it == cache.end()) {
    it = cache
             .emplace(key, gl::program::compute_with_includes(source, call.name,
                                                              {gl::glsl_source_dir()}, preamble))
             .first;
  }
  const gl::program& prog = it->second;

  std::vector<gl::buffer> inputs;
  inputs.reserve(call.inputs.size());
  for (const auto& in : call.inputs) {
    inputs.push_back(gl::buffer::from_bytes(in.bytes.data(), in.bytes.size()));
    inputs.back().bind(in.binding);
  }
  gl::buffer out = gl::buffer::filled(out_bytes, 0xFF);
  out.bind(call.output_binding);

  std::array<unsigned, 3> groups = call.groups;
  if (groups[0] == 0 && groups[1] == 0 && groups[2] == 0) {
    groups = {gl::groups_for(count, static_cast<GLint>(call.local_size[0])), 1, 1};
  }
  gl::dispatch(prog, groups[0], groups[1], groups[2]);
  std::vector<unsigned char> bytes(out_bytes);
  out.read_bytes(bytes.data(), 0, out_bytes);
  return bytes;
}

// ---- formatting ---------------------------------------------------------------------------------
std::string show(float v) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  std::ostringstream s;
  s << std::setprecision(9) << v << " (0x" << std::hex << std::setw(8) << std::setfill('0') << bits
    << ")";
  return s.str();
}

std::string show(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

std::string show(std::int64_t v) { return std::to_string(v); }
std::string show(std::uint64_t v) { return std::to_string(v); }

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

double ulp_distance(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) {
    return std::isnan(a) && std::isnan(b) ? 0.0 : std::numeric_limits<double>::infinity();
  }
  if (std::isinf(a) || std::isinf(b)) {
    return a == b ? 0.0 : std::numeric_limits<double>::infinity();
  }
  // Map the sign-magnitude bit patterns onto one line of integers: adjacent floats are 1 apart
  // and +0 / -0 coincide.
  auto ordered = [](float f) {
    std::uint32_t u = 0;
    std::memcpy(&u, &f, sizeof u);
    const std::int64_t magnitude = static_cast<std::int64_t>(u & 0x7fffffffu);
    return (u >> 31) != 0 ? -magnitude : magnitude;
  };
  return std::fabs(static_cast<double>(ordered(a) - ordered(b)));
}

namespace {

std::string title(const std::string& what) { return what.empty() ? "values" : what; }

template <class R>
comparison compare_floats_impl(const std::vector<float>& gpu, const std::vector<R>& cpu,
                               const float_bound& bound, const describe_fn& describe,
                               const std::string& what) {
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
                      (bound.rel >= 0 && rel <= bound.rel) || (bound.abs >= 0 && diff <= bound.abs);
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
