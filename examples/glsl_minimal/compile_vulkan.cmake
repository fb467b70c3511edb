# SPDX-License-Identifier: MIT
# Prepends #version 450 to the example shader and compiles it to SPIR-V for Vulkan 1.1.
file(READ "${SHADER}" body)
file(WRITE "${OUT}/pick_vpls_vk.comp" "#version 450\n${body}")
execute_process(COMMAND ${VALIDATOR} -V --target-env vulkan1.1 -I${GLSL_DIR}
                        "${OUT}/pick_vpls_vk.comp" -o "${OUT}/pick_vpls.spv"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "glslangValidator failed (${rc}):\n${out}\n${err}")
endif()
message(STATUS "pick_vpls.comp compiled to SPIR-V for Vulkan 1.1")
