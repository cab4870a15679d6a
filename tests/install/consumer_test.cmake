# Script run by the install tests (cmake -P), tests/install/CMakeLists.txt:
#
#   install_and_consume         MODE=install: installs an existing build tree
#   install_static_and_consume  MODE=static: installs the static build that
#                               add_constraint_type made (SUPERDEX_BINARY_DIR), or
#                               configures the source tree into a scratch build
#                               with BUILD_SHARED_LIBS=OFF, builds only the
#                               library and installs it
#
# then, for both, checks the installed package and configures, builds and runs
# examples/consumer against it with find_package(SuperDex) three times: with
# the default flags, with -DCMAKE_CXX_FLAGS=-march=x86-64 (baseline SSE2,
# unlike the library's -march=native) and with -march=native; the consumer
# checks values and frees across the boundary, so this shows that the package
# imposes no -march and that both sides agree on Eigen's layout whatever
# instruction set each is compiled for.
#
# Inputs:
#   MODE                 install (default) or static
#   TEST_NAME            name in the messages (default install_and_consume)
#   SUPERDEX_BINARY_DIR  the SuperDex build tree to install (MODE=static: a
#                        static one; unset, one is built from the source tree)
#   SUPERDEX_SOURCE_DIR  MODE=static without SUPERDEX_BINARY_DIR: the SuperDex
#                        source tree to configure
#   GENERATOR            MODE=static: CMake generator of the scratch build
#                        (default: CMake's)
#   SUPERDEX_NATIVE      MODE=static: passed through (default: the option's)
#   CONSUMER_SOURCE_DIR  examples/consumer
#   WORK_DIR             scratch folder (wiped first): prefix/, consumer-*/ and,
#                        MODE=static, superdex/ (the library's build)
#   BUILD_TYPE           configuration to build, install and consume
#   CXX_COMPILER, C_COMPILER  the compilers SuperDex was built with
#   CXX_COMPILER_LAUNCHER  (optional) CMAKE_CXX_COMPILER_LAUNCHER of the
#                        outer build, list items separated by '|'
#   PYTHON_EXECUTABLE, PYTHON_INSTALL_DIR  (optional, MODE=install) the
#                        interpreter and the module folder relative to the
#                        prefix: when set, the installed mochi is imported from
#                        the prefix and steps a scene with the prefix's
#                        libsuperdex
# Environment, read when the test runs:
#   SUPERDEX_BUILD_JOBS  parallel jobs of every build (cmake --build -j N);
#                        unset: cmake --build's default
cmake_minimum_required(VERSION 3.20)

if(NOT MODE)
  set(MODE install)
endif()
if(NOT TEST_NAME)
  set(TEST_NAME install_and_consume)
endif()
if(MODE STREQUAL "install")
  set(required SUPERDEX_BINARY_DIR)
elseif(MODE STREQUAL "static" AND SUPERDEX_BINARY_DIR)
  set(required SUPERDEX_BINARY_DIR)
elseif(MODE STREQUAL "static")
  set(required SUPERDEX_SOURCE_DIR)
else()
  message(FATAL_ERROR "consumer_test.cmake: MODE must be install or static, got '${MODE}'")
endif()
foreach(var IN ITEMS ${required} CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer_test.cmake: ${var} is not set")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

set(jobs_arg)
if(DEFINED ENV{SUPERDEX_BUILD_JOBS} AND NOT "$ENV{SUPERDEX_BUILD_JOBS}" STREQUAL "")
  set(jobs_arg -j $ENV{SUPERDEX_BUILD_JOBS})
endif()
# the outer build's compilers and launcher, for every configure below
set(compiler_args)
if(CXX_COMPILER)
  list(APPEND compiler_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(CXX_COMPILER_LAUNCHER)
  string(REPLACE "|" "\\;" launcher "${CXX_COMPILER_LAUNCHER}")
  list(APPEND compiler_args "-DCMAKE_CXX_COMPILER_LAUNCHER=${launcher}")
endif()

# runs one stage, its output shown as it comes; a non-zero exit (or a crash)
# fails the test with the stage's name. OUTPUT <var> also returns the output.
function(run_stage name)
  cmake_parse_arguments(PARSE_ARGV 1 stage "" "OUTPUT" "COMMAND")
  message(STATUS "${TEST_NAME}: ${name}")
  string(TIMESTAMP start "%s")
  execute_process(COMMAND ${stage_COMMAND} RESULT_VARIABLE rc
    OUTPUT_VARIABLE out ERROR_VARIABLE out ECHO_OUTPUT_VARIABLE ECHO_ERROR_VARIABLE)
  string(TIMESTAMP end "%s")
  math(EXPR seconds "${end} - ${start}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${TEST_NAME}: ${name} failed (${rc})")
  endif()
  message(STATUS "${TEST_NAME}: ${name}: done in ${seconds} s")
  if(stage_OUTPUT)
    set(${stage_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()

# a failed check of the package: reported, the test fails at the end, and the
# stages after it still run (a consumer's crash tells more than the check)
function(check_failed)
  string(JOIN "" text ${ARGN})
  message(SEND_ERROR "${TEST_NAME}: ${text}")
endfunction()

# 1. the package: install an existing build (in the build type it was made
# with: the exported targets of a None build name only that configuration),
# or build a static one here
if(SUPERDEX_BINARY_DIR)
  set(install_config ${BUILD_TYPE})
  file(STRINGS ${SUPERDEX_BINARY_DIR}/CMakeCache.txt cached_type REGEX "^CMAKE_BUILD_TYPE:")
  string(REGEX REPLACE "^CMAKE_BUILD_TYPE:[A-Z]*=" "" cached_type "${cached_type}")
  if(cached_type)
    set(install_config ${cached_type})
  endif()
  run_stage("install into ${prefix}" COMMAND
    ${CMAKE_COMMAND} --install ${SUPERDEX_BINARY_DIR} --prefix ${prefix} --config ${install_config})
else()
  set(superdex_build ${WORK_DIR}/superdex)
  set(generator_args)
  if(GENERATOR)
    set(generator_args -G ${GENERATOR})
  endif()
  set(library_args)
  if(DEFINED SUPERDEX_NATIVE AND NOT SUPERDEX_NATIVE STREQUAL "")
    list(APPEND library_args -DSUPERDEX_NATIVE=${SUPERDEX_NATIVE})
  endif()
  if(C_COMPILER)
    list(APPEND library_args -DCMAKE_C_COMPILER=${C_COMPILER})
  endif()
  # build type None (neither optimized nor with debug information): the test
  # checks what a static package brings to a consumer's link, not speed, and
  # an unoptimized library compiles in a fraction of the time
  run_stage("configure ${SUPERDEX_SOURCE_DIR} (static) into ${superdex_build}" COMMAND
    ${CMAKE_COMMAND} -S ${SUPERDEX_SOURCE_DIR} -B ${superdex_build} ${generator_args}
      -DCMAKE_BUILD_TYPE=None
      -DBUILD_SHARED_LIBS=OFF
      -DSUPERDEX_BUILD_TESTS=OFF -DSUPERDEX_BUILD_EXAMPLES=OFF
      -DSUPERDEX_BUILD_PERF=OFF -DSUPERDEX_BUILD_PYTHON=OFF
      ${library_args} ${compiler_args})
  run_stage("build the static library" COMMAND
    ${CMAKE_COMMAND} --build ${superdex_build} --config None --target superdex ${jobs_arg})
  run_stage("install into ${prefix}" COMMAND
    ${CMAKE_COMMAND} --install ${superdex_build} --prefix ${prefix} --config None)
endif()

# 2. what the package says
file(GLOB_RECURSE targets_files ${prefix}/*/SuperDexTargets*.cmake)
if(NOT targets_files)
  message(FATAL_ERROR "${TEST_NAME}: no SuperDexTargets.cmake under ${prefix}")
endif()
file(GLOB_RECURSE config_files ${prefix}/*/SuperDexConfig.cmake)
if(NOT config_files)
  message(FATAL_ERROR "${TEST_NAME}: no SuperDexConfig.cmake under ${prefix}")
endif()
file(READ ${config_files} config_text)
string(FIND "${config_text}" "set(SuperDex_STATIC ON)" static_at)
if(MODE STREQUAL "static" AND static_at EQUAL -1)
  check_failed("${config_files} is not a static package (no 'set(SuperDex_STATIC ON)')")
endif()
file(GLOB_RECURSE shared_libraries ${prefix}/*/libsuperdex.so*)
if(MODE STREQUAL "static" AND shared_libraries)
  check_failed("a static build installed ${shared_libraries}")
endif()
set(targets_text)
foreach(file IN LISTS targets_files)
  file(READ ${file} text)
  string(APPEND targets_text "${text}")
  # the private dependencies must not leak into a shared package
  if(static_at EQUAL -1 AND text MATCHES "(cholmod|metis|suitesparse|petsc)")
    check_failed("${file} mentions '${CMAKE_MATCH_1}', a private dependency of the shared library")
  endif()
  # the library's instruction set is its own: an exported -march would
  # compile every consumer for the build host
  if(text MATCHES "[^\n]*-march[^\n]*")
    check_failed("${file} exports an instruction set: ${CMAKE_MATCH_0}")
  endif()
endforeach()
# Eigen's alignment is pinned for both sides of the boundary, whatever each
# side's -march (docs/install.md)
foreach(definition IN ITEMS EIGEN_MAX_ALIGN_BYTES=64 EIGEN_MAX_STATIC_ALIGN_BYTES=64)
  if(NOT targets_text MATCHES "INTERFACE_COMPILE_DEFINITIONS \"[^\"]*${definition}")
    check_failed("SuperDex::superdex does not export the compile definition ${definition}")
  endif()
endforeach()
file(GLOB_RECURSE headers ${prefix}/include/superdex/*.h)
foreach(header IN LISTS headers)
  file(STRINGS ${header} private_includes REGEX "#include[ \t]*[<\"](cholmod|metis|petsc)")
  if(private_includes)
    check_failed("installed header ${header} includes a private dependency: ${private_includes}")
  endif()
endforeach()
if(NOT EXISTS ${prefix}/include/superdex/core/config.h)
  check_failed("include/superdex/core/config.h was not installed")
endif()

# 3. examples/consumer against the prefix only (no package registry): with
#    the default flags, with the baseline instruction set (SSE2) and with the
#    build host's. The library is compiled for the host (SUPERDEX_NATIVE) or
#    for the compiler's default: either way one of these differs from it.
foreach(variant IN ITEMS default x86-64 native)
  set(build ${WORK_DIR}/consumer-${variant})
  set(flags_arg)
  if(NOT variant STREQUAL "default")
    set(flags_arg -DCMAKE_CXX_FLAGS=-march=${variant})
  endif()
  run_stage("configure examples/consumer (${variant})" COMMAND
    ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${build}
      -DCMAKE_PREFIX_PATH=${prefix}
      -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
      -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
      ${flags_arg} ${compiler_args})
  run_stage("build examples/consumer (${variant})" COMMAND
    ${CMAKE_COMMAND} --build ${build} --config ${BUILD_TYPE} ${jobs_arg})
  find_program(consumer_${variant} superdex_consumer PATHS ${build} ${build}/${BUILD_TYPE}
    NO_DEFAULT_PATH REQUIRED)
  run_stage("run ${consumer_${variant}}" COMMAND ${consumer_${variant}} OUTPUT run_output)
  # the baseline build must really be one: nothing in the package may have
  # raised its instruction set
  if(variant STREQUAL "x86-64" AND NOT run_output MATCHES "consumer instruction set: SSE2,")
    check_failed("the consumer built with -march=x86-64 was not compiled for SSE2 alone "
      "(something added another -march)")
  endif()
endforeach()

# 4. the installed Python module: imported from the prefix alone (not the
#    build tree), it must load the prefix's libsuperdex and step a scene
if(MODE STREQUAL "install" AND PYTHON_EXECUTABLE AND PYTHON_INSTALL_DIR)
  set(site ${prefix}/${PYTHON_INSTALL_DIR})
  run_stage("import the installed mochi from ${site}" COMMAND
    ${CMAKE_COMMAND} -E env PYTHONPATH=${site} PYTHONDONTWRITEBYTECODE=1
    ${PYTHON_EXECUTABLE} -c "
import os, sys, mochi
site, prefix = os.path.realpath(sys.argv[1]), os.path.realpath(sys.argv[2])
assert os.path.realpath(mochi.__file__).startswith(site), mochi.__file__
libs = [l.split()[-1] for l in open('/proc/self/maps') if 'libsuperdex' in l]
assert libs and all(os.path.realpath(l).startswith(prefix) for l in libs), libs
scene = mochi.Scene.create()
body = scene.create_rigid_actor(mass=1, inertia=[1, 1, 1])
for _ in range(10):
    scene.step(0.01)
assert abs(body.get_linear_velocity()[1] + 0.981) < 1e-9, body.get_linear_velocity()
print('installed mochi:', mochi.__file__, libs[0])
" ${site} ${prefix})
endif()
