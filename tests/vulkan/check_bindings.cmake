# SPDX-License-Identifier: MIT
# Checks that a kernel's default bindings form a valid Vulkan descriptor set layout: compiles it as
# Vulkan GLSL (#version 450 + GL_GOOGLE_include_directive, no defines: the defaults of its
# parameter header), reflects the SPIR-V with spirv-cross and fails if two resources share a
# (set, binding). In Vulkan one binding number of a set holds one descriptor (one type); OpenGL
# keeps uniform blocks and storage buffers in separate binding namespaces, which is why a collision
# compiles and runs there and glslang accepts it.
#   cmake -DVALIDATOR=<glslangValidator> -DSPIRV_CROSS=<spirv-cross> -DGLSL_DIR=<pack root>
#         -DEXTRA_DIR=<another include folder> -DKERNEL=<path under an include folder> -DOUT=<dir>
#         -P check_bindings.cmake
cmake_minimum_required(VERSION 3.19)  # string(JSON)
foreach(var VALIDATOR SPIRV_CROSS GLSL_DIR KERNEL OUT)
  if(NOT ${var})
    message(FATAL_ERROR "check_bindings.cmake needs -D${var}=...")
  endif()
endforeach()

string(MAKE_C_IDENTIFIER "${KERNEL}" stem)
set(wrapper ${OUT}/${stem}.comp)
set(spv ${OUT}/${stem}.spv)
file(WRITE ${wrapper} "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"${KERNEL}\"\n")
set(includes -I${GLSL_DIR})
if(EXTRA_DIR)
  list(APPEND includes -I${EXTRA_DIR})
endif()
execute_process(COMMAND ${VALIDATOR} -V --target-env vulkan1.1 ${includes} -o ${spv} ${wrapper}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${KERNEL}: glslangValidator failed (${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${SPIRV_CROSS} ${spv} --reflect RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${KERNEL}: spirv-cross --reflect failed (${rc}):\n${err}")
endif()

# Every kind of descriptor spirv-cross reflects (push constants and inputs take no binding).
set(kinds ubos ssbos textures separate_images separate_samplers images acceleration_structures subpass_inputs)
set(seen "")        # "<set>:<binding>" per descriptor, in order
set(names "")       # "<kind> <name>", parallel to seen
set(problems "")
set(table "")
foreach(kind ${kinds})
  string(JSON count ERROR_VARIABLE missing LENGTH "${json}" ${kind})
  if(missing)
    continue()  # the shader has none of this kind
  endif()
  if(count EQUAL 0)
    continue()
  endif()
  math(EXPR last "${count} - 1")
  foreach(i RANGE ${last})
    string(JSON name GET "${json}" ${kind} ${i} name)
    string(JSON set ERROR_VARIABLE no_set GET "${json}" ${kind} ${i} set)
    string(JSON binding ERROR_VARIABLE no_binding GET "${json}" ${kind} ${i} binding)
    if(no_set OR no_binding)
      list(APPEND problems "${kind} ${name} has no set / binding decoration")
      continue()
    endif()
    set(key "${set}:${binding}")
    list(FIND seen "${key}" other)
    if(NOT other EQUAL -1)
      list(GET names ${other} other_name)
      list(APPEND problems "set ${set} binding ${binding} holds both ${other_name} and ${kind} ${name}")
    endif()
    list(APPEND seen "${key}")
    list(APPEND names "${kind} ${name}")
    list(APPEND table "  set ${set} binding ${binding}: ${kind} ${name}")
  endforeach()
endforeach()

if(NOT seen)
  message(FATAL_ERROR "${KERNEL}: spirv-cross reflected no descriptors (is this a kernel?)")
endif()
list(SORT table COMPARE NATURAL)
list(JOIN table "\n" table)
message("${KERNEL}, default bindings as Vulkan sees them:\n${table}")
if(problems)
  foreach(p IN LISTS problems)
    message("BINDING COLLISION: ${p}")
  endforeach()
  message(FATAL_ERROR "${KERNEL}: its default bindings are not a valid Vulkan descriptor set layout (one "
                      "descriptor per binding and set): give each resource its own binding in the kernel's "
                      "parameter header")
endif()
message(STATUS "${KERNEL}: every descriptor binding unique within its set")
