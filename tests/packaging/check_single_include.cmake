# SPDX-License-Identifier: MIT
# Fails when single_include/vplkit/vplkit.hpp differs from a fresh amalgamation of include/.
set(fresh "${VPLKIT_SCRATCH}/vplkit.hpp")
execute_process(COMMAND ${CMAKE_COMMAND} -DVPLKIT_ROOT=${VPLKIT_ROOT} -DVPLKIT_OUTPUT=${fresh}
                        -P ${VPLKIT_ROOT}/cmake/amalgamate.cmake
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "amalgamation failed (${rc})")
endif()
set(committed "${VPLKIT_ROOT}/single_include/vplkit/vplkit.hpp")
if(NOT EXISTS "${committed}")
  message(FATAL_ERROR "${committed} is missing: run `cmake --build <build> --target vplkit_amalgamate`")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${fresh}" "${committed}" RESULT_VARIABLE differs)
if(differs)
  message(FATAL_ERROR "single_include/vplkit/vplkit.hpp is stale: include/ changed since it was "
                      "generated. Run `cmake --build <build> --target vplkit_amalgamate` and commit it.")
endif()
message(STATUS "single_include/vplkit/vplkit.hpp is current")
