#include "io/atomic_file.hpp"

#include "io/errors.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace vplrender {

namespace {

std::atomic<unsigned> counter{0};

std::string make_temp_name(const std::string& final_path, unsigned n) {
  const std::filesystem::path p(final_path);
  const std::string name = "." + p.filename().string() + "." + std::to_string(::getpid()) + "." + std::to_string(n) + ".tmp";
  return (p.parent_path() / name).string();
}

}  // namespace

std::string temporary_name_for(const std::string& final_path) { return make_temp_name(final_path, counter.load()); }

void write_atomically(const std::string& final_path, const std::function<void(const std::string&)>& write) {
  if (final_path.empty()) throw output_error("empty output path");
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = make_temp_name(final_path, counter++);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) throw output_error(final_path + ": cannot create a temporary file beside it (" + std::strerror(errno) + ")");
  ::close(fd);

  auto discard = [&]() { ::unlink(temp.c_str()); };
  try {
    write(temp);
  } catch (...) {
    discard();
    throw;
  }
  // Flush to disk before the rename, or a crash could leave a complete name over empty data.
  fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    discard();
    throw output_error(final_path + ": temporary file vanished while writing (" + std::strerror(e) + ")");
  }
  struct stat st {};
  const bool empty = ::fstat(fd, &st) == 0 && st.st_size == 0;
  ::fsync(fd);
  ::close(fd);
  if (empty) {
    discard();
    throw output_error(final_path + ": the writer produced an empty file");
  }
  if (std::rename(temp.c_str(), final_path.c_str()) != 0) {
    const int e = errno;
    discard();
    throw output_error(final_path + ": cannot rename the temporary file into place (" + std::strerror(e) + ")");
  }
}

}  // namespace vplrender
