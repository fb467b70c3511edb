// SPDX-License-Identifier: MIT
// gpu_report_tables RAW_DIR REPORT.md ARCHIVE_NAME: the markdown report of scripts/gpu-report.sh
// from the raw files that script collected (a GPU machine may have neither Python nor jq; this
// is built with the examples and packed with them). Writes REPORT.md and prints the short summary
// table on stdout. RAW_DIR holds:
//   runs.tsv            name, status, wall seconds, command (one line per run)
//   device/             device.json (a vplrender report: gl_renderer), vulkan.txt, host.txt,
//                       nvidia_smi.txt (when nvidia-smi exists)
//   frames/*.json       vplrender --frames reports
//   profile/p_*.json    vplrender single-frame reports (the stage profile)
//   table1/table1_<scene>_<method>.csv   speed_vs_error CSVs
//   tests/<label>.log   ctest output
// Exit status 0, or 1 when REPORT.md cannot be written.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

std::string first_line(const fs::path& p, const std::string& fallback) {
  std::ifstream in(p);
  std::string line;
  return in && std::getline(in, line) ? trim(line) : fallback;
}

json read_json(const fs::path& p) {
  try {
    std::ifstream in(p);
    return json::parse(in);
  } catch (const std::exception&) {
    return json();
  }
}

// Milliseconds as the tables print them: 3 significant digits, at least 2 decimals below 10.
std::string ms(double v) {
  std::ostringstream s;
  if (v >= 100.0) s << std::fixed << std::setprecision(0) << v;
  else if (v >= 10.0) s << std::fixed << std::setprecision(1) << v;
  else s << std::fixed << std::setprecision(2) << v;
  return s.str();
}

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(2) << v;
  return s.str();
}

// Markdown cells: no pipes or line breaks.
std::string cell(std::string s) {
  for (char& c : s)
    if (c == '|' || c == '\n') c = ' ';
  return s;
}

struct run_row {
  std::string name, status, wall, command;
};

std::vector<run_row> read_runs(const fs::path& p) {
  std::vector<run_row> rows;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    run_row r;
    std::istringstream s(line);
    std::getline(s, r.name, '\t');
    std::getline(s, r.status, '\t');
    std::getline(s, r.wall, '\t');
    std::getline(s, r.command);
    if (!r.name.empty()) rows.push_back(r);
  }
  return rows;
}

std::string status_of(const std::vector<run_row>& runs, const std::string& name) {
  for (const run_row& r : runs)
    if (r.name == name) return r.status;
  return "not run";
}

std::vector<fs::path> files(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> v;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && e.path().extension() == ext) v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

// The stage's ms in a vplrender report's "stages" (0 when absent); several names are summed.
double stage_ms(const json& stages, const std::function<bool(const std::string&)>& pick) {
  double sum = 0.0;
  if (!stages.is_array()) return sum;
  for (const json& s : stages) {
    const std::string name = s.value("name", "");
    if (pick(name)) sum += s.value("ms", s.value("median_ms", 0.0));
  }
  return sum;
}

bool starts(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }
bool has(const std::string& s, const char* p) { return s.find(p) != std::string::npos; }

// What a vplrender run was, from its parameters.
std::string describe_run(const json& j) {
  const json& p = j.value("parameters", json::object());
  std::ostringstream s;
  std::string scene = p.value("scene", "?");
  const std::size_t slash = scene.find_last_of('/');
  if (slash != std::string::npos) scene = scene.substr(slash + 1);
  s << scene << ", " << p.value("method", "?") << ", " << p.value("backend", "?") << ", " << p.value("width", 0)
    << "x" << p.value("height", 0) << ", " << p.value("vpls", 0) << " VPLs";
  const std::string m = p.value("method", "");
  if (m == "gather" || m == "mis" || m == "gbg" || m == "exact" || m == "mis-as-published")
    s << ", " << p.value("dirs", 0) << " dirs";
  s << ", DPRSM 2x" << p.value("dprsm", 0) << "^2, " << p.value("voxels", 0) << "^3 voxels, " << p.value("visibility", "?")
    << ", " << p.value("vpl_mode", "?") << " VPLs";
  return s.str();
}

// ctest's summary line: "N% tests passed, F tests failed out of T" and the real time.
struct test_summary {
  bool found = false;
  int failed = 0, total = 0;
  std::string time = "-";
  std::vector<std::string> failures;
};

test_summary read_ctest(const fs::path& p) {
  test_summary t;
  const std::string text = read_text(p);
  std::smatch m;
  if (std::regex_search(text, m, std::regex(R"((\d+)% tests passed, (\d+) tests failed out of (\d+))"))) {
    t.found = true;
    t.failed = std::stoi(m[2]);
    t.total = std::stoi(m[3]);
  }
  if (std::regex_search(text, m, std::regex(R"(Total Test time \(real\) = +([0-9.]+) sec)"))) t.time = m[1];
  std::istringstream in(text);
  std::string line;
  bool in_list = false;
  while (std::getline(in, line)) {
    if (has(line, "The following tests FAILED")) in_list = true;
    else if (in_list && line.size() > 1 && line[0] == '\t') t.failures.push_back(trim(line.substr(1)));
    else if (in_list) in_list = false;
  }
  return t;
}

// A speed_vs_error CSV: header and rows as maps.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::vector<std::map<std::string, std::string>> rows;
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> head;
  auto split = [](const std::string& l) {
    std::vector<std::string> v;
    std::string cur;
    for (char c : l) {
      if (c == ',') {
        v.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    v.push_back(cur);
    return v;
  };
  if (!std::getline(in, line)) return rows;
  head = split(trim(line));
  while (std::getline(in, line)) {
    const std::vector<std::string> v = split(trim(line));
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < head.size() && i < v.size(); ++i) row[head[i]] = v[i];
    rows.push_back(row);
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& key) {
  const auto it = row.find(key);
  if (it == row.end() || it->second.empty()) return -1.0;
  try {
    return std::stod(it->second);
  } catch (const std::exception&) {
    return -1.0;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: gpu_report_tables RAW_DIR REPORT.md ARCHIVE_NAME\n";
    return 2;
  }
  const fs::path raw = argv[1];
  const fs::path report = argv[2];
  const std::string archive = argv[3];
  const std::vector<run_row> runs = read_runs(raw / "runs.tsv");

  // ---- the device
  const json device = read_json(raw / "device" / "device.json");
  const std::string gl =
      device.is_object() && device.value("gl_renderer", json()).is_string() ? device["gl_renderer"].get<std::string>()
                                                                            : "no GL context (" + status_of(runs, "device") + ")";
  const std::string vulkan = first_line(raw / "device" / "vulkan.txt", "vulkan: unknown");
  const std::string smi = first_line(raw / "device" / "nvidia_smi.txt", "");
  const std::string host = trim(read_text(raw / "device" / "host.txt"));
  const bool llvmpipe = has(gl, "llvmpipe");

  std::ostringstream md;
  md << "# vplkit on " << cell(gl) << "\n\n"
     << "Made by `scripts/gpu-report.sh` (docs/renderer.md, \"GPU report\"). Times are milliseconds per frame unless "
        "named otherwise; `gpu` stages are GL timer queries, `cpu-wall` ones steady_clock.";
  if (llvmpipe) md << " **This device is llvmpipe (Mesa's software rasteriser on the CPU): the numbers say llvmpipe, not a GPU.**";
  md << "\n\n## Device\n\n| what | |\n|---|---|\n"
     << "| OpenGL | " << cell(gl) << " |\n"
     << "| Vulkan | " << cell(vulkan.rfind("vulkan: ", 0) == 0 ? vulkan.substr(8) : vulkan) << " |\n";
  if (!smi.empty()) md << "| nvidia-smi (name, driver, memory, max SM clock) | " << cell(smi) << " |\n";
  {
    std::istringstream in(host);
    std::string line;
    while (std::getline(in, line)) {
      const std::size_t c = line.find(": ");
      if (c != std::string::npos) md << "| " << cell(line.substr(0, c)) << " | " << cell(line.substr(c + 2)) << " |\n";
    }
  }

  // ---- frames
  md << "\n## Frames (`vplrender --frames N`)\n\n"
     << "N frames in one process after one untimed warm-up frame, the light moving on a circle of radius 0.05 of "
        "the scene's diagonal through its position; a frame's time is the wall time from its G-buffer to its image "
        "on the host (docs/renderer.md, \"Frames\"). Target on an NVIDIA H100/H200: cornell at 512x512 with 16 VPLs "
        "at 60 frames per second or more (16.7 ms).\n\n"
     << "| run | frames | median ms | frames/s | min ms | max ms | status |\n|---|---|---|---|---|---|---|\n";
  std::vector<std::pair<std::string, json>> frame_runs;
  for (const fs::path& p : files(raw / "frames", ".json")) frame_runs.emplace_back(p.stem().string(), read_json(p));
  std::string summary_frames = "-", summary_frames_what = "frames (gpu, global, 16 VPLs)";
  for (const auto& [name, j] : frame_runs) {
    const json f = j.is_object() ? j.value("frames", json()) : json();
    if (!f.is_object()) continue;
    md << "| " << cell(describe_run(j)) << " | " << f.value("count", 0) << " | " << ms(f.value("median_ms", 0.0)) << " | "
       << ms(f.value("fps", 0.0)) << " | " << ms(f.value("min_ms", 0.0)) << " | " << ms(f.value("max_ms", 0.0)) << " | "
       << cell(status_of(runs, name)) << " |\n";
    if (name == "fr_gpu_global_v16") {
      summary_frames = ms(f.value("median_ms", 0.0)) + " ms (" + ms(f.value("fps", 0.0)) + " frames/s)";
      summary_frames_what = "frames: " + describe_run(j) + ", median";
    }
  }
  for (const run_row& r : runs)
    if (starts(r.name, "fr_") && r.status != "ok") md << "| " << cell(r.name) << " | | | | | | " << cell(r.status) << " |\n";
  // Per-stage medians, one column per run.
  std::vector<std::string> stage_names;
  for (const auto& [name, j] : frame_runs) {
    const json f = j.is_object() ? j.value("frames", json()) : json();
    if (!f.is_object()) continue;
    for (const json& s : f.value("stages", json::array())) {
      const std::string n = s.value("name", "");
      if (std::find(stage_names.begin(), stage_names.end(), n) == stage_names.end()) stage_names.push_back(n);
    }
  }
  if (!stage_names.empty()) {
    md << "\nPer-stage medians (ms):\n\n| stage |";
    std::string rule = "|---|";
    for (const auto& [name, j] : frame_runs) {
      md << " " << cell(name) << " |";
      rule += "---|";
    }
    md << "\n" << rule << "\n";
    for (const std::string& n : stage_names) {
      md << "| " << cell(n) << " |";
      for (const auto& [name, j] : frame_runs) {
        const json f = j.is_object() ? j.value("frames", json()) : json();
        std::string v = "";
        if (f.is_object())
          for (const json& s : f.value("stages", json::array()))
            if (s.value("name", "") == n) v = ms(s.value("median_ms", 0.0));
        md << " " << v << " |";
      }
      md << "\n";
    }
  }

  // ---- tests
  md << "\n## Tests (`ctest -L vulkan`, `ctest -L parity -LE vulkan`)\n\n"
     << "| label | passed | failed | total | time s | status |\n|---|---|---|---|---|---|\n";
  std::map<std::string, test_summary> tests;
  for (const char* label : {"vulkan", "parity"}) {
    const test_summary t = read_ctest(raw / "tests" / (std::string(label) + ".log"));
    tests[label] = t;
    md << "| " << label << " | " << (t.found ? std::to_string(t.total - t.failed) : "-") << " | "
       << (t.found ? std::to_string(t.failed) : "-") << " | " << (t.found ? std::to_string(t.total) : "-") << " | " << t.time
       << " | " << cell(status_of(runs, std::string("ctest_") + label)) << " |\n";
  }
  for (const auto& [label, t] : tests)
    for (const std::string& f : t.failures) md << "\n- " << label << " failed: " << cell(f);
  md << "\n";

  // ---- stage profile
  md << "\n## Stage profile (`vplrender`, one frame per run)\n\n"
     << "| run | what | gbuffer | dprsm | voxels | builders | cdf | estimate | read-back | total | status |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const fs::path& p : files(raw / "profile", ".json")) {
    const json j = read_json(p);
    if (!j.is_object()) continue;
    const json& st = j["stages"];
    const double builders = stage_ms(st, [](const std::string& n) {
      return has(n, "weights") || has(n, "hole fill") || has(n, "sampler tables");
    });
    md << "| " << p.stem().string() << " | " << cell(describe_run(j)) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return starts(n, "gbuffer"); })) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return starts(n, "dprsm"); })) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return starts(n, "voxelize"); })) << " | " << ms(builders) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return starts(n, "cdf"); })) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return starts(n, "estimate"); })) << " | "
       << ms(stage_ms(st, [](const std::string& n) { return n == "read-back (cpu)"; })) << " | "
       << ms(j.value("total_ms", 0.0)) << " | " << cell(status_of(runs, p.stem().string())) << " |\n";
  }
  for (const run_row& r : runs)
    if (starts(r.name, "p_") && r.status != "ok") md << "| " << cell(r.name) << " | | | | | | | | | | " << cell(r.status) << " |\n";
  md << "\n`total` is the whole process's stages (GL context, raster setup, voxel grid, uploads and writing the outputs "
        "included); `builders` sums the weight stages, the GBG hole fill and the sampler tables.\n";

  // ---- Table 1
  md << "\n## Table 1 analogue (`speed_vs_error --paper --backend gpu`)\n\n"
     << "Build + estimate per frame (ms, the median of the repeats), RMSE against converged gathering (reference b) "
        "in brackets. Paper (GTX 780): Sponza Buddha global 270, local 410, gbg 190, mis 230; Sibenik 600, 630, 350, "
        "460.\n\n| scene | global | local | gbg | gbg (16 dirs) | mis |\n|---|---|---|---|---|---|\n";
  std::string summary_t1 = "-", summary_t1_what = "Table 1 analogue: cornell, global";
  for (const char* scene : {"cornell", "open", "sponza"}) {
    std::ostringstream row;
    bool any = false;
    row << "| " << scene << " |";
    for (const char* m : {"global", "local", "gbg", "gbg16", "mis"}) {
      const std::string stem = std::string("table1_") + scene + "_" + m;
      const auto rows = read_csv(raw / "table1" / (stem + ".csv"));
      const std::string status = status_of(runs, std::string("t1_") + scene + "_" + m);
      if (status != "not run") any = true;
      if (!rows.empty()) {
        const double t = number(rows.front(), "total_ms"), e = number(rows.front(), "rmse_gather");
        row << " " << ms(t) << (e >= 0.0 ? " (" + sci(e) + ")" : "") << " |";
        if (std::string(scene) == "cornell" && std::string(m) == "global") {
          summary_t1 = ms(t) + " ms";
          summary_t1_what += ", " + rows.front().at("samples") + " VPLs, " + rows.front().at("width") + "x" +
                             rows.front().at("height");
        }
      } else {
        row << " " << cell(status == "ok" ? "no CSV" : status) << " |";
      }
    }
    if (any) md << row.str() << "\n";
  }

  // ---- runs and files
  md << "\n## Runs\n\n| run | status | wall s | command |\n|---|---|---|---|\n";
  for (const run_row& r : runs) md << "| " << cell(r.name) << " | " << cell(r.status) << " | " << r.wall << " | `" << cell(r.command) << "` |\n";
  md << "\nRaw files (every JSON report, CSV and log of the runs above, no images): `" << archive << "`.\n";

  std::ofstream out(report);
  out << md.str();
  if (!out) {
    std::cerr << "gpu_report_tables: cannot write " << report << "\n";
    return 1;
  }

  // ---- the summary, last
  auto tests_cell = [&](const char* label) {
    const test_summary& t = tests[label];
    return t.found ? std::to_string(t.total - t.failed) + "/" + std::to_string(t.total) + " passed"
                   : status_of(runs, std::string("ctest_") + label);
  };
  int not_ok = 0;
  for (const run_row& r : runs) not_ok += r.status != "ok" ? 1 : 0;
  std::cout << "| gpu-report | |\n|---|---|\n"
            << "| device | " << cell(gl) << " |\n"
            << "| vulkan | " << cell(vulkan.rfind("vulkan: ", 0) == 0 ? vulkan.substr(8) : vulkan) << " |\n"
            << "| " << cell(summary_frames_what) << " | " << summary_frames << " |\n"
            << "| " << cell(summary_t1_what) << " | " << summary_t1 << " |\n"
            << "| parity tests | " << tests_cell("parity") << " |\n"
            << "| vulkan tests | " << tests_cell("vulkan") << " |\n"
            << "| runs not ok | " << not_ok << " of " << runs.size() << " |\n"
            << "| report | " << report.string() << " |\n";
  return 0;
}
