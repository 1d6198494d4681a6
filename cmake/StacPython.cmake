# The Python module (python/), optional: built when Python's headers and
# pybind11 are found, skipped with a note otherwise (the C++ build does not
# need them). Debian's interpreter by default, where cmake/run.sh installs
# numpy and pytest from Debian's packages (a pyenv or conda python3 earlier
# on PATH would lack them): -DPython_EXECUTABLE=... picks another, and
# scikit-build-core (`pip install .`) passes the building interpreter.
if(NOT DEFINED Python_EXECUTABLE AND NOT SKBUILD AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python 3.8 QUIET COMPONENTS Interpreter Development.Module)
if(Python_FOUND)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()
if(Python_FOUND AND pybind11_FOUND)
  message(STATUS "Python module: ${Python_EXECUTABLE} (${Python_VERSION}), pybind11 ${pybind11_VERSION}")
  add_subdirectory(python)
elseif(SKBUILD)
  # `pip install .` exists to build the module: a wheel without it would
  # install and then fail at `import stac`.
  message(FATAL_ERROR "pip install: the Python module needs Python's headers and pybind11 "
                      "(Debian: python3-dev pybind11-dev; see cmake/run.sh)")
else()
  message(STATUS "Python module not built: needs Python's headers and pybind11 "
                 "(Debian: python3-dev pybind11-dev; see cmake/run.sh)")
endif()
