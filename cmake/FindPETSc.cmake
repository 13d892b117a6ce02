# FindPETSc: PETSc through its pkg-config file (PETSc.pc or petsc.pc).
#
# Where it looks:
#   - PETSC_DIR and PETSC_ARCH (CMake variables, else the environment): the
#     pkg-config file of ${PETSC_DIR}/${PETSC_ARCH}/lib/pkgconfig (a PETSc
#     built in its source tree), else of ${PETSC_DIR}/lib/pkgconfig (a
#     prefix install, PETSC_ARCH empty or unused).  PETSc must then come from
#     there: a PETSC_DIR without the file is an error, never a silent fallback.
#   - without PETSC_DIR: pkg-config's own search (PKG_CONFIG_PATH, the
#     system directories, and CMAKE_PREFIX_PATH).
# A PETSC_DIR taken from the environment is kept in the cache, so that a
# later configure (without the module loaded) finds the same PETSc.
#
# Defines the imported target PETSc::PETSc and PETSc_FOUND, PETSc_VERSION,
# PETSc_PC_FILE (the pkg-config file used), PETSc_ORIGIN (how it was found).
# find_package(PETSc 3.18) checks the version.
find_package(PkgConfig QUIET)

if(NOT PETSC_DIR AND DEFINED ENV{PETSC_DIR} AND NOT "$ENV{PETSC_DIR}" STREQUAL "")
  set(PETSC_DIR "$ENV{PETSC_DIR}" CACHE PATH "PETSc's PETSC_DIR (empty: pkg-config's search)")
  if(NOT PETSC_ARCH AND DEFINED ENV{PETSC_ARCH})
    set(PETSC_ARCH "$ENV{PETSC_ARCH}" CACHE STRING "PETSc's PETSC_ARCH")
  endif()
elseif(PETSC_DIR AND DEFINED ENV{PETSC_DIR} AND NOT "$ENV{PETSC_DIR}" STREQUAL ""
       AND NOT "$ENV{PETSC_DIR}" STREQUAL "${PETSC_DIR}")
  message(WARNING "PETSC_DIR in the environment ($ENV{PETSC_DIR}) differs from the "
                  "CMake variable (${PETSC_DIR}); using the CMake variable "
                  "(pass -DPETSC_DIR=... to change it).")
endif()

set(_petsc_pc_dir "")
set(PETSc_ORIGIN "")
set(PETSc_PC_FILE "")
set(PETSc_NOT_FOUND_MESSAGE "")
if(PETSC_DIR)
  set(_petsc_candidates "${PETSC_DIR}/lib/pkgconfig")
  if(PETSC_ARCH)
    list(PREPEND _petsc_candidates "${PETSC_DIR}/${PETSC_ARCH}/lib/pkgconfig")
  endif()
  foreach(_dir IN LISTS _petsc_candidates)
    if(EXISTS "${_dir}/PETSc.pc" OR EXISTS "${_dir}/petsc.pc")
      set(_petsc_pc_dir "${_dir}")
      break()
    endif()
  endforeach()
  if(NOT _petsc_pc_dir)
    string(REPLACE ";" " or " _petsc_looked "${_petsc_candidates}")
    string(CONCAT PETSc_NOT_FOUND_MESSAGE
        "PETSC_DIR='${PETSC_DIR}' PETSC_ARCH='${PETSC_ARCH}': no PETSc.pc or petsc.pc in "
        "${_petsc_looked}. Set PETSC_DIR (and PETSC_ARCH for a PETSc built in its "
        "source tree) to a PETSc build, or leave PETSC_DIR empty to use pkg-config's search.")
  endif()
  set(PETSc_ORIGIN "found through PETSC_DIR=${PETSC_DIR}")
  if(PETSC_ARCH)
    string(APPEND PETSc_ORIGIN " PETSC_ARCH=${PETSC_ARCH}")
  endif()
else()
  set(PETSc_ORIGIN "found by pkg-config's search (PETSC_DIR not set)")
endif()

if(NOT PKG_CONFIG_FOUND)
  set(PETSc_NOT_FOUND_MESSAGE "pkg-config is needed to read PETSc's PETSc.pc")
elseif(NOT PETSc_NOT_FOUND_MESSAGE)
  if(_petsc_pc_dir)
    set(_petsc_saved_path "$ENV{PKG_CONFIG_PATH}")
    if(_petsc_saved_path)
      set(ENV{PKG_CONFIG_PATH} "${_petsc_pc_dir}:${_petsc_saved_path}")
    else()
      set(ENV{PKG_CONFIG_PATH} "${_petsc_pc_dir}")
    endif()
  endif()
  # Asked again at every configure (pkg-config's answer is cached otherwise,
  # and would not follow a new PETSC_DIR).
  unset(__pkg_config_checked_PETSC CACHE)
  pkg_search_module(PETSC QUIET IMPORTED_TARGET PETSc petsc)
  if(PETSC_FOUND)
    pkg_get_variable(_petsc_found_dir ${PETSC_MODULE_NAME} pcfiledir)
  endif()
  if(_petsc_pc_dir)
    set(ENV{PKG_CONFIG_PATH} "${_petsc_saved_path}")
  endif()
  if(PETSC_FOUND)
    set(PETSc_VERSION "${PETSC_VERSION}")
    set(_petsc_got "${_petsc_found_dir}")
    set(_petsc_want "${_petsc_found_dir}")
    if(_petsc_pc_dir)
      file(REAL_PATH "${_petsc_pc_dir}" _petsc_want)
      file(REAL_PATH "${_petsc_found_dir}" _petsc_got)
    endif()
    if(_petsc_want STREQUAL _petsc_got)
      set(PETSc_PC_FILE "${_petsc_found_dir}/${PETSC_MODULE_NAME}.pc")
    else()
      string(CONCAT PETSc_NOT_FOUND_MESSAGE "pkg-config found PETSc in ${_petsc_found_dir}, "
                                  "not in ${_petsc_pc_dir} (PETSC_DIR)")
    endif()
  else()
    string(CONCAT PETSc_NOT_FOUND_MESSAGE
        "pkg-config finds no PETSc.pc or petsc.pc (PKG_CONFIG_PATH='$ENV{PKG_CONFIG_PATH}', "
        "PKG_CONFIG_LIBDIR='$ENV{PKG_CONFIG_LIBDIR}'). Set PETSC_DIR "
        "(and PETSC_ARCH) to a PETSc build, or add its lib/pkgconfig to PKG_CONFIG_PATH.")
  endif()
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(PETSc
  REQUIRED_VARS PETSc_PC_FILE
  VERSION_VAR PETSc_VERSION
  REASON_FAILURE_MESSAGE "${PETSc_NOT_FOUND_MESSAGE}")
if(PETSc_FOUND AND NOT TARGET PETSc::PETSc)
  add_library(PETSc::PETSc INTERFACE IMPORTED)
  target_link_libraries(PETSc::PETSc INTERFACE PkgConfig::PETSC)
endif()
unset(_petsc_candidates)
unset(_petsc_pc_dir)
unset(_petsc_got)
unset(_petsc_want)
