# SPDX-License-Identifier: MIT
# The library's layers (docs/architecture.md): the one place that states their order.
# Checks that no header of include/vplkit and no file of the GLSL pack includes an area of a higher
# layer, nor an area of its own layer other than its own:
#   cmake -DROOTS="<dir>;<dir>" -P check_layers.cmake
# Each root holds a vplkit/ folder (include/ and glsl/ of the repository). A file's area is the
# folder below vplkit/ (include/vplkit/builders/detail/x.hpp is in `builders`); files directly in
# vplkit/ (the umbrella vplkit.hpp) may include anything. Prints every violation as
# "<file>:<line>: ...", then fails if there was one.
if(NOT ROOTS)
  message(FATAL_ERROR "check_layers.cmake needs -DROOTS=<dir>[;<dir>...]")
endif()

# Lowest layer first. Areas of one layer are independent of each other.
set(vplkit_layers
  "core glsl"                                    # vocabulary: vectors, errors, gather points; the include resolver
  "distribution paraboloid sampling visibility"  # self-contained parts, each on core only
  "mis image vpl"                                # parts built on the ones below (pdfs on sampling, ...)
  "builders"                                     # weights from a G-buffer and a DPRSM; their distributions
  "estimators")                                  # per-gather-point estimates from those distributions

set(layer 0)
foreach(line IN LISTS vplkit_layers)
  string(REPLACE " " ";" areas "${line}")
  foreach(area IN LISTS areas)
    set(layer_of_${area} ${layer})
  endforeach()
  math(EXPR layer "${layer} + 1")
endforeach()

set(problems "")
set(checked 0)
foreach(root IN LISTS ROOTS)
  file(GLOB_RECURSE files "${root}/vplkit/*.hpp" "${root}/vplkit/*.h" "${root}/vplkit/*.glsl"
                          "${root}/vplkit/*.comp")
  foreach(file IN LISTS files)
    file(RELATIVE_PATH rel "${root}/vplkit" "${file}")
    if(NOT rel MATCHES "/")
      continue()  # the umbrella header
    endif()
    string(REGEX REPLACE "/.*" "" area "${rel}")
    if(NOT DEFINED layer_of_${area})
      list(APPEND problems "${file}: area '${area}' is in no layer (add it to check_layers.cmake)")
      continue()
    endif()
    math(EXPR checked "${checked} + 1")
    file(STRINGS "${file}" lines)
    set(n 0)
    foreach(line IN LISTS lines)
      math(EXPR n "${n} + 1")
      if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*[<\"]vplkit/([A-Za-z0-9_]+)/")
        continue()
      endif()
      set(used "${CMAKE_MATCH_1}")
      if(used STREQUAL area)
        continue()
      endif()
      if(NOT DEFINED layer_of_${used})
        list(APPEND problems "${file}:${n}: includes area '${used}', which is in no layer")
      elseif(NOT layer_of_${used} LESS layer_of_${area})
        set(p "${file}:${n}: ${area} (layer ${layer_of_${area}}) includes ${used}")
        list(APPEND problems "${p} (layer ${layer_of_${used}}), an area may include only lower layers")
      endif()
    endforeach()
  endforeach()
endforeach()

if(problems)
  foreach(p IN LISTS problems)
    message("LAYER VIOLATION: ${p}")
  endforeach()
  message(FATAL_ERROR "includes cross the library's layers upward (docs/architecture.md)")
endif()
if(checked EQUAL 0)
  message(FATAL_ERROR "check_layers.cmake found no file under ${ROOTS}")
endif()
message(STATUS "layers OK: ${checked} files")
