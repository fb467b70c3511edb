# SPDX-License-Identifier: MIT
# Shared by run_gpu_report.cmake and run_ris_mis_gpu.cmake: run_quick_report(<expected>) runs
# `bash ${SCRIPT} --quick ${BUILD} ${WORKDIR}/out` in a fresh WORKDIR, fails unless it exits 0 and
# OUTDIR holds exactly the files <expected> names (sorted, ;-separated), each of 1 byte to 16 MiB
# (what a device run brings back), and sets `md` to the report (the .md among them) and `out` to
# what the script printed.
function(run_quick_report expected)
  file(REMOVE_RECURSE ${WORKDIR})
  file(MAKE_DIRECTORY ${WORKDIR})
  get_filename_component(script_name ${SCRIPT} NAME)
  execute_process(COMMAND bash ${SCRIPT} --quick ${BUILD} ${WORKDIR}/out WORKING_DIRECTORY ${WORKDIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${script_name} --quick: exit ${rc}\n${out}\n${err}")
  endif()
  file(GLOB_RECURSE produced LIST_DIRECTORIES true RELATIVE ${WORKDIR}/out ${WORKDIR}/out/*)
  list(SORT produced)
  if(NOT produced STREQUAL "${expected}")
    message(FATAL_ERROR "OUTDIR holds '${produced}', expected '${expected}': the report and the archive only")
  endif()
  foreach(f ${produced})
    file(SIZE ${WORKDIR}/out/${f} size)
    if(size GREATER 16777216 OR size EQUAL 0)
      message(FATAL_ERROR "${f}: ${size} bytes (must be 1 .. 16 MiB)")
    endif()
    if(f MATCHES "\\.md$")
      file(READ ${WORKDIR}/out/${f} report)
    endif()
  endforeach()
  set(md "${report}" PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
endfunction()
