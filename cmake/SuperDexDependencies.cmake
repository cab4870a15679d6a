# Finds the Debian-packaged dependencies and wraps the ones without a CMake
# package in SuperDex:: imported targets.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)

# CHOLMOD, METIS, oneTBB, PETSc and MPI: the library's private dependencies,
# in a file of their own that the installed package of a static build
# includes too
include(${CMAKE_CURRENT_LIST_DIR}/SuperDexPrivateDependencies.cmake)

# Python and pybind11 for the mochi module (SUPERDEX_BUILD_PYTHON): Debian's
# /usr/bin/python3 with python3-dev and pybind11-dev, found explicitly — the
# first python3 on PATH may be another interpreter, without numpy.
if(SUPERDEX_BUILD_PYTHON)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python with numpy and matplotlib (Debian's)")
  find_package(Python3 3.9 REQUIRED COMPONENTS Interpreter Development.Module)
  find_package(pybind11 2.6 CONFIG REQUIRED)
endif()
