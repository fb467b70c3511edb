// SPDX-License-Identifier: MIT
#include "io/atomic_file.hpp"

#include "io/errors.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

namespace vplrender {

void write_atomically(const std::string& final_path, const std::function<void(const std::string&)>& write) {
  output_set set;
  set.write(final_path, write);
  set.publish();
}

void write_file_bytes(const std::string& path, const std::string& shown_as, const void* data, std::size_t bytes) {
  auto fail = [&](int err) {
    if (err == ENOSPC || err == EDQUOT)
      throw output_error(shown_as + ": no space left on device (writing " + std::to_string(bytes) + " bytes)");
    throw output_error(shown_as + ": cannot write (" + std::strerror(err) + ")");
  };
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno);
  const char* p = static_cast<const char*>(data);
  std::size_t left = bytes;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;  // a write of 0 bytes to a regular file: the disk is full
      ::close(fd);
      fail(err);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail(errno);
}

}  // namespace vplrender
