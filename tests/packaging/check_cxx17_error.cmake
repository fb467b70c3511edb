# SPDX-License-Identifier: MIT
# Below C++17 the headers stop with one clear message naming C++17 (not a cascade of errors about
# std::data or inline variables): the umbrella header, the single header, and a distribution
# header on its own, each compiled with -std=c++14 directly. With -std=c++17 each compiles.
#   cmake -DVPLKIT_ROOT=<repo> -DCXX_COMPILER=<c++> -DSCRATCH=<dir> -P check_cxx17_error.cmake
file(MAKE_DIRECTORY "${SCRATCH}")
set(cases "vplkit/vplkit.hpp|${VPLKIT_ROOT}/include"
          "vplkit/vplkit.hpp|${VPLKIT_ROOT}/single_include"
          "vplkit/distribution/discrete_cdf.hpp|${VPLKIT_ROOT}/include")
set(k 0)
foreach(c IN LISTS cases)
  string(REPLACE "|" ";" c "${c}")
  list(GET c 0 header)
  list(GET c 1 dir)
  math(EXPR k "${k} + 1")
  set(tu "${SCRATCH}/tu${k}.cpp")
  file(WRITE "${tu}" "#include <${header}>\nint main() { return 0; }\n")
  execute_process(COMMAND ${CXX_COMPILER} -std=c++14 -fsyntax-only -I${dir} "${tu}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "${header} (-I${dir}) compiled with -std=c++14: no C++17 check")
  endif()
  if(NOT err MATCHES "vplkit needs C\\+\\+17 or later")
    message(FATAL_ERROR "${header} (-I${dir}) with -std=c++14 failed without the C++17 message:\n${err}")
  endif()
  string(FIND "${err}" "\n" first_newline)
  string(SUBSTRING "${err}" 0 ${first_newline} first_line)
  message(STATUS "-std=c++14 on ${header}: ${first_line}")
  execute_process(COMMAND ${CXX_COMPILER} -std=c++17 -fsyntax-only -I${dir} "${tu}"
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${header} (-I${dir}) does not compile with -std=c++17:\n${err}")
  endif()
endforeach()
