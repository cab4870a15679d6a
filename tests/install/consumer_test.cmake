# Script run by the install_and_consume test (cmake -P). Inputs:
#   SUPERDEX_BINARY_DIR  the SuperDex build tree to install
#   CONSUMER_SOURCE_DIR  examples/consumer
#   WORK_DIR             scratch folder (wiped first): prefix/, build/
#   BUILD_TYPE           configuration to install and to build the consumer in
#   CXX_COMPILER         the compiler SuperDex was built with
#   PYTHON_EXECUTABLE, PYTHON_INSTALL_DIR  (optional) the interpreter and the
#                        module folder relative to the prefix: when set, the
#                        installed mochi is imported from the prefix and steps
#                        a scene with the prefix's libsuperdex
cmake_minimum_required(VERSION 3.20)

foreach(var IN ITEMS SUPERDEX_BINARY_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer_test.cmake: ${var} is not set")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${WORK_DIR})

# runs one stage; a non-zero exit fails the test with the stage's name
function(run_stage name)
  message(STATUS "install_and_consume: ${name}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install_and_consume: ${name} failed (${rc})")
  endif()
endfunction()

# 1. install
run_stage("install into ${prefix}"
  ${CMAKE_COMMAND} --install ${SUPERDEX_BINARY_DIR} --prefix ${prefix} --config ${BUILD_TYPE})

# the private dependencies must not leak into the package or the headers
file(GLOB_RECURSE targets_files ${prefix}/*/SuperDexTargets*.cmake)
if(NOT targets_files)
  message(FATAL_ERROR "install_and_consume: no SuperDexTargets.cmake under ${prefix}")
endif()
file(GLOB_RECURSE config_files ${prefix}/*/SuperDexConfig.cmake)
if(NOT config_files)
  message(FATAL_ERROR "install_and_consume: no SuperDexConfig.cmake under ${prefix}")
endif()
file(READ ${config_files} config_text)
string(FIND "${config_text}" "set(SuperDex_STATIC ON)" static_at)
if(static_at EQUAL -1)
  foreach(file IN LISTS targets_files)
    file(READ ${file} text)
    if(text MATCHES "(cholmod|metis|suitesparse|petsc)")
      message(FATAL_ERROR "install_and_consume: ${file} mentions '${CMAKE_MATCH_1}', "
        "a private dependency of the shared library")
    endif()
  endforeach()
endif()
file(GLOB_RECURSE headers ${prefix}/include/superdex/*.h)
foreach(header IN LISTS headers)
  file(STRINGS ${header} private_includes REGEX "#include[ \t]*[<\"](cholmod|metis|petsc)")
  if(private_includes)
    message(FATAL_ERROR "install_and_consume: installed header ${header} includes a private "
      "dependency: ${private_includes}")
  endif()
endforeach()
if(NOT EXISTS ${prefix}/include/superdex/core/config.h)
  message(FATAL_ERROR "install_and_consume: include/superdex/core/config.h was not installed")
endif()

# 2. configure the consumer against the prefix only (no package registry)
set(compiler_arg)
if(CXX_COMPILER)
  set(compiler_arg -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
run_stage("configure examples/consumer"
  ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${build}
    -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    ${compiler_arg})

# 3. build it
run_stage("build examples/consumer" ${CMAKE_COMMAND} --build ${build} --config ${BUILD_TYPE})

# 4. run it
find_program(consumer superdex_consumer PATHS ${build} ${build}/${BUILD_TYPE} NO_DEFAULT_PATH
  REQUIRED)
run_stage("run ${consumer}" ${consumer})

# 5. the installed Python module: imported from the prefix alone (not the
#    build tree), it must load the prefix's libsuperdex and step a scene
if(PYTHON_EXECUTABLE AND PYTHON_INSTALL_DIR)
  set(site ${prefix}/${PYTHON_INSTALL_DIR})
  run_stage("import the installed mochi from ${site}"
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
