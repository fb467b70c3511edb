# SPDX-License-Identifier: MIT
# Writes OUTPUT: one `VPLKIT_EPOXY_GL(glFoo)` line per GL dispatch pointer that epoxy declares in
# HEADER (epoxy/gl_generated.h). Run at configure time; rewrites OUTPUT only when it changes.
#   cmake -DHEADER=<gl_generated.h> -DOUTPUT=<file.inc> -P epoxy_gl_entries.cmake
if(NOT HEADER OR NOT OUTPUT)
  message(FATAL_ERROR "epoxy_gl_entries.cmake needs -DHEADER=... and -DOUTPUT=...")
endif()
file(STRINGS "${HEADER}" lines REGEX "^EPOXY_PUBLIC .*\\(EPOXY_CALLSPEC \\*epoxy_gl[A-Za-z0-9_]+\\)")
set(text "// GENERATED from ${HEADER} by support/headless_gl/epoxy_gl_entries.cmake. Do not edit.\n")
set(count 0)
foreach(line IN LISTS lines)
  string(REGEX MATCH "\\*epoxy_(gl[A-Za-z0-9_]+)\\)" _ "${line}")
  string(APPEND text "VPLKIT_EPOXY_GL(${CMAKE_MATCH_1})\n")
  math(EXPR count "${count} + 1")
endforeach()
if(count LESS 100)
  message(FATAL_ERROR "epoxy_gl_entries.cmake: found only ${count} dispatch pointers in ${HEADER}; "
                      "epoxy's header layout changed, update the regular expression")
endif()
set(old "")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
