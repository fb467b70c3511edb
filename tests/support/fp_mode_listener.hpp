// SPDX-License-Identifier: MIT
#pragma once
// The Catch2 listener that runs every test case of a parity or Vulkan test program in the
// reference's floating-point mode (fp_mode.hpp): FTZ|DAZ when VPLKIT_PARITY_FTZ_DAZ=1, else IEEE as
// the process started. Include it from one translation unit per program, after defining
// CATCH_CONFIG_EXTERNAL_INTERFACES and before any other include of catch.hpp, then write
// CATCH_REGISTER_LISTENER(reference_mode_listener) once at global scope (the macro pastes the name
// into an identifier, so the header also declares it there).
#include <fp_mode.hpp>

#include <catch2/catch.hpp>

#include <memory>

namespace vplkit_test {

class reference_mode_listener : public Catch::TestEventListenerBase {
public:
  using TestEventListenerBase::TestEventListenerBase;

  void testCaseStarting(Catch::TestCaseInfo const& info) override {
    TestEventListenerBase::testCaseStarting(info);
    scope_ = std::make_unique<reference_scope>();
  }

  void testCaseEnded(Catch::TestCaseStats const& stats) override {
    scope_.reset();
    TestEventListenerBase::testCaseEnded(stats);
  }

private:
  std::unique_ptr<reference_scope> scope_;
};

}  // namespace vplkit_test

using reference_mode_listener = vplkit_test::reference_mode_listener;
