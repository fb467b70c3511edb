# SPDX-License-Identifier: MIT
# A portability lint for every shader source of the project (the pack, vplrender's kernels):
#   cmake -DDIRS="<dir>;<dir>..." -P glsl_restrict_arguments.cmake
# NVIDIA's GLSL compiler (seen with driver 580) refuses a struct-typed element of a `restrict`
# buffer as a function argument, `f(records[i])`: error C1317, "qualified actual parameter #1
# cannot be converted to less qualified parameter". The GLSL 4.30 spec allows it and Mesa and
# glslang accept it, so nothing else in CI would notice; every estimate kernel once failed to
# compile on NVIDIA this way. The fix is a local copy first: `T r = records[i]; f(r);`.
# The lint collects the struct-typed members of every `restrict` buffer block (members of the
# basic types are passed by value everywhere without trouble) and reports each place where one
# of them is an argument, as `(name[...])`, `(name[...],`, `, name)` and so on. It is a lint, not
# a parser: an index with nested brackets is not looked into. Prints every finding, then fails if
# there was one.
if(NOT DIRS)
  message(FATAL_ERROR "glsl_restrict_arguments.cmake needs -DDIRS=<dir>[;<dir>...]")
endif()
set(files "")
foreach(dir IN LISTS DIRS)
  file(GLOB_RECURSE found "${dir}/*.glsl" "${dir}/*.comp" "${dir}/*.h" "${dir}/*.vert" "${dir}/*.frag")
  list(APPEND files ${found})
endforeach()
if(NOT files)
  message(FATAL_ERROR "glsl_restrict_arguments: no shader sources under ${DIRS}")
endif()

# Sources with ';', '[' and ']' replaced (CMake lists and regexes would trip over them) and line
# comments removed.
function(read_source path out)
  file(READ "${path}" s)
  string(REPLACE ";" "@S@" s "${s}")
  string(REPLACE "[" "@L@" s "${s}")
  string(REPLACE "]" "@R@" s "${s}")
  string(REGEX REPLACE "//[^\n]*" "" s "${s}")
  set(${out} "${s}" PARENT_SCOPE)
endfunction()

set(basic "^(bool|int|uint|float|double|[biud]?vec[234]|d?mat[234](x[234])?)$")
set(names "")
foreach(path IN LISTS files)
  read_source("${path}" s)
  string(REGEX MATCHALL "restrict[^{}@]*buffer[ \t\n]+[A-Za-z0-9_]+[ \t\n]*{[^}]*}" blocks "${s}")
  foreach(block IN LISTS blocks)
    string(REGEX REPLACE "^[^{]*{" "" body "${block}")
    string(REPLACE "}" "" body "${body}")
    string(REPLACE "@S@" ";" decls "${body}")
    foreach(decl IN LISTS decls)
      string(STRIP "${decl}" decl)
      if(decl MATCHES "^([A-Za-z_][A-Za-z0-9_]*)[ \t\n]+([A-Za-z_][A-Za-z0-9_]*)")
        set(type "${CMAKE_MATCH_1}")
        set(name "${CMAKE_MATCH_2}")  # saved: the next MATCHES resets CMAKE_MATCH_*
        if(NOT type MATCHES "${basic}")
          list(APPEND names "${name}")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()
list(REMOVE_DUPLICATES names)

set(problems 0)
foreach(path IN LISTS files)
  read_source("${path}" s)
  foreach(name IN LISTS names)
    string(REGEX MATCHALL "[(,][ \t\n]*${name}[ \t\n]*(@L@[^@]*@R@)?[ \t\n]*[),]" hits "${s}")
    foreach(hit IN LISTS hits)
      string(FIND "${s}" "${hit}" at)
      string(SUBSTRING "${s}" 0 ${at} before)
      string(REGEX REPLACE "[^\n]" "" newlines "${before}")
      string(LENGTH "${newlines}" line)
      math(EXPR line "${line} + 1")
      string(REPLACE "@L@" "[" shown "${hit}")
      string(REPLACE "@R@" "]" shown "${shown}")
      message("${path}:${line}: `${name}` (a struct in a restrict buffer) passed as an argument: "
              "'${shown}'; copy it to a local first (NVIDIA: error C1317)")
      math(EXPR problems "${problems} + 1")
    endforeach()
  endforeach()
endforeach()
list(LENGTH files n_files)
list(LENGTH names n_names)
if(problems GREATER 0)
  message(FATAL_ERROR "glsl_restrict_arguments: ${problems} finding(s) in ${n_files} files")
endif()
message("glsl_restrict_arguments: ${n_files} files, ${n_names} struct-typed restrict buffer members, none passed as an argument")
