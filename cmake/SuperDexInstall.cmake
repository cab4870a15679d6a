# Installation and the find_package(SuperDex) package.
#
#   <prefix>/lib/libsuperdex.so*                         the library (libsuperdex.a: BUILD_SHARED_LIBS=OFF)
#   <prefix>/include/superdex/<folder>/*.h               public headers, same paths as in the tree
#   <prefix>/include/superdex/superdex.h                 umbrella header
#   <prefix>/include/superdex/core/config.h              generated build configuration
#   <prefix>/include/superdex/constraints/constraint_type_headers.h   generated from constraint_types.h
#   <prefix>/lib/cmake/SuperDex/SuperDex{Config,ConfigVersion,Targets}.cmake
#   <prefix>/lib/cmake/SuperDex/SuperDexPrivateDependencies.cmake   static builds only
#
# Consumers write find_package(SuperDex) and link SuperDex::superdex, which
# brings Eigen and Eigen's pinned alignment (PUBLIC), nothing else: no -march
# (docs/install.md). CHOLMOD, METIS, oneTBB, PETSc, MPI and the BLAS they
# load are PRIVATE to the shared library and do not appear in the exported
# interface; a static library leaves them to the consumer's link step, and
# its SuperDexConfig.cmake finds them with the file the build uses,
# SuperDexPrivateDependencies.cmake, installed next to it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SUPERDEX_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/SuperDex
    CACHE STRING "Where SuperDexConfig.cmake is installed, relative to the prefix")
mark_as_advanced(SUPERDEX_INSTALL_CMAKEDIR)

# the library; its include directory is set on the target (INSTALL_INTERFACE)
set(_superdex_includes_destination)
if(NOT CMAKE_INSTALL_INCLUDEDIR STREQUAL "include")
  set(_superdex_includes_destination INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
install(TARGETS superdex
  EXPORT SuperDexTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT development
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime
  ${_superdex_includes_destination})

# public headers, folder by folder; the file set is read at install time, so
# headers added later need no reconfigure
foreach(folder IN LISTS SUPERDEX_LIBRARY_FOLDERS)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/superdex/${folder}
    COMPONENT development
    FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/superdex.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/superdex
  COMPONENT development
  OPTIONAL)
install(FILES ${PROJECT_BINARY_DIR}/generated/superdex/core/config.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/superdex/core
  COMPONENT development)
install(FILES ${PROJECT_BINARY_DIR}/generated/superdex/constraints/constraint_type_headers.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/superdex/constraints
  COMPONENT development)

# the package: targets, config, version
install(EXPORT SuperDexTargets
  NAMESPACE SuperDex::
  FILE SuperDexTargets.cmake
  DESTINATION ${SUPERDEX_INSTALL_CMAKEDIR}
  COMPONENT development)

get_target_property(_superdex_type superdex TYPE)
if(_superdex_type STREQUAL "STATIC_LIBRARY")
  set(SUPERDEX_STATIC ON)
else()
  set(SUPERDEX_STATIC OFF)
endif()
configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/SuperDexConfig.cmake.in
  ${PROJECT_BINARY_DIR}/SuperDexConfig.cmake
  INSTALL_DESTINATION ${SUPERDEX_INSTALL_CMAKEDIR})
# 0.x: minor versions may break the API
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/SuperDexConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/SuperDexConfig.cmake
  ${PROJECT_BINARY_DIR}/SuperDexConfigVersion.cmake
  DESTINATION ${SUPERDEX_INSTALL_CMAKEDIR}
  COMPONENT development)
if(SUPERDEX_STATIC)
  install(FILES ${PROJECT_SOURCE_DIR}/cmake/SuperDexPrivateDependencies.cmake
    DESTINATION ${SUPERDEX_INSTALL_CMAKEDIR}
    COMPONENT development)
endif()

unset(_superdex_includes_destination)
unset(_superdex_type)
