# Finds the Debian-packaged dependencies and wraps the ones without a CMake
# package in SuperDex:: imported targets.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(SuperDex::cholmod INTERFACE IMPORTED)
target_include_directories(SuperDex::cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(SuperDex::cholmod INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(SuperDex::metis INTERFACE IMPORTED)
target_include_directories(SuperDex::metis SYSTEM INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(SuperDex::metis INTERFACE ${METIS_LIBRARY})

# PETSc (Debian's petsc-dev, with OpenMPI): pkg-config gives PETSc's own
# include and library; MPI's headers come from FindMPI.
# oneTBB: the task arena of the parallel loops (core/parallel.h)
find_package(TBB REQUIRED CONFIG)

find_package(PkgConfig REQUIRED)
pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc)
find_package(MPI REQUIRED COMPONENTS C)
add_library(SuperDex::petsc INTERFACE IMPORTED)
target_link_libraries(SuperDex::petsc INTERFACE PkgConfig::PETSC MPI::MPI_C)
# C bindings only: no MPI C++ library to link
target_compile_definitions(SuperDex::petsc INTERFACE OMPI_SKIP_MPICXX=1 MPICH_SKIP_MPICXX=1)

# Python and pybind11 for the mochi module (SUPERDEX_BUILD_PYTHON): Debian's
# /usr/bin/python3 with python3-dev and pybind11-dev, found explicitly — the
# first python3 on PATH may be another interpreter, without numpy.
if(SUPERDEX_BUILD_PYTHON)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python with numpy and matplotlib (Debian's)")
  find_package(Python3 3.9 REQUIRED COMPONENTS Interpreter Development.Module)
  find_package(pybind11 2.6 CONFIG REQUIRED)
endif()
