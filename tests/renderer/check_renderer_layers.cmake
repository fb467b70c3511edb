# SPDX-License-Identifier: MIT
# The example renderer's layers (docs/renderer.md, "Source layout"): the one place that states their
# order. Checks that no file of examples/vplrender/src, examples/speed_vs_error or a tool includes a
# file of a higher layer, nor of another area of its own layer:
#   cmake -DROOT=<dir holding vplrender/src and speed_vs_error> -P check_renderer_layers.cmake
# A file's area is its folder below vplrender/src (render/cpu and render/gpu are areas of their
# own); render/pipeline.* and render/frames.* drive both backends and form the area
# `render/pipeline`; examples/speed_vs_error is the area `speed_vs_error`. An include written
# without a folder ("pareto.hpp") is a file of the includer's own area. Prints every violation as
# "<file>:<line>: ...", then fails if there was one.
if(NOT ROOT)
  message(FATAL_ERROR "check_renderer_layers.cmake needs -DROOT=<examples dir>")
endif()

# Lowest layer first. Areas of one layer are independent of each other.
set(renderer_layers
  "io"                          # files, images, errors: no renderer vocabulary
  "scene"                       # triangles, materials, camera, light; loaders
  "raster"                      # G-buffer, DPRSM, voxels, GPU scene buffers: the frame's inputs
  "render"                      # settings, results, frame buffers, stage timing: the backends' vocabulary
  "render/cpu render/gpu"       # the two backends, each on its own
  "render/pipeline"             # a frame on either backend: rasterise, build, estimate; frames
  "cli"                         # command-line options to settings and a prepared scene (both programs)
  "app speed_vs_error tools")   # the programs

set(layer 0)
foreach(line IN LISTS renderer_layers)
  string(REPLACE " " ";" areas "${line}")
  foreach(area IN LISTS areas)
    string(MAKE_C_IDENTIFIER "${area}" id)
    set(layer_of_${id} ${layer})
  endforeach()
  math(EXPR layer "${layer} + 1")
endforeach()

# The area of a path relative to vplrender/src ("render/gpu/gpu_backend.cpp").
function(area_of rel out)
  if(rel MATCHES "^render/(pipeline|frames)\\.")
    set(${out} "render/pipeline" PARENT_SCOPE)
  elseif(rel MATCHES "^render/(cpu|gpu)/")
    set(${out} "render/${CMAKE_MATCH_1}" PARENT_SCOPE)
  elseif(rel MATCHES "^([A-Za-z0-9_]+)/")
    set(${out} "${CMAKE_MATCH_1}" PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

set(problems "")
set(checked 0)
file(GLOB_RECURSE vr_files "${ROOT}/vplrender/src/*.hpp" "${ROOT}/vplrender/src/*.cpp")
file(GLOB sve_files "${ROOT}/speed_vs_error/*.hpp" "${ROOT}/speed_vs_error/*.cpp")
foreach(file IN LISTS vr_files sve_files)
  if(file MATCHES "/speed_vs_error/[^/]+$")
    set(area "speed_vs_error")
  else()
    file(RELATIVE_PATH rel "${ROOT}/vplrender/src" "${file}")
    area_of("${rel}" area)
  endif()
  string(MAKE_C_IDENTIFIER "${area}" aid)
  if(area STREQUAL "" OR NOT DEFINED layer_of_${aid})
    list(APPEND problems "${file}: area '${area}' is in no layer (add it to check_renderer_layers.cmake)")
    continue()
  endif()
  math(EXPR checked "${checked} + 1")
  file(STRINGS "${file}" lines)
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([A-Za-z0-9_]+/[A-Za-z0-9_/.]+)\"")
      continue()
    endif()
    area_of("${CMAKE_MATCH_1}" used)
    if(used STREQUAL area)
      continue()
    endif()
    string(MAKE_C_IDENTIFIER "${used}" uid)
    if(NOT DEFINED layer_of_${uid})
      list(APPEND problems "${file}:${n}: includes area '${used}', which is in no layer")
    elseif(NOT layer_of_${uid} LESS layer_of_${aid})
      set(p "${file}:${n}: ${area} (layer ${layer_of_${aid}}) includes ${used}")
      list(APPEND problems "${p} (layer ${layer_of_${uid}}), an area may include only lower layers")
    endif()
  endforeach()
endforeach()

if(problems)
  foreach(p IN LISTS problems)
    message("LAYER VIOLATION: ${p}")
  endforeach()
  message(FATAL_ERROR "includes cross the renderer's layers upward (docs/renderer.md, Source layout)")
endif()
if(checked EQUAL 0)
  message(FATAL_ERROR "check_renderer_layers.cmake found no file under ${ROOT}")
endif()
message(STATUS "renderer layers OK: ${checked} files")
