# The packaging tests (cmake -P; registered by StacInstall.cmake):
#
#   STEP=install           cmake --install <build> --prefix <scratch>/prefix
#   STEP=consumer          test/packaging/consumer: find_package(stac), links
#                          stac::stac (a static libstac pulls urdfdom, tinyxml
#                          and yaml-cpp onto the consumer's link line), runs it
#   STEP=runtime_consumer  test/packaging/runtime_consumer: find_package(stac
#                          COMPONENTS runtime) with Ceres, KDL, yaml-cpp and
#                          pkg-config made unfindable; checks that the link
#                          line and the executable's NEEDED entries name none
#                          of the calibration dependencies, and runs it
#
# Inputs: STAC_BINARY_DIR PACKAGE_TEST_DIR CONSUMERS_DIR GENERATOR C_COMPILER
# CXX_COMPILER STEP.
cmake_minimum_required(VERSION 3.16)

set(prefix ${PACKAGE_TEST_DIR}/prefix)

function(run what)
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}${err}" PARENT_SCOPE)
endfunction()

# Configures and builds a consumer; sets `link_log` (the verbose build output).
function(build_consumer name)
  set(src ${CONSUMERS_DIR}/${name})
  set(bin ${PACKAGE_TEST_DIR}/${name})
  file(REMOVE_RECURSE ${bin})
  run("configuring ${name}" ${CMAKE_COMMAND} -S ${src} -B ${bin} -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_FIND_PACKAGE_PREFER_CONFIG=ON
    ${ARGN})
  message(STATUS "${run_output}")
  run("building ${name}" ${CMAKE_COMMAND} --build ${bin} --verbose)
  set(link_log "${run_output}" PARENT_SCOPE)
endfunction()

if(STEP STREQUAL "install")
  file(REMOVE_RECURSE ${prefix})
  run("cmake --install" ${CMAKE_COMMAND} --install ${STAC_BINARY_DIR} --prefix ${prefix})
  foreach(f include/stac/sensors_file.hpp include/stac/runtime/sensor_maps.hpp)
    if(NOT EXISTS ${prefix}/${f})
      message(FATAL_ERROR "not installed: ${f}")
    endif()
  endforeach()
  file(GLOB_RECURSE configs ${prefix}/*/stacConfig.cmake ${prefix}/*/stacConfigVersion.cmake
    ${prefix}/*/stacTargets.cmake ${prefix}/*/stacRuntimeTargets.cmake)
  list(LENGTH configs n)
  if(NOT n EQUAL 4)
    message(FATAL_ERROR "expected the four package files, found: ${configs}")
  endif()
  file(GLOB_RECURSE libs ${prefix}/*/libstac.*)
  if(NOT libs)
    message(FATAL_ERROR "libstac not installed under ${prefix}")
  endif()
  message(STATUS "installed into ${prefix}: ${libs}")

elseif(STEP STREQUAL "consumer")
  build_consumer(consumer)
  run("running the consumer" ${PACKAGE_TEST_DIR}/consumer/stac_consumer)
  message(STATUS "${run_output}")

elseif(STEP STREQUAL "runtime_consumer")
  build_consumer(runtime_consumer
    -DCMAKE_DISABLE_FIND_PACKAGE_Ceres=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_orocos_kdl=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_yaml-cpp=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_Threads=ON)
  set(exe ${PACKAGE_TEST_DIR}/runtime_consumer/stac_runtime_consumer)
  # The link line: no calibration library, no dependency of one.
  foreach(bad ceres glog gflags orocos urdf tinyxml yaml libstac cholmod)
    string(TOLOWER "${link_log}" lower_log)
    if(lower_log MATCHES "[-/]l?${bad}")
      message(FATAL_ERROR "the runtime consumer's build mentions '${bad}':\n${link_log}")
    endif()
  endforeach()
  # The executable's dynamic dependencies (readelf where there is one).
  find_program(READELF readelf)
  if(READELF)
    run("readelf -d" ${READELF} -d ${exe})
    string(REGEX MATCHALL "\\(NEEDED\\)[^\n]*" needed "${run_output}")
    message(STATUS "runtime consumer NEEDED: ${needed}")
    foreach(bad ceres glog gflags orocos urdf tinyxml yaml stac cholmod blas lapack)
      string(TOLOWER "${needed}" lower_needed)
      if(lower_needed MATCHES "${bad}")
        message(FATAL_ERROR "the runtime consumer needs '${bad}': ${needed}")
      endif()
    endforeach()
  endif()
  run("running the runtime consumer" ${exe})
  message(STATUS "${run_output}")

else()
  message(FATAL_ERROR "unknown STEP '${STEP}'")
endif()
