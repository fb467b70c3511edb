# SPDX-License-Identifier: MIT
# scripts/results/ris_mis_gpu.sh --quick on this build (llvmpipe here): exit 0; OUTDIR holds the
# report and the archive only (what a device run brings back: at most 8 files); the report names
# the device, counts the tests and has an equal-time row per budget, for flux and tile candidates
# (the tiles' table compares with the flux run's gather and mis); no step failed or was
# skipped; the archive holds the sweeps' CSVs, the test log and the runs' table.
cmake_minimum_required(VERSION 3.19)
include(${CMAKE_CURRENT_LIST_DIR}/run_quick_report.cmake)
run_quick_report("ris_mis_gpu.md;ris_mis_gpu_raw.tar.gz")
foreach(want "# ris-mis on the GPU backend: OpenGL " "\ncommit: " "## Tests: ctest"
             "100% tests passed, 0 tests failed out of [1-9]" "### cornell \\(M = 2, R = 1\\)"
             "\\| budget \\(global at\\) \\| time ms \\| best other \\|"
             "\n\\| 4 \\| [0-9]+ \\| [a-z-]+ \\([A-Za-z_0-9]+\\) [0-9.]+e[-+][0-9]+\\*? \\| gpu_cornell_M2_R1 \\| [0-9.]+e[-+][0-9]+\\*? \\| [0-9.]+ \\|"
             "\n\\| 16 \\| [0-9]+ \\|" "\nsve_cornell_global\tok\t" "\nsve_cornell_M2_R1\tok\t"
             "### cornell \\(M = 2, R = 1, tiles\\)"
             "\n\\| 4 \\| [0-9]+ \\| [a-z-]+ \\([A-Za-z_0-9]+\\) [0-9.]+e[-+][0-9]+\\*? \\| gpu_cornell_M2_R1_tiles \\|"
             "\nsve_cornell_M2_R1_tiles\tok\t")
  if(NOT md MATCHES "${want}")
    message(FATAL_ERROR "ris_mis_gpu.md lacks '${want}':\n${md}")
  endif()
endforeach()
if(md MATCHES "\t(exit [0-9]+|skipped)")
  message(FATAL_ERROR "a step did not succeed:\n${md}")
endif()
execute_process(COMMAND tar -tzf ${WORKDIR}/out/ris_mis_gpu_raw.tar.gz OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
foreach(want "raw/sweeps/gpu_cornell_global.csv" "raw/sweeps/gpu_cornell_M2_R1.csv"
             "raw/sweeps/gpu_cornell_M2_R1_tiles.csv" "raw/logs/ctest.log"
             "raw/runs.tsv" "raw/equal_time.md" "raw/device.txt")
  if(NOT listing MATCHES "${want}")
    message(FATAL_ERROR "the archive lacks ${want}:\n${listing}")
  endif()
endforeach()
message(STATUS "ok: ris_mis_gpu.sh --quick")
