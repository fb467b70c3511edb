// SPDX-License-Identifier: MIT
#include "io/text_file.hpp"

#include "io/errors.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace vplrender {

namespace {

std::string kind_problem(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "is a directory, not a file";
  const char* kind = S_ISFIFO(st.st_mode) ? "a named pipe"
                     : S_ISCHR(st.st_mode) ? "a character device"
                     : S_ISBLK(st.st_mode) ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a file";
  return std::string("is not a regular file (") + kind + ")";
}

struct fd_closer {
  int fd;
  ~fd_closer() { ::close(fd); }
};

}  // namespace

bool is_regular_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string file_problem(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return errno == ENOENT ? "does not exist" : std::string("cannot be examined (") + std::strerror(errno) + ")";
  return kind_problem(st);
}

std::string read_file_bytes(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw input_error(path + ": cannot open (" + std::strerror(errno) + ")");
  if (const std::string p = kind_problem(st); !p.empty()) throw input_error(path + ": " + p);
  // O_NONBLOCK: should the path have become a FIFO since the stat, the open returns at once
  // instead of waiting for a writer, and the fstat below refuses it. (No effect on regular files.)
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw input_error(path + ": cannot open (" + std::strerror(errno) + ")");
  const fd_closer closer{fd};
  if (::fstat(fd, &st) != 0) throw input_error(path + ": cannot open (" + std::strerror(errno) + ")");
  if (const std::string p = kind_problem(st); !p.empty()) throw input_error(path + ": " + p);
  std::string data;
  data.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw input_error(path + ": read error (" + std::strerror(errno) + ")");
    }
    if (got == 0) break;
    data.append(buf, static_cast<std::size_t>(got));
  }
  return data;
}

}  // namespace vplrender
