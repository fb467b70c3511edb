# SPDX-License-Identifier: MIT
# scripts/gpu-report.sh --quick on this build (llvmpipe here): exit 0; OUTDIR holds the report and
# the archive only (the device pack brings back at most 8 files of 16 MiB, no deeper than 2
# folders); the report has its sections and tables, with the device named; the archive holds the
# raw JSON, CSV and logs; the summary table is printed last.
cmake_minimum_required(VERSION 3.19)
include(${CMAKE_CURRENT_LIST_DIR}/run_quick_report.cmake)
run_quick_report("gpu-report-raw.tar.gz;gpu-report.md")
foreach(want "# vplkit on OpenGL " "## Device" "| OpenGL | OpenGL " "| Vulkan | " "| build | "
             "## Frames \\(`vplrender --frames N`\\)" "\\| cornell, global, gpu, 48x32, 16 VPLs[^|]*\\| 3 \\| [0-9.]+ \\| [0-9.]+ \\|"
             "\\| cornell, mis, gpu, 48x32, 16 VPLs, 16 dirs[^|]*\\| 3 \\|" "\\| cornell, global, cpu, 48x32[^|]*\\| 2 \\|"
             "Per-stage medians" "\\| estimate \\(gpu\\) \\|" "## Tests" "\\| vulkan \\| [1-9][0-9]* \\| 0 \\|"
             "\\| parity \\| [1-9][0-9]* \\| 0 \\|" "## Stage profile" "\\| p_s64 \\| cornell, global, gpu, 64x64"
             "## Table 1 analogue" "\\| cornell \\| [0-9.]+ \\([0-9.]+e[-+][0-9]+\\) \\|" "## Runs" "gpu-report-raw.tar.gz")
  if(NOT md MATCHES "${want}")
    message(FATAL_ERROR "gpu-report.md lacks '${want}':\n${md}")
  endif()
endforeach()
if(md MATCHES "\\| (timed out after|failed \\(exit|skipped \\()")
  message(FATAL_ERROR "a run did not succeed:\n${md}")
endif()
execute_process(COMMAND tar -tzf ${WORKDIR}/out/gpu-report-raw.tar.gz OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
foreach(want "frames/fr_gpu_global_v16.json" "profile/p_cpu.json" "table1/table1_cornell_global.csv"
             "tests/parity.log" "tests/vulkan.log" "device/device.json" "runs.tsv")
  if(NOT listing MATCHES "${want}")
    message(FATAL_ERROR "the archive lacks ${want}:\n${listing}")
  endif()
endforeach()
if(listing MATCHES "\\.exr|\\.png")
  message(FATAL_ERROR "the archive holds images:\n${listing}")
endif()
# The summary table comes last.
string(STRIP "${out}" out)
if(NOT out MATCHES "\\| gpu-report \\| \\|\n\\|---\\|---\\|\n\\| device \\| [^\n]+\n(\\|[^\n]+\n)*\\| report \\| [^\n]+gpu-report.md \\|$")
  message(FATAL_ERROR "the summary table is not the last thing printed:\n${out}")
endif()
message(STATUS "ok: gpu-report.sh --quick")
