# Configures, builds and runs a consumer project against vplkit, the way a user would.
#   MODE=install      : install vplkit into a scratch prefix, consumer uses find_package(vplkit)
#   MODE=subdirectory : consumer uses add_subdirectory(<vplkit source>), compiles README's example
#                       and a program that includes kernel parameter headers
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
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
run(${CMAKE_COMMAND} --build "${work}/build")
run("${work}/build/consumer")
if(MODE STREQUAL "subdirectory")
  run("${work}/build/params_consumer")
endif()
