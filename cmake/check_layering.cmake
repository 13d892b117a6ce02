# Fails when a file includes a header of a module it may not use, and when a
# module declares a dependency that none of its files includes.
#
#   cmake -DSOURCE_DIR=<repo> -DLAYERS=<build>/layers.txt [-DEXTRA=<module>:<file>]
#         [-DEXTRA_DEPENDS=<module>:<dependency>] -P check_layering.cmake
#
# LAYERS is written by lem_module() in the root CMakeLists.txt, one line per
# module: name|dependency,...  A module may use its own headers and those of
# its dependencies, transitively.  A header's module is its folder: the
# headers of include/lem/<m>/ belong to module <m>, and every header of
# include/lem must sit in a module's folder.
# Drivers (drivers/*.cpp) may use every module.  EXTRA checks one more file
# as if it were part of <module> (the test that the check catches a bad one).
# The converse: each dependency a module declares must be named by an
# include of at least one of the module's own files (sources and headers);
# one reached only through another dependency is not needed in the list.
# EXTRA_DEPENDS declares one more, lower module as a dependency of <module>
# (the test that the check catches an unused one).

cmake_minimum_required(VERSION 3.20)

file(STRINGS "${LAYERS}" lines)
set(modules "")
foreach(line IN LISTS lines)
  string(REPLACE "|" ";" parts "${line}")
  list(GET parts 0 name)
  list(LENGTH parts count)
  set(deps "")
  if(count GREATER 1)
    list(GET parts 1 deps)
    string(REPLACE "," ";" deps "${deps}")
  endif()
  list(APPEND modules ${name})
  set(deps_${name} ${deps})
  set(used_${name} "")
endforeach()
if(DEFINED EXTRA_DEPENDS)
  string(REGEX REPLACE ":.*" "" extra_module "${EXTRA_DEPENDS}")
  string(REGEX REPLACE "^[^:]*:" "" extra_dependency "${EXTRA_DEPENDS}")
  list(APPEND deps_${extra_module} ${extra_dependency})
endif()

# Everything a module may use: itself and its dependencies' closures (the
# modules are listed bottom up, so a dependency's closure is known).
foreach(m IN LISTS modules)
  set(allowed_${m} ${m})
  foreach(d IN LISTS deps_${m})
    list(APPEND allowed_${m} ${allowed_${d}})
  endforeach()
  list(REMOVE_DUPLICATES allowed_${m})
endforeach()
set(allowed_drivers ${modules})

function(owner_of header out)
  if(header MATCHES "^([a-z_]+)/[^/]+$" AND CMAKE_MATCH_1 IN_LIST modules)
    set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

set(problems "")
function(check_file module path)
  file(STRINGS "${path}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"lem/[^\"]+\"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE ".*\"lem/([^\"]+)\".*" "\\1" header "${line}")
    owner_of(${header} owner)
    file(RELATIVE_PATH shown "${SOURCE_DIR}" "${path}")
    if(owner STREQUAL "")
      list(APPEND problems "${shown} includes lem/${header}, which belongs to no module")
    elseif(NOT owner IN_LIST allowed_${module})
      list(APPEND problems "${shown} (module ${module}) includes lem/${header} \
(module ${owner}), which ${module} may not use")
    else()
      list(APPEND used_${module} ${owner})
    endif()
  endforeach()
  set(problems "${problems}" PARENT_SCOPE)
  set(used_${module} "${used_${module}}" PARENT_SCOPE)
endfunction()

# Headers: each one checked as part of its module; none left unowned.
file(GLOB_RECURSE headers RELATIVE "${SOURCE_DIR}/include/lem" "${SOURCE_DIR}/include/lem/*.hpp")
foreach(h IN LISTS headers)
  owner_of(${h} owner)
  if(owner STREQUAL "")
    list(APPEND problems "include/lem/${h} is in no module's folder (move it to include/lem/<module>/)")
  else()
    check_file(${owner} "${SOURCE_DIR}/include/lem/${h}")
  endif()
endforeach()
foreach(m IN LISTS modules)
  file(GLOB_RECURSE sources "${SOURCE_DIR}/src/${m}/*.cpp" "${SOURCE_DIR}/src/${m}/*.hpp")
  foreach(f IN LISTS sources)
    check_file(${m} "${f}")
  endforeach()
endforeach()
file(GLOB drivers "${SOURCE_DIR}/drivers/*.cpp")
foreach(f IN LISTS drivers)
  check_file(drivers "${f}")
endforeach()
# A directory of src/ that is no module would escape the check.
file(GLOB dirs LIST_DIRECTORIES true RELATIVE "${SOURCE_DIR}/src" "${SOURCE_DIR}/src/*")
foreach(d IN LISTS dirs)
  if(IS_DIRECTORY "${SOURCE_DIR}/src/${d}" AND NOT d IN_LIST modules)
    list(APPEND problems "src/${d} is not a module (add a lem_module for it)")
  endif()
endforeach()
if(DEFINED EXTRA)
  string(REGEX REPLACE ":.*" "" extra_module "${EXTRA}")
  string(REGEX REPLACE "^[^:]*:" "" extra_file "${EXTRA}")
  check_file(${extra_module} "${extra_file}")
endif()

# A declared dependency that no file of the module names is one the link
# carries for nothing (or one that another dependency already brings).
foreach(m IN LISTS modules)
  foreach(d IN LISTS deps_${m})
    if(NOT d IN_LIST used_${m})
      list(APPEND problems "module ${m} declares the dependency ${d} in lem_module(), \
but none of its files includes a lem/${d}/ header (remove it from the DEPENDS list)")
    endif()
  endforeach()
endforeach()

if(problems)
  list(LENGTH problems count)
  string(REPLACE ";" "\n  " text "${problems}")
  message(FATAL_ERROR "layering: ${count} problem(s) with the layering:\n  ${text}")
endif()
list(LENGTH modules count)
message(STATUS "layering: ${count} modules, every include respects the layering "
               "and every declared dependency is included")
