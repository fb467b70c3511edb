#pragma once
// Every output goes to a temporary file in the destination's own directory (so rename(2) stays on
// one file system and is atomic) and is renamed into place only once complete. A failure at any
// point removes the temporary file and leaves any previous file of that name untouched.
#include <functional>
#include <string>

namespace vplrender {

// Reserves a fresh temporary name ".<name>.<pid>.<n>.tmp" beside `final_path` (O_EXCL, mode 0666
// less the umask), calls write(temp_path), flushes it to disk and renames it over `final_path`.
// Exceptions from `write` propagate after the clean-up; other failures throw output_error naming
// the path and the reason.
void write_atomically(const std::string& final_path, const std::function<void(const std::string& temp_path)>& write);

// The temporary name write_atomically would use next (exposed for tests).
std::string temporary_name_for(const std::string& final_path);

}  // namespace vplrender
