#include <parity_harness.hpp>
#include <random>
#include <cmath>
TEST_CASE("scratch") {
  std::mt19937 g(1);
  std::vector<float> in;
  for (int i = 0; i < 100000; ++i) { float x = float(g() % 1000000) / 1e6f, y = float(g() % 1000000) / 1e6f; in.push_back(x); in.push_back(y); }
  const char* exprs[] = {"float q = 1.0 + dot(vec2(x,y), vec2(x,y)); return 4.0 / (q * q);", "float q = 1.0 + (x*x + y*y); return 4.0 / (q * q);", "float q = 1.0 + dot(vec2(x,y), vec2(x,y)); return q * q;", "return dot(vec2(x,y), vec2(x,y));", "float q = 1.0 + dot(vec2(x,y), vec2(x,y)); return 1.0 / q;", "float q = 1.0 + (x*x + y*y); return 4.0 / q;", "float q = 1.0 + (x*x + y*y); float w = q * q; return 4.0 / w;"};
  for (const char* e : exprs) {
    std::string body = std::string(e).find("return") != std::string::npos ? e : std::string("return ") + e + ";";
    const std::string k = "layout(std430, binding = 0) readonly buffer In { vec2 q[]; };\nlayout(std430, binding = 1) writeonly buffer Out { float r[]; };\nfloat f(float x, float y) { " + body + " }\nvoid main() { uint i = gl_GlobalInvocationID.x; if (i >= VPLKIT_PARITY_COUNT) return; r[i] = f(q[i].x, q[i].y); }";
    auto gpu = vplkit::parity::run_compute<float>(k, {64,1,1}, {vplkit::parity::input(0, in)}, 1, 100000);
    std::vector<double> c;
    for (int i = 0; i < 100000; ++i) { float x = in[2*i], y = in[2*i+1]; double v = 0; std::string s = e;
      if (s == "1.0 / sqrt(x)" || s == "inversesqrt(x)") v = 1.0 / std::sqrt(double(x));
      else if (s == "4.0 / (x * x)") v = 4.0 / double(x * x);
      else if (s == "y / (x * x)") v = double(y) / double(x * x);
      else if (s == "1.0 / (x * x)") v = 1.0 / double(x * x);
      else if (s == "x / sqrt(y)") v = double(x) / std::sqrt(double(y));
      else if (s.find("return q * q") != std::string::npos) { float q = 1.0f + (x*x + y*y); v = double(q) * double(q); }
      else if (s.find("return dot") != std::string::npos) { v = double(x)*x + double(y)*y; }
      else if (s.find("1.0 / q") != std::string::npos) { float q = 1.0f + (x*x + y*y); v = 1.0 / double(q); }
      else if (s.find("4.0 / q;") != std::string::npos) { float q = 1.0f + (x*x + y*y); v = 4.0 / double(q); }
      else { float q = 1.0f + (x*x + y*y); v = 4.0 / double(q * q); }
      c.push_back(v); }
    VPLKIT_CHECK_PARITY(vplkit::parity::compare_floats(gpu, c, vplkit::parity::within_ulps(0.5), {}, e));
  }
}
