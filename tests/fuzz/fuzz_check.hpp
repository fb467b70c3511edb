// SPDX-License-Identifier: MIT
#pragma once
// What the harnesses share: a contract check that crashes (libFuzzer then saves the input), a
// reader that turns the fuzzer's bytes into values, and a private folder for the files they write.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

// Not assert(): it must hold in every build type, and it says which contract broke.
#define VPLKIT_FUZZ_CHECK(cond)                                                                 \
  do {                                                                                          \
    if (!(cond)) {                                                                              \
      std::fprintf(stderr, "contract violated: %s (%s:%d)\n", #cond, __FILE__, __LINE__);     \
      std::abort();                                                                             \
    }                                                                                           \
  } while (0)

namespace vplkit_fuzz {

// Consumes the input front to back; past the end every value reads as zero.
class byte_reader {
public:
  byte_reader(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  template <class T>
  T get() {
    T out{};
    const std::size_t k = n_ < sizeof(T) ? n_ : sizeof(T);
    std::memcpy(&out, p_, k);
    p_ += k;
    n_ -= k;
    return out;
  }
  std::size_t left() const { return n_; }

private:
  const std::uint8_t* p_;
  std::size_t n_;
};

// A new folder under the system's temporary directory, e.g. make_temp_dir("vplkit_fuzz_obj").
inline std::filesystem::path make_temp_dir(const std::string& stem) {
  std::string tmpl = (std::filesystem::temp_directory_path() / (stem + "_XXXXXX")).string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) std::abort();
  return std::filesystem::path(buf.data());
}

inline void write_file(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << bytes;
}

}  // namespace vplkit_fuzz
