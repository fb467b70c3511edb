// SPDX-License-Identifier: MIT
#include "io/output_set.hpp"

#include "io/cleanup_on_signal.hpp"
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

std::string make_temp_name(const std::string& final_path, const std::string& kind, unsigned n) {
  const std::filesystem::path p(final_path);
  const std::string name =
      "." + p.filename().string() + "." + std::to_string(::getpid()) + "." + kind + std::to_string(n) + ".tmp";
  return (p.parent_path() / name).string();
}

struct temp_file {
  std::string path;
  cleanup_slot slot = 0;
};

// A fresh name beside `final_path`, created with O_EXCL (or hard-linked to `link_from`). The name
// is registered for clean-up on a signal before the file exists, so no signal can leave it behind
// (the pid in the name keeps it ours).
temp_file create_beside(const std::string& final_path, const char* kind, const std::string& link_from = {}) {
  int err = 0;
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp_file t;
    t.path = make_temp_name(final_path, kind, counter++);
    t.slot = register_for_cleanup(t.path);
    int rc;
    if (link_from.empty()) {
      rc = ::open(t.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (rc >= 0) ::close(rc);
    } else {
      rc = ::link(link_from.c_str(), t.path.c_str());
    }
    if (rc >= 0) return t;
    err = errno;
    unregister_cleanup(t.slot);
    if (err != EEXIST) break;
  }
  throw output_error(final_path + ": cannot create a temporary file beside it (" + std::strerror(err) + ")");
}

}  // namespace

std::string temporary_name_for(const std::string& final_path) { return make_temp_name(final_path, "", counter.load()); }

output_set::~output_set() { discard_all(); }

void output_set::discard_all() noexcept {
  for (entry& e : entries_) {
    ::unlink(e.temp_path.c_str());
    unregister_cleanup(e.cleanup_slot);
  }
  entries_.clear();
}

output_set::entry& output_set::find_or_reserve(const std::string& final_path) {
  for (entry& e : entries_)
    if (e.final_path == final_path) return e;
  reserve(final_path);
  return entries_.back();
}

void output_set::reserve(const std::string& final_path) {
  if (final_path.empty()) throw output_error("empty output path");
  for (const entry& e : entries_)
    if (e.final_path == final_path) return;
  install_cleanup_on_signal();
  entry e;
  e.final_path = final_path;
  const temp_file t = create_beside(final_path, "");
  e.temp_path = t.path;
  e.cleanup_slot = t.slot;
  entries_.push_back(std::move(e));
}

void output_set::write(const std::string& final_path, const std::function<void(const std::string&)>& write) {
  entry* e = &find_or_reserve(final_path);
  try {
    write(e->temp_path);
  } catch (...) {
    discard_all();
    throw;
  }
  // Flush to disk before the rename, or a crash could leave a complete name over empty data.
  const int fd = ::open(e->temp_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    discard_all();
    throw output_error(final_path + ": temporary file vanished while writing (" + std::strerror(err) + ")");
  }
  struct stat st {};
  const bool empty = ::fstat(fd, &st) == 0 && st.st_size == 0;
  const int sync_rc = ::fsync(fd);
  const int sync_err = errno;
  ::close(fd);
  if (empty) {
    discard_all();
    throw output_error(final_path + ": the writer produced an empty file");
  }
  if (sync_rc != 0 && sync_err != EINVAL && sync_err != EROFS) {
    discard_all();
    throw output_error(final_path + (sync_err == ENOSPC ? ": no space left on device (flushing to disk)"
                                                        : ": cannot flush to disk (" + std::string(std::strerror(sync_err)) + ")"));
  }
  e->written = true;
}

void output_set::publish() {
  for (const entry& e : entries_)
    if (!e.written) {
      const std::string path = e.final_path;
      discard_all();
      throw output_error(path + ": reserved as an output but never written");
    }
  // Hard links to the files being replaced, so a rename failing half way can put them back.
  std::vector<temp_file> backups(entries_.size());
  std::vector<bool> had_previous(entries_.size(), false);
  auto drop_backups = [&]() {
    for (const temp_file& b : backups)
      if (!b.path.empty()) {
        ::unlink(b.path.c_str());
        unregister_cleanup(b.slot);
      }
  };
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    struct stat st {};
    if (::lstat(entries_[i].final_path.c_str(), &st) != 0) continue;  // nothing to keep
    had_previous[i] = true;
    try {
      backups[i] = create_beside(entries_[i].final_path, "old", entries_[i].final_path);
    } catch (const output_error&) {
      // No hard links here (some file systems): publish without the safety net for this file.
    }
  }
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (std::rename(entries_[i].temp_path.c_str(), entries_[i].final_path.c_str()) == 0) continue;
    const int err = errno;
    // Undo the renames done so far: the previous file back, or no file where there was none.
    for (std::size_t k = 0; k < i; ++k) {
      if (!backups[k].path.empty())
        std::rename(backups[k].path.c_str(), entries_[k].final_path.c_str());
      else if (!had_previous[k])
        ::unlink(entries_[k].final_path.c_str());
    }
    const std::string path = entries_[i].final_path;
    drop_backups();
    discard_all();
    throw output_error(path + ": cannot rename the temporary file into place (" + std::strerror(err) + ")");
  }
  drop_backups();
  for (entry& e : entries_) unregister_cleanup(e.cleanup_slot);
  entries_.clear();
}

std::vector<std::string> output_set::temporaries() const {
  std::vector<std::string> out;
  for (const entry& e : entries_) out.push_back(e.temp_path);
  return out;
}

}  // namespace vplrender
