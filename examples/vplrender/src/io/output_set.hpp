// SPDX-License-Identifier: MIT
#pragma once
// The outputs of one run (EXR, PNG preview, JSON report) published as a set: each file is written
// to a temporary beside its final name, and only when every one of them is complete are they
// renamed into place, one rename after the other with nothing in between. A failure before that
// (a writer throws, the disk is full) removes the temporaries and leaves the previous run's files
// untouched; so does SIGINT/SIGTERM (the temporaries are registered with cleanup_on_signal). A
// rename that fails half way puts the files already renamed back (hard-linked copies of the old
// ones are kept until publish() returns).
#include <functional>
#include <string>
#include <vector>

namespace vplrender {

class output_set {
public:
  output_set() = default;
  ~output_set();  // removes whatever was not published
  output_set(const output_set&) = delete;
  output_set& operator=(const output_set&) = delete;

  // Creates the temporary ".<name>.<pid>.<n>.tmp" beside `final_path` now (O_EXCL, mode 0666 less
  // the umask), so a directory that refuses files fails before a long render. Throws output_error.
  void reserve(const std::string& final_path);
  // Calls write(temp_path) for a reserved path (reserving it first if needed), then checks the
  // file is not empty and flushes it to disk. Exceptions from `write` propagate after the
  // clean-up of the whole set; other failures throw output_error naming the path.
  void write(const std::string& final_path, const std::function<void(const std::string& temp_path)>& write);
  // Renames every written temporary over its final name. Throws output_error (and restores the
  // previous files) when a path was reserved but never written or a rename fails.
  void publish();

  // The temporary names currently held (for tests).
  std::vector<std::string> temporaries() const;

private:
  struct entry {
    std::string final_path, temp_path;
    int cleanup_slot = 0;
    bool written = false;
  };
  entry& find_or_reserve(const std::string& final_path);
  void discard_all() noexcept;
  std::vector<entry> entries_;
};

// The temporary name the next reserve() of `final_path` would try (exposed for tests).
std::string temporary_name_for(const std::string& final_path);

}  // namespace vplrender
