# Every third-party package STAC builds against (Debian packages; see
# cmake/run.sh for the apt names).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(orocos_kdl REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
# urdfdom's CMake config drags in console_bridge's; pkg-config is simpler.
pkg_check_modules(URDFDOM REQUIRED IMPORTED_TARGET urdfdom)
pkg_check_modules(TINYXML REQUIRED IMPORTED_TARGET tinyxml)

if(NOT TARGET orocos-kdl::orocos-kdl)
  add_library(orocos-kdl::orocos-kdl INTERFACE IMPORTED)
  set_target_properties(orocos-kdl::orocos-kdl PROPERTIES
    INTERFACE_LINK_LIBRARIES "${orocos_kdl_LIBRARIES}"
    INTERFACE_INCLUDE_DIRECTORIES "${orocos_kdl_INCLUDE_DIRS}")
endif()
if(TARGET yaml-cpp AND NOT TARGET yaml-cpp::yaml-cpp)
  add_library(yaml-cpp::yaml-cpp ALIAS yaml-cpp)
endif()
