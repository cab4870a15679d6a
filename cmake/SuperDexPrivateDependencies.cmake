# The private dependencies of the SuperDex library, as the imported targets
# it links PRIVATE:
#
#   SuperDex::cholmod   CHOLMOD and SuiteSparse_config (no CMake package in
#                       Debian's libsuitesparse-dev: found by name)
#   SuperDex::metis     METIS (libmetis-dev, found by name)
#   TBB::tbb            oneTBB's CMake package (libtbb-dev)
#   SuperDex::petsc     PETSc from pkg-config (petsc-dev, with Open MPI) and
#                       MPI's C library from FindMPI
#
# One piece of code for two users, so that they cannot drift apart:
#   - the build: cmake/SuperDexDependencies.cmake includes it;
#   - an installed static package: a static libsuperdex.a leaves these
#     libraries to the consumer's link step (SuperDexTargets.cmake lists
#     them as $<LINK_ONLY:...>), so SuperDexConfig.cmake includes the copy
#     installed next to it, with SUPERDEX_DEPENDENCIES_FOR_PACKAGE set.
#
# Every target is created only where it does not exist yet (the consumer may
# have found TBB or MPI itself, or called find_package(SuperDex) twice). A
# missing dependency is a fatal error in the build (as a REQUIRED find would
# be); in the package, CMake packages are found with find_dependency and any
# missing piece sets SuperDex_FOUND to FALSE with SuperDex_NOT_FOUND_MESSAGE
# and ends this file (the config then returns).

# find_package in the build (REQUIRED), find_dependency in the package
macro(_superdex_find_package name)
  if(SUPERDEX_DEPENDENCIES_FOR_PACKAGE)
    find_dependency(${name} ${ARGN})
  else()
    find_package(${name} ${ARGN} REQUIRED)
  endif()
endmacro()

# a dependency without a CMake package is missing: fatal in the build; in the
# package, SuperDex is not found (a macro: its return() ends this file)
macro(_superdex_dependency_missing what)
  set(_superdex_missing_text
    "SuperDex needs ${what} (${ARGN})")
  if(SUPERDEX_DEPENDENCIES_FOR_PACKAGE)
    set(SuperDex_FOUND FALSE)
    set(SuperDex_NOT_FOUND_MESSAGE
      "this SuperDex is a static library: its consumers link its private dependencies. ${_superdex_missing_text}")
    unset(_superdex_missing_text)
    return()
  else()
    message(FATAL_ERROR "${_superdex_missing_text}")
  endif()
endmacro()

# CHOLMOD (SuiteSparse)
if(NOT TARGET SuperDex::cholmod)
  find_path(SuperDex_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  find_library(SuperDex_CHOLMOD_LIBRARY cholmod)
  find_library(SuperDex_SUITESPARSECONFIG_LIBRARY suitesparseconfig)
  mark_as_advanced(SuperDex_CHOLMOD_INCLUDE_DIR SuperDex_CHOLMOD_LIBRARY
                   SuperDex_SUITESPARSECONFIG_LIBRARY)
  if(NOT SuperDex_CHOLMOD_INCLUDE_DIR OR NOT SuperDex_CHOLMOD_LIBRARY
     OR NOT SuperDex_SUITESPARSECONFIG_LIBRARY)
    _superdex_dependency_missing("CHOLMOD: cholmod.h, libcholmod and libsuitesparseconfig"
      "Debian: libsuitesparse-dev")
  endif()
  add_library(SuperDex::cholmod INTERFACE IMPORTED)
  target_include_directories(SuperDex::cholmod SYSTEM INTERFACE ${SuperDex_CHOLMOD_INCLUDE_DIR})
  target_link_libraries(SuperDex::cholmod INTERFACE
    ${SuperDex_CHOLMOD_LIBRARY} ${SuperDex_SUITESPARSECONFIG_LIBRARY})
endif()

# METIS
if(NOT TARGET SuperDex::metis)
  find_path(SuperDex_METIS_INCLUDE_DIR metis.h)
  find_library(SuperDex_METIS_LIBRARY metis)
  mark_as_advanced(SuperDex_METIS_INCLUDE_DIR SuperDex_METIS_LIBRARY)
  if(NOT SuperDex_METIS_INCLUDE_DIR OR NOT SuperDex_METIS_LIBRARY)
    _superdex_dependency_missing("METIS: metis.h and libmetis" "Debian: libmetis-dev")
  endif()
  add_library(SuperDex::metis INTERFACE IMPORTED)
  target_include_directories(SuperDex::metis SYSTEM INTERFACE ${SuperDex_METIS_INCLUDE_DIR})
  target_link_libraries(SuperDex::metis INTERFACE ${SuperDex_METIS_LIBRARY})
endif()

# oneTBB: the task arena of the parallel loops (core/parallel.h)
if(NOT TARGET TBB::tbb)
  _superdex_find_package(TBB CONFIG)
endif()

# PETSc (Debian's petsc-dev, with Open MPI): pkg-config gives PETSc's own
# include directory and library, FindMPI the MPI library SuperDex calls
# (C bindings only). FindMPI finds a language's MPI only where that language
# is enabled: the build enables C; a consumer enabling only C++ gets the same
# MPI library from the CXX component, without the C++ bindings.
if(NOT TARGET SuperDex::petsc)
  if(NOT TARGET PkgConfig::SuperDex_PETSC)
    _superdex_find_package(PkgConfig)
    pkg_check_modules(SuperDex_PETSC QUIET IMPORTED_TARGET PETSc)
    if(NOT SuperDex_PETSC_FOUND)
      _superdex_dependency_missing("PETSc: PETSc.pc for pkg-config, PETSc's headers and library"
        "Debian: petsc-dev")
    endif()
  endif()
  if(CMAKE_C_COMPILER_LOADED)
    set(_superdex_mpi_language C)
  else()
    set(_superdex_mpi_language CXX)
    if(NOT DEFINED MPI_CXX_SKIP_MPICXX)
      set(MPI_CXX_SKIP_MPICXX TRUE)
      set(_superdex_unset_skip_mpicxx TRUE)
    endif()
  endif()
  if(NOT TARGET MPI::MPI_${_superdex_mpi_language})
    _superdex_find_package(MPI COMPONENTS ${_superdex_mpi_language})
  endif()
  if(_superdex_unset_skip_mpicxx)
    unset(MPI_CXX_SKIP_MPICXX)
    unset(_superdex_unset_skip_mpicxx)
  endif()
  add_library(SuperDex::petsc INTERFACE IMPORTED)
  target_link_libraries(SuperDex::petsc INTERFACE
    PkgConfig::SuperDex_PETSC MPI::MPI_${_superdex_mpi_language})
  # C bindings only: no MPI C++ library to link
  target_compile_definitions(SuperDex::petsc INTERFACE OMPI_SKIP_MPICXX=1 MPICH_SKIP_MPICXX=1)
  unset(_superdex_mpi_language)
endif()
