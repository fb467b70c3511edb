// SPDX-License-Identifier: MIT
// The outputs of a run as one set (io/output_set.hpp): EXR, PNG and JSON go to temporaries and are
// renamed into place together; a failure at any point (a writer, a full disk, a rename half way)
// leaves the previous run's three files as they were and no temporary behind. The SIGTERM case runs
// the executable (renderer_cli_sigterm_cleans_up, sigterm_cleans_up.sh).
#include <catch2/catch.hpp>

#include "io/atomic_file.hpp"
#include "io/errors.hpp"
#include "io/exr_io.hpp"
#include "io/json_file.hpp"
#include "io/output_set.hpp"
#include "io/png_preview.hpp"
#include "io/text_file.hpp"
#include "renderer_test_util.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

using namespace vplrender;
using vplrender_test::temp_dir;

namespace {

image_rgb small_image() {
  image_rgb img(4, 3);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.1f * float(i % 7);
  return img;
}

std::vector<std::string> sorted_entries(const temp_dir& d) {
  std::vector<std::string> e = d.entries();
  std::sort(e.begin(), e.end());
  return e;
}

struct previous_run {
  std::string exr, png, json;
};
previous_run write_previous(const temp_dir& d) {
  return {d.write("out.exr", "old exr"), d.write("out.png", "old png"), d.write("out.json", "old json")};
}
void check_previous_intact(const temp_dir& d, const previous_run& p) {
  CHECK(read_file_bytes(p.exr) == "old exr");
  CHECK(read_file_bytes(p.png) == "old png");
  CHECK(read_file_bytes(p.json) == "old json");
  CHECK(sorted_entries(d) == std::vector<std::string>{"out.exr", "out.json", "out.png"});
}

}  // namespace

TEST_CASE("a set is published only when all of it is written") {
  temp_dir d;
  const previous_run p = write_previous(d);
  {
    output_set set;
    for (const std::string& f : {p.exr, p.png, p.json}) set.reserve(f);
    CHECK(set.temporaries().size() == 3);
    CHECK(d.entries().size() == 6);  // the temporaries exist from reserve() on
    write_exr(set, p.exr, small_image());
    write_png_preview(set, p.png, small_image());
    write_json(set, p.json, nlohmann::json{{"run", 2}});
    // Nothing published yet ...
    CHECK(read_file_bytes(p.exr) == "old exr");
    CHECK(read_file_bytes(p.png) == "old png");
    CHECK(read_file_bytes(p.json) == "old json");
    CHECK(d.entries().size() == 6);
    set.publish();
  }
  // ... then all three at once, and no temporary left.
  CHECK(sorted_entries(d) == std::vector<std::string>{"out.exr", "out.json", "out.png"});
  CHECK(read_exr(p.exr).width == 4);
  CHECK(read_file_bytes(p.png).substr(1, 3) == "PNG");
  CHECK(nlohmann::json::parse(read_file_bytes(p.json))["run"] == 2);
}

TEST_CASE("a PNG that cannot be written (disk full) keeps the previous set and no temporary") {
  temp_dir d;
  const previous_run p = write_previous(d);
  output_set set;
  for (const std::string& f : {p.exr, p.png, p.json}) set.reserve(f);
  write_exr(set, p.exr, small_image());
  // The PNG's bytes meet a full disk (/dev/full answers every write with ENOSPC).
  REQUIRE(::access("/dev/full", W_OK) == 0);
  CHECK_THROWS_WITH(set.write(p.png,
                              [&](const std::string&) {
                                const std::string bytes(1000, 'x');
                                write_file_bytes("/dev/full", p.png, bytes.data(), bytes.size());
                              }),
                    p.png + ": no space left on device (writing 1000 bytes)");
  check_previous_intact(d, p);
  CHECK(set.temporaries().empty());
}

TEST_CASE("the destructor of an unpublished set removes its temporaries") {
  temp_dir d;
  const previous_run p = write_previous(d);
  {
    output_set set;
    for (const std::string& f : {p.exr, p.png, p.json}) set.reserve(f);
    write_exr(set, p.exr, small_image());
  }
  check_previous_intact(d, p);
}

TEST_CASE("publishing a set with a reserved but unwritten file fails and keeps the previous set") {
  temp_dir d;
  const previous_run p = write_previous(d);
  output_set set;
  for (const std::string& f : {p.exr, p.png, p.json}) set.reserve(f);
  write_exr(set, p.exr, small_image());
  write_png_preview(set, p.png, small_image());
  CHECK_THROWS_WITH(set.publish(), p.json + ": reserved as an output but never written");
  check_previous_intact(d, p);
}

TEST_CASE("a rename failing half way puts the files already renamed back") {
  temp_dir d;
  const previous_run p = write_previous(d);
  // The JSON's final name is a non-empty directory: its rename fails after the EXR's and PNG's.
  const std::string json = d.file("blocked.json");
  std::filesystem::create_directory(json);
  d.write("blocked.json/inside", "x");
  output_set set;
  write_exr(set, p.exr, small_image());
  write_png_preview(set, p.png, small_image());
  write_json(set, json, nlohmann::json::object());
  CHECK_THROWS_WITH(set.publish(), Catch::Contains(json + ": cannot rename the temporary file into place"));
  CHECK(read_file_bytes(p.exr) == "old exr");
  CHECK(read_file_bytes(p.png) == "old png");
  CHECK(sorted_entries(d) == std::vector<std::string>{"blocked.json", "out.exr", "out.json", "out.png"});
  // Where there was no previous file, a failed set leaves none.
  temp_dir e;
  std::filesystem::create_directory(e.file("blocked.json"));
  e.write("blocked.json/inside", "x");
  output_set fresh;
  write_exr(fresh, e.file("new.exr"), small_image());
  write_json(fresh, e.file("blocked.json"), nlohmann::json::object());
  CHECK_THROWS_AS(fresh.publish(), output_error);
  CHECK(sorted_entries(e) == std::vector<std::string>{"blocked.json"});
}

TEST_CASE("write_file_bytes names a full disk and other errors with the path") {
  const std::string bytes(100, 'x');
  CHECK_THROWS_WITH(write_file_bytes("/dev/full", "shown.png", bytes.data(), bytes.size()),
                    "shown.png: no space left on device (writing 100 bytes)");
  CHECK_THROWS_WITH(write_file_bytes("/no/such/dir/f", "f.png", bytes.data(), bytes.size()),
                    "f.png: cannot write (No such file or directory)");
}
