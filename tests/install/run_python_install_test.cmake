# The Python package's install test, run by ctest as `cmake -D... -P run_python_install_test.cmake`
# (python/CMakeLists.txt, test coopdyn_install_python):
#
#   1. cmake --install <build tree> --component python into a scratch prefix
#   2. every file the install wrote (install_manifest_python.txt) is under the prefix, and the
#      files are exactly the package's: its pure-Python files and the extensions this build made
#   3. the installed package imports from the prefix alone (PYTHONPATH), extensions included
#
# Inputs (-D): COOPDYN_BUILD_DIR, COOPDYN_WORK_DIR, COOPDYN_PYTHON (the interpreter),
# COOPDYN_PYTHON_INSTALL_DIR (relative to the prefix), COOPDYN_PYTHON_FILES (the pure-Python
# files), COOPDYN_EXTENSIONS (the extension modules built: _coopdyn, _mujoco, _experiments); the
# two lists comma-separated.
cmake_minimum_required(VERSION 3.22)

foreach(var COOPDYN_BUILD_DIR COOPDYN_WORK_DIR COOPDYN_PYTHON COOPDYN_PYTHON_INSTALL_DIR COOPDYN_PYTHON_FILES
            COOPDYN_EXTENSIONS)
  if(NOT ${var})
    message(FATAL_ERROR "run_python_install_test.cmake: ${var} is not set")
  endif()
endforeach()
if(IS_ABSOLUTE "${COOPDYN_PYTHON_INSTALL_DIR}")
  message(FATAL_ERROR "run_python_install_test.cmake: COOPDYN_PYTHON_INSTALL_DIR is absolute (a virtual "
                      "environment's): the test installs only under a scratch prefix")
endif()

string(REPLACE "," ";" COOPDYN_PYTHON_FILES "${COOPDYN_PYTHON_FILES}")
string(REPLACE "," ";" COOPDYN_EXTENSIONS "${COOPDYN_EXTENSIONS}")

set(prefix "${COOPDYN_WORK_DIR}/prefix")
file(REMOVE_RECURSE "${COOPDYN_WORK_DIR}")
file(MAKE_DIRECTORY "${prefix}")
file(REAL_PATH "${prefix}" prefix)
set(manifest "${COOPDYN_BUILD_DIR}/install_manifest_python.txt")
file(REMOVE "${manifest}")

execute_process(COMMAND "${CMAKE_COMMAND}" --install "${COOPDYN_BUILD_DIR}" --component python --prefix "${prefix}"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "python install test: cmake --install --component python failed (${rc})")
endif()

# 2. file by file: under the prefix, and the package's files, no more and no fewer.
if(NOT EXISTS "${manifest}")
  message(FATAL_ERROR "python install test: ${manifest} was not written")
endif()
file(STRINGS "${manifest}" installed)
set(package_dir "${prefix}/${COOPDYN_PYTHON_INSTALL_DIR}/coopdyn")
set(expected)
foreach(file IN LISTS COOPDYN_PYTHON_FILES)
  list(APPEND expected "${package_dir}/${file}")
endforeach()
set(seen_extensions)
foreach(path IN LISTS installed)
  string(FIND "${path}" "${prefix}/" at)
  if(NOT at EQUAL 0)
    message(FATAL_ERROR "python install test: ${path} is outside the prefix ${prefix}")
  endif()
  if(NOT EXISTS "${path}")
    message(FATAL_ERROR "python install test: ${path} is in the manifest but not on disk")
  endif()
  list(FIND expected "${path}" index)
  get_filename_component(name "${path}" NAME)
  get_filename_component(dir "${path}" DIRECTORY)
  if(index GREATER_EQUAL 0)
    list(REMOVE_AT expected ${index})
  elseif(dir STREQUAL package_dir AND name MATCHES "^(_[a-z]+)\\..*\\.so$")
    list(APPEND seen_extensions "${CMAKE_MATCH_1}")
  else()
    message(FATAL_ERROR "python install test: unexpected file ${path}")
  endif()
endforeach()
if(expected)
  message(FATAL_ERROR "python install test: not installed: ${expected}")
endif()
list(SORT seen_extensions)
set(want_extensions ${COOPDYN_EXTENSIONS})
list(SORT want_extensions)
if(NOT seen_extensions STREQUAL want_extensions)
  message(FATAL_ERROR "python install test: installed extensions '${seen_extensions}', built '${want_extensions}'")
endif()

# 3. the installed package, from the prefix alone.
set(imports "import coopdyn, os, sys")
foreach(extension IN LISTS COOPDYN_EXTENSIONS)
  string(APPEND imports "; import coopdyn.${extension}")
endforeach()
string(APPEND imports "; sys.stdout.write(os.path.realpath(coopdyn.__file__))")
execute_process(COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${prefix}/${COOPDYN_PYTHON_INSTALL_DIR}"
                        PYTHONDONTWRITEBYTECODE=1 "${COOPDYN_PYTHON}" -c "${imports}"
                WORKING_DIRECTORY "${COOPDYN_WORK_DIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE imported ERROR_VARIABLE error)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "python install test: importing the installed package failed: ${error}")
endif()
if(NOT imported STREQUAL "${package_dir}/__init__.py")
  message(FATAL_ERROR "python install test: imported ${imported}, not the installed ${package_dir}/__init__.py")
endif()
list(LENGTH installed count)
message(STATUS "python install test: OK (${count} files under ${prefix})")
