#include "io/json_file.hpp"

#include "io/atomic_file.hpp"
#include "io/errors.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace vplrender {

void write_json(const std::string& path, const nlohmann::json& j) {
  // error_handler replace: a file name that is not valid UTF-8 must not make dump() throw.
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  write_atomically(path, [&](const std::string& temp) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(temp.c_str(), "wb"), std::fclose);
    if (!f) throw output_error(path + ": cannot write (" + std::strerror(errno) + ")");
    if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size() || std::fflush(f.get()) != 0)
      throw output_error(path + ": write failed (" + std::strerror(errno) + ")");
  });
}

}  // namespace vplrender
