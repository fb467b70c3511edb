#include <parity_harness.hpp>
#include <epoxy/gl.h>
#include <chrono>
TEST_CASE("fp64 probe") {
  vplkit::parity::context();
  GLint n = 0; glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) { std::string e = (const char*)glGetStringi(GL_EXTENSIONS, i); if (e.find("fp64") != std::string::npos || e.find("int64")!=std::string::npos) std::cout << e << "\n"; }
  std::vector<float> u(1 << 20); for (size_t i = 0; i < u.size(); ++i) u[i] = float(i) * 1e-3f;
  for (int dbl = 0; dbl < 2; ++dbl) {
  std::string k = dbl ? R"(
layout(std430, binding = 0) readonly buffer In { float u[]; };
layout(std430, binding = 1) writeonly buffer Out { float r[]; };
void main() { uint i = gl_GlobalInvocationID.x; if (i >= VPLKIT_PARITY_COUNT) return;
  double a = double(u[i]); double s = 0.0; for (int k = 0; k < 64; ++k) s = s * 0.999 + a; r[i] = float(s / double(u[i] + 1.0)); })" : R"(
layout(std430, binding = 0) readonly buffer In { float u[]; };
layout(std430, binding = 1) writeonly buffer Out { float r[]; };
void main() { uint i = gl_GlobalInvocationID.x; if (i >= VPLKIT_PARITY_COUNT) return;
  float a = u[i]; float s = 0.0; for (int k = 0; k < 64; ++k) s = s * 0.999 + a; r[i] = s / (u[i] + 1.0); })";
  for (int rep = 0; rep < 3; ++rep) {
  auto t0 = std::chrono::steady_clock::now();
  auto r = vplkit::parity::run_compute<float>(k, {256,1,1}, {vplkit::parity::input(0,u)}, 1, u.size());
  auto t1 = std::chrono::steady_clock::now();
  std::cout << (dbl ? "double " : "float ") << std::chrono::duration<double,std::milli>(t1-t0).count() << " ms r[5]=" << r[5] << "\n";
  }}
}
