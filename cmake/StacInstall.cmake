# Install rules and the CMake package (included from the top-level
# CMakeLists.txt when STAC_INSTALL is on; the apps install themselves).
#
#   find_package(stac CONFIG REQUIRED)                     # stac::stac, stac::runtime
#   find_package(stac CONFIG REQUIRED COMPONENTS runtime)  # stac::runtime only:
#                                                          # needs Eigen, nothing else
#
# Two export sets, so that a consumer of stac::runtime (firmware, a real-time
# loop) never has to find Ceres, KDL, urdfdom or yaml-cpp.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(STAC_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/stac"
  CACHE STRING "Where to install stacConfig.cmake (relative to the prefix)")

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/stac
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")

install(TARGETS stac_runtime EXPORT stacRuntimeTargets)
install(EXPORT stacRuntimeTargets
  FILE stacRuntimeTargets.cmake
  NAMESPACE stac::
  DESTINATION ${STAC_INSTALL_CMAKEDIR})

install(TARGETS stac EXPORT stacTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT stacTargets
  FILE stacTargets.cmake
  NAMESPACE stac::
  DESTINATION ${STAC_INSTALL_CMAKEDIR})

# A static libstac.a leaves its private dependencies (urdfdom, tinyxml,
# yaml-cpp) to the consumer's link line: the exported target names them as
# $<LINK_ONLY:...>, and stacConfig.cmake finds them again. A shared libstac
# carries them itself.
get_target_property(STAC_LIBRARY_TYPE stac TYPE)
if(STAC_LIBRARY_TYPE STREQUAL "STATIC_LIBRARY")
  set(STAC_STATIC_LIBRARY ON)
else()
  set(STAC_STATIC_LIBRARY OFF)
  # Installed apps find an installed shared libstac.
  file(RELATIVE_PATH _stac_bin_to_lib
    "${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}"
    "${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}")
  foreach(app stac_calib stac_simulate stac_eval stac_export_header)
    if(TARGET ${app})
      set_target_properties(${app} PROPERTIES INSTALL_RPATH "$ORIGIN/${_stac_bin_to_lib}")
    endif()
  endforeach()
endif()

configure_package_config_file(
  ${CMAKE_CURRENT_LIST_DIR}/stacConfig.cmake.in
  ${PROJECT_BINARY_DIR}/stacConfig.cmake
  INSTALL_DESTINATION ${STAC_INSTALL_CMAKEDIR})
# 0.x: a new minor version may break the API.
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/stacConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/stacConfig.cmake
  ${PROJECT_BINARY_DIR}/stacConfigVersion.cmake
  DESTINATION ${STAC_INSTALL_CMAKEDIR})

# ---- Packaging tests (fmt's habit): install into a scratch prefix, then
# configure, build and run two small consumer projects against it. ----
if(STAC_BUILD_TESTS)
  set(_stac_pkg_dir ${PROJECT_BINARY_DIR}/package_test)
  set(_stac_pkg_args
    -DSTAC_BINARY_DIR=${PROJECT_BINARY_DIR}
    -DPACKAGE_TEST_DIR=${_stac_pkg_dir}
    -DCONSUMERS_DIR=${PROJECT_SOURCE_DIR}/test/packaging
    -DGENERATOR=${CMAKE_GENERATOR}
    -DC_COMPILER=${CMAKE_C_COMPILER}
    -DCXX_COMPILER=${CMAKE_CXX_COMPILER})
  add_test(NAME package_install
    COMMAND ${CMAKE_COMMAND} ${_stac_pkg_args} -DSTEP=install
            -P ${CMAKE_CURRENT_LIST_DIR}/StacPackageTest.cmake)
  add_test(NAME package_consumer
    COMMAND ${CMAKE_COMMAND} ${_stac_pkg_args} -DSTEP=consumer
            -P ${CMAKE_CURRENT_LIST_DIR}/StacPackageTest.cmake)
  add_test(NAME package_runtime_consumer
    COMMAND ${CMAKE_COMMAND} ${_stac_pkg_args} -DSTEP=runtime_consumer
            -P ${CMAKE_CURRENT_LIST_DIR}/StacPackageTest.cmake)
  set_tests_properties(package_install PROPERTIES
    LABELS unit FIXTURES_SETUP stac_installed TIMEOUT 120)
  set_tests_properties(package_consumer package_runtime_consumer PROPERTIES
    LABELS unit FIXTURES_REQUIRED stac_installed TIMEOUT 120)
endif()

