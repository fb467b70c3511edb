# Checks the written rules of the GLSL pack (docs/glsl.md) on one include file:
#   cmake -DFILE=<glsl/vplkit/.../x.glsl> -DREL=<vplkit/.../x.glsl> -P glsl_rules.cmake
#  - no #version (the including shader chooses it);
#  - guarded: the first directive is `#ifndef VPLKIT_<PATH>_GLSL` (vplkit/core/constants.glsl ->
#    VPLKIT_CORE_CONSTANTS_GLSL), the next one `#define` of the same name, the last one #endif;
#  - no layout bindings (`binding =`): the host chooses them;
#  - every name declared at column 0 (functions, constants, structs, macros) starts with
#    vplkit_ / VPLKIT_. The pack writes top-level declarations at column 0, so this catches a
#    forgotten prefix; it is a lint, not a parser.
# Prints every violation, then fails if there was one.
if(NOT FILE OR NOT REL)
  message(FATAL_ERROR "glsl_rules.cmake needs -DFILE=... and -DREL=...")
endif()
# One list element per line: ';' and brackets would split or glue CMake list elements, and no
# rule below looks at them, so they are replaced first.
file(READ "${FILE}" content)
string(REPLACE ";" " SEMICOLON " content "${content}")
string(REPLACE "[" " LBRACKET " content "${content}")
string(REPLACE "]" " RBRACKET " content "${content}")
string(REPLACE "\\" " BACKSLASH " content "${content}")
string(REPLACE "\r" "" content "${content}")
string(REPLACE "\n" ";" lines "${content}")
string(REGEX REPLACE "\\.glsl$" "" guard "${REL}")
string(TOUPPER "${guard}" guard)
string(REGEX REPLACE "[^A-Z0-9]" "_" guard "${guard}_GLSL")

set(problems "")
set(directives "")
set(in_comment FALSE)
set(n 0)
foreach(line IN LISTS lines)
  math(EXPR n "${n} + 1")
  # Drop block comments (possibly spanning lines) and line comments before looking.
  set(text "${line}")
  if(in_comment)
    string(FIND "${text}" "*/" close)
    if(close EQUAL -1)
      continue()
    endif()
    math(EXPR close "${close} + 2")
    string(SUBSTRING "${text}" ${close} -1 text)
    set(in_comment FALSE)
  endif()
  string(REGEX REPLACE "/\\*.*\\*/" "" text "${text}")
  string(FIND "${text}" "/*" open)
  if(NOT open EQUAL -1)
    string(SUBSTRING "${text}" 0 ${open} text)
    set(in_comment TRUE)
  endif()
  string(REGEX REPLACE "//.*$" "" text "${text}")

  if(text MATCHES "^[ \t]*#[ \t]*([a-z]+)[ \t]*([A-Za-z0-9_]*)")
    set(directive "${CMAKE_MATCH_1}")
    set(macro "${CMAKE_MATCH_2}")
    list(APPEND directives "${directive} ${macro}")
    if(directive STREQUAL "version")
      list(APPEND problems "${REL}:${n}: #version in an include file")
    endif()
    if(directive STREQUAL "define" AND NOT macro MATCHES "^(VPLKIT_|vplkit_)")
      list(APPEND problems "${REL}:${n}: macro ${macro} lacks the VPLKIT_ prefix")
    endif()
    continue()
  endif()
  if(text MATCHES "binding[ \t]*=")
    list(APPEND problems "${REL}:${n}: layout binding in an include file (the host chooses bindings)")
  endif()
  # Column-0 declarations: [const|highp|...] type name  /  struct name
  if(text MATCHES "^(const[ \t]+|highp[ \t]+|mediump[ \t]+|lowp[ \t]+|precise[ \t]+)*([A-Za-z_][A-Za-z0-9_]*)[ \t]+([A-Za-z_][A-Za-z0-9_]*)")
    set(kind "${CMAKE_MATCH_2}")
    set(name "${CMAKE_MATCH_3}")
    if(NOT kind MATCHES "^(return|else|layout|in|out|inout|uniform|buffer|shared)$"
       AND NOT name MATCHES "^(vplkit_|VPLKIT_)")
      list(APPEND problems "${REL}:${n}: top-level name ${name} lacks the vplkit_ prefix")
    endif()
  endif()
endforeach()

list(LENGTH directives count)
if(count LESS 3)
  list(APPEND problems "${REL}: no include guard (#ifndef ${guard} / #define ${guard} ... #endif)")
else()
  list(GET directives 0 first)
  list(GET directives 1 second)
  list(GET directives -1 last)
  if(NOT first STREQUAL "ifndef ${guard}" OR NOT second STREQUAL "define ${guard}")
    list(APPEND problems "${REL}: must open with #ifndef ${guard} / #define ${guard} (found '#${first}', '#${second}')")
  endif()
  if(NOT last MATCHES "^endif")
    list(APPEND problems "${REL}: the include guard's #endif must be the last directive")
  endif()
endif()

if(problems)
  foreach(p IN LISTS problems)
    message("RULE VIOLATION: ${p}")
  endforeach()
  message(FATAL_ERROR "${REL} breaks the GLSL pack rules (see docs/glsl.md)")
endif()
message(STATUS "${REL}: pack rules OK (guard ${guard})")
