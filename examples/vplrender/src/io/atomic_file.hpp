// SPDX-License-Identifier: MIT
#pragma once
// One output written atomically: a set of one (io/output_set.hpp). A failure at any point removes
// the temporary file and leaves any previous file of that name untouched.
#include "io/output_set.hpp"

#include <functional>
#include <string>

namespace vplrender {

// Reserves a temporary beside `final_path`, calls write(temp_path), flushes it to disk and renames
// it over `final_path`. Exceptions from `write` propagate after the clean-up; other failures throw
// output_error naming the path and the reason.
void write_atomically(const std::string& final_path, const std::function<void(const std::string& temp_path)>& write);

// The bytes to `path` with write(2), every error checked: ENOSPC reads "<shown_as>: no space left on
// device (writing N bytes)", others "<shown_as>: cannot write (<strerror>)". Throws output_error.
void write_file_bytes(const std::string& path, const std::string& shown_as, const void* data, std::size_t bytes);

}  // namespace vplrender
