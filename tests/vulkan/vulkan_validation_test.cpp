// SPDX-License-Identifier: MIT
// The validation plumbing itself: every other Vulkan test case passes only if no message arrives,
// which would also be the case if the layer were not running. Here a host declares a layout that
// does not match the kernel (the uniform block declared as a storage buffer, the mistake the old
// shared default bindings forced on Vulkan hosts); the layer must report it through the messenger.
#include "vulkan_test_support.hpp"

#include <vplkit/image/median_fill_params.h>

#include <string>

using namespace vplkit::vk_test;

TEST_CASE("the validation layer reports a descriptor layout that does not match the kernel") {
  validation_log log;
  {
    context ctx(log);
    REQUIRE(log.messages.empty());
    try {
      const kernel k(ctx, "median_fill",
                     {{VPLKIT_MEDIAN_FILL_BINDING_IN, slot_kind::storage},
                      {VPLKIT_MEDIAN_FILL_BINDING_OUT, slot_kind::storage},
                      {VPLKIT_MEDIAN_FILL_BINDING_PARAMS, slot_kind::storage}});
    } catch (const vk_error& e) {
      std::cout << "  the driver refused the pipeline as well: " << e.what() << "\n";
    }
  }
  bool mismatch = false;
  for (const std::string& m : log.messages) mismatch |= m.find("VUID-VkComputePipelineCreateInfo-layout-") != std::string::npos;
  std::cout << "  " << log.messages.size() << " validation message(s), layout mismatch reported: " << mismatch << "\n";
  CHECK(mismatch);
}
