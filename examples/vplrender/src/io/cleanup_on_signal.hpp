// SPDX-License-Identifier: MIT
#pragma once
// Temporary files that must not outlive the process when it is interrupted: SIGINT or SIGTERM
// unlinks every registered path and then dies of the same signal (so the caller still sees
// "killed by SIGTERM"). The handler uses only async-signal-safe calls (unlink, signal, raise) on
// a fixed table filled before the paths can exist on disk.
#include <string>

namespace vplrender {

// Installs the handler for SIGINT and SIGTERM (idempotent). Call it once in main.
void install_cleanup_on_signal();

// A slot in the table; 0 when the table is full (the path is then not cleaned on a signal; the
// normal clean-up of output_set still removes it).
using cleanup_slot = int;
cleanup_slot register_for_cleanup(const std::string& path);
void unregister_cleanup(cleanup_slot slot);

}  // namespace vplrender
