#include <parity_distribution_support.hpp>
using namespace vplkit::parity::dist;
TEST_CASE("scratch build") {
  for (bool ff : {false, true}) {
    for (u32 n : {1u, 2u, 5u, 1023u, 1024u, 1025u, 100000u, (1u << 20) + 3u}) {
     for (int kind = 0; kind < 4; ++kind) {
      auto w = kind == 0 ? random_weights(n, 7) : kind == 1 ? zero_run_weights(n, n / 10, 3) : kind == 2 ? log_uniform_weights(n, -30, 30, 5) : exponential_weights(n, 9);
      build_options o; o.float_float = ff; if (kind == 3) o.max_groups = 3;
      auto r = gpu_build(w, n, 1, o);
      vplkit::discrete_cdf<float> c(w);
      auto inv = check_invariants(r.cdf.data(), r.guide.data(), w.data(), n, c.empty());
      auto d = compare_cdfs(r.cdf.data(), c.cdf().data(), n);
      auto ex = near_exact_cdf(w.data(), n);
      auto de = compare_cdfs(r.cdf.data(), ex.data(), n);
      auto dc = compare_cdfs(c.cdf().data(), ex.data(), n);
      std::cout << o.text() << " kind " << kind << " n=" << n << " " << r.ms << " ms total " << r.info[0].total << " vs " << c.total() << " inv[" << inv << "]\n  vs cpu: " << describe(d) << "\n  gpu vs exact: " << describe(de) << "\n  cpu vs exact: " << describe(dc) << "\n";
    }}
  }
}
