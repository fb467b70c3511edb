# SPDX-License-Identifier: MIT
# Runs EXE with ARGS (a ;-list) in WORKDIR; checks the exit status RC and that stdout+stderr match
# MATCH. Also checks that a failed run left no output image behind.
separate_arguments(_args UNIX_COMMAND "")
set(_args ${ARGS})
execute_process(COMMAND ${EXE} ${_args} WORKING_DIRECTORY ${WORKDIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REPLACE "\n" " " all "${out} ${err}")
if(NOT rc STREQUAL RC)
  message(FATAL_ERROR "exit status ${rc}, expected ${RC}\nstdout: ${out}\nstderr: ${err}")
endif()
if(MATCH AND NOT all MATCHES "${MATCH}")
  message(FATAL_ERROR "output does not match '${MATCH}'\nstdout: ${out}\nstderr: ${err}")
endif()
if(NOT RC STREQUAL "0" AND EXISTS ${WORKDIR}/cli_out.exr)
  message(FATAL_ERROR "a failed run left cli_out.exr behind")
endif()
message(STATUS "ok: exit ${rc}")
