# Python: Debian's interpreter (/usr/bin/python3, the one whose numpy, pytest and Open3D the
# packages install), found for the tests whether or not the module is built; the module when
# pybind11 is there. A `python3` earlier on PATH may be another interpreter without them, so
# /usr/bin/python3 is preferred unless Python3_EXECUTABLE is given.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)

set(FMCW_PYTHON_DIR ${CMAKE_BINARY_DIR}/python)
set(FMCW_PYTHON_MODULE OFF)
if(FMCW_BUILD_PYTHON AND Python3_Development.Module_FOUND)
  if(FMCW_SANITIZE)
    # An ASan-instrumented module only loads into an interpreter started with the ASan runtime.
    message(STATUS "fmcw Python module: not built with FMCW_SANITIZE")
  else()
    find_package(pybind11 CONFIG QUIET)
    if(pybind11_FOUND)
      add_subdirectory(python)
      set(FMCW_PYTHON_MODULE ON)
      message(STATUS "fmcw Python module: ${FMCW_PYTHON_DIR} (pybind11 ${pybind11_VERSION}, ${Python3_EXECUTABLE})")
    else()
      message(STATUS "fmcw Python module: not built (pybind11 not found; Debian: pybind11-dev)")
    endif()
  endif()
endif()
