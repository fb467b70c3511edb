# SPDX-License-Identifier: MIT
# Configures, builds and runs a consumer project against vplkit, the way a user would.
#   MODE=install      : install vplkit into a scratch prefix, consumer uses find_package(vplkit)
#   MODE=subdirectory : consumer uses add_subdirectory(<vplkit source>), compiles README's example
#                       and a program that includes kernel parameter headers
#   MODE=own_glm      : add_subdirectory from a parent that defines its own glm::glm (and C++14)
#   MODE=fetchcontent : FetchContent_Declare(vplkit SOURCE_DIR <vplkit source>)
#   MODE=pkgconfig    : install into a scratch prefix, compile with `pkg-config --cflags vplkit`
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "command failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()

set(work "${SCRATCH}/${MODE}")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}")

if(MODE STREQUAL "install")
  set(prefix "${work}/prefix")
  run(${CMAKE_COMMAND} --install "${VPLKIT_BINARY_DIR}" --prefix "${prefix}")
  run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_ROOT}/consumer_install" -B "${work}/build" -G "${GENERATOR}"
      -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_PREFIX_PATH=${prefix})
elseif(MODE STREQUAL "subdirectory")
  # README.md's example, between the readme-example markers, is the consumer's main.cpp.
  file(READ "${VPLKIT_ROOT}/README.md" readme)
  string(REGEX MATCH "<!-- readme-example:begin -->[^`]*```cpp\n(.*)```[^`]*<!-- readme-example:end -->" found "${readme}")
  if(NOT found)
    message(FATAL_ERROR "README.md has no ```cpp block between <!-- readme-example:begin/end --> markers")
  endif()
  file(WRITE "${work}/readme_example.cpp" "${CMAKE_MATCH_1}")
  run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_ROOT}/consumer_subdirectory" -B "${work}/build" -G "${GENERATOR}"
      -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DVPLKIT_SOURCE=${VPLKIT_ROOT}
      -DREADME_EXAMPLE=${work}/readme_example.cpp)
elseif(MODE STREQUAL "own_glm" OR MODE STREQUAL "fetchcontent")
  run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_ROOT}/consumer_${MODE}" -B "${work}/build" -G "${GENERATOR}"
      -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DVPLKIT_SOURCE=${VPLKIT_ROOT})
elseif(MODE STREQUAL "pkgconfig")
  set(prefix "${work}/prefix")
  run(${CMAKE_COMMAND} --install "${VPLKIT_BINARY_DIR}" --prefix "${prefix}")
  # vplkit.pc first; GLM's glm.pc (Requires: glm) from the system's default path.
  set(ENV{PKG_CONFIG_PATH} "${prefix}/share/pkgconfig")
  foreach(q "--cflags;vplkit" "--variable=glsldir;vplkit" "--modversion;vplkit")
    execute_process(COMMAND pkg-config ${q} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                    OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "pkg-config ${q} failed (${rc}): ${err}")
    endif()
    list(APPEND answers "${out}")
  endforeach()
  list(GET answers 0 cflags)
  list(GET answers 1 glsldir)
  list(GET answers 2 version)
  message("pkg-config: cflags '${cflags}', glsldir '${glsldir}', version ${version}")
  if(NOT version STREQUAL VPLKIT_VERSION)
    message(FATAL_ERROR "vplkit.pc says version ${version}, the project ${VPLKIT_VERSION}")
  endif()
  if(NOT EXISTS "${glsldir}/vplkit/distribution/discrete_cdf.glsl")
    message(FATAL_ERROR "pkg-config --variable=glsldir vplkit gives ${glsldir}, which has no GLSL pack")
  endif()
  separate_arguments(cflags UNIX_COMMAND "${cflags}")
  file(MAKE_DIRECTORY "${work}/build")
  run(${CXX_COMPILER} -std=c++17 -Wall -Wextra -Wpedantic -Werror ${cflags} "-DVPLKIT_GLSL_DIR=\"${glsldir}\""
      "${CONSUMER_SOURCE_ROOT}/consumer_install/main.cpp" -o "${work}/build/consumer")
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
if(NOT MODE STREQUAL "pkgconfig")
  run(${CMAKE_COMMAND} --build "${work}/build")
endif()
run("${work}/build/consumer")
if(MODE STREQUAL "subdirectory")
  run("${work}/build/params_consumer")
endif()
