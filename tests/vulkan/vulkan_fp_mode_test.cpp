// SPDX-License-Identifier: MIT
// The floating-point mode of the C++ references in vulkan_kernels_test (tests/support/fp_mode.hpp):
// every test case runs with FTZ|DAZ when VPLKIT_PARITY_FTZ_DAZ=1 (ctest registers that variant as
// vulkan_kernels_test[ftz-daz]), the Vulkan harness in IEEE mode around the driver.
#define CATCH_CONFIG_EXTERNAL_INTERFACES
#include <fp_mode_listener.hpp>

#include <limits>

CATCH_REGISTER_LISTENER(reference_mode_listener)

TEST_CASE("reference mode: FTZ|DAZ exactly when VPLKIT_PARITY_FTZ_DAZ=1, IEEE inside ieee_scope") {
  const bool requested = vplkit_test::reference_ftz_daz_requested();
  CHECK(vplkit_test::ftz_daz_active() == requested);
  volatile float tiny = std::numeric_limits<float>::min();
  volatile float half = 0.5f;
  const float product = tiny * half;  // a denormal, or 0 under FTZ
  CHECK((product == 0.0f) == requested);
  {
    vplkit_test::ieee_scope ieee;
    CHECK_FALSE(vplkit_test::ftz_daz_active());
    const float kept = tiny * half;
    CHECK(kept > 0.0f);
  }
  CHECK(vplkit_test::ftz_daz_active() == requested);
}
