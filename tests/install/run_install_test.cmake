# Install test driver, run by ctest as `cmake -D... -P run_install_test.cmake`.
#
#   1. cmake --install <build tree> (the library's component) into a scratch prefix; every file
#      it wrote under the prefix, every header of include/coopdyn among them
#   2. configure + build tests/install against it via CMAKE_PREFIX_PATH
#   3. run the consumer
#   4. if pkg-config exists: check `pkg-config --cflags coopdyn`
#
# Inputs (-D): COOPDYN_BUILD_DIR, COOPDYN_CONSUMER_DIR, COOPDYN_WORK_DIR,
# COOPDYN_CONFIG, COOPDYN_GENERATOR, COOPDYN_CXX_COMPILER, COOPDYN_Eigen3_DIR,
# COOPDYN_VERSION, COOPDYN_EXPECT_MUJOCO (the build has coopdyn::mujoco: the
# consumer must get it too, and its adapter consumer is built and run).
cmake_minimum_required(VERSION 3.22)

foreach(var COOPDYN_BUILD_DIR COOPDYN_CONSUMER_DIR COOPDYN_WORK_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "run_install_test.cmake: ${var} is not set")
  endif()
endforeach()

set(prefix "${COOPDYN_WORK_DIR}/prefix")
set(consumer_build "${COOPDYN_WORK_DIR}/consumer-build")
file(REMOVE_RECURSE "${COOPDYN_WORK_DIR}")
file(MAKE_DIRECTORY "${COOPDYN_WORK_DIR}")

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (${rc})")
  endif()
endfunction()

# 1. install
set(config_args "")
if(COOPDYN_CONFIG)
  set(config_args --config "${COOPDYN_CONFIG}")
endif()
# The library's component alone (the Python package, component python, has a test of its own:
# run_python_install_test.cmake), and every file it wrote must be under the prefix.
set(manifest "${COOPDYN_BUILD_DIR}/install_manifest_Unspecified.txt")
file(REMOVE "${manifest}")
run_step("cmake --install"
  "${CMAKE_COMMAND}" --install "${COOPDYN_BUILD_DIR}" --component Unspecified --prefix "${prefix}" ${config_args})
file(REAL_PATH "${prefix}" real_prefix)
file(STRINGS "${manifest}" installed)
set(headers 0)
foreach(path IN LISTS installed)
  string(FIND "${path}" "${real_prefix}/" at)
  string(FIND "${path}" "${prefix}/" at_given)
  if(NOT at EQUAL 0 AND NOT at_given EQUAL 0)
    message(FATAL_ERROR "install test: ${path} is outside the prefix ${prefix}")
  endif()
  if(path MATCHES "/include/coopdyn/.*\\.hpp$")
    math(EXPR headers "${headers} + 1")
  endif()
endforeach()
# Every header of the source tree's include/coopdyn, no more and no fewer.
get_filename_component(source_dir "${COOPDYN_CONSUMER_DIR}/../.." ABSOLUTE)
file(GLOB_RECURSE source_headers "${source_dir}/include/coopdyn/*.hpp")
list(LENGTH source_headers source_count)
if(NOT headers EQUAL source_count)
  message(FATAL_ERROR "install test: ${headers} headers installed, the source tree has ${source_count}")
endif()

# 2. configure + build the consumer
set(configure_args -S "${COOPDYN_CONSUMER_DIR}" -B "${consumer_build}"
  "-DCMAKE_PREFIX_PATH=${prefix}")
if(COOPDYN_GENERATOR)
  list(APPEND configure_args -G "${COOPDYN_GENERATOR}")
endif()
if(COOPDYN_CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${COOPDYN_CXX_COMPILER}")
endif()
if(COOPDYN_Eigen3_DIR)
  list(APPEND configure_args "-DEigen3_DIR=${COOPDYN_Eigen3_DIR}")
endif()
if(COOPDYN_CONFIG)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${COOPDYN_CONFIG}")
endif()
if(COOPDYN_EXPECT_MUJOCO)
  list(APPEND configure_args "-DCOOPDYN_EXPECT_MUJOCO=ON")
endif()
run_step("configuring the consumer" "${CMAKE_COMMAND}" ${configure_args})
run_step("building the consumer"
  "${CMAKE_COMMAND}" --build "${consumer_build}" ${config_args})

# 3. run it (single- or multi-config layout)
set(consumer_exe "")
foreach(candidate "${consumer_build}/consumer" "${consumer_build}/${COOPDYN_CONFIG}/consumer"
                  "${consumer_build}/consumer.exe" "${consumer_build}/${COOPDYN_CONFIG}/consumer.exe")
  if(NOT consumer_exe AND EXISTS "${candidate}" AND NOT IS_DIRECTORY "${candidate}")
    set(consumer_exe "${candidate}")
  endif()
endforeach()
if(NOT consumer_exe)
  message(FATAL_ERROR "install test: consumer executable not found in ${consumer_build}")
endif()
run_step("running the consumer" "${consumer_exe}")
if(COOPDYN_EXPECT_MUJOCO)
  get_filename_component(consumer_dir "${consumer_exe}" DIRECTORY)
  file(GLOB mujoco_consumer "${consumer_dir}/mujoco_consumer" "${consumer_dir}/mujoco_consumer.exe")
  if(NOT mujoco_consumer)
    message(FATAL_ERROR "install test: mujoco_consumer (coopdyn::mujoco) was not built in ${consumer_dir}")
  endif()
  run_step("running the MuJoCo adapter's consumer" ${mujoco_consumer})
endif()

# 4. pkg-config (optional)
find_program(PKG_CONFIG_EXECUTABLE NAMES pkg-config pkgconf)
if(NOT PKG_CONFIG_EXECUTABLE)
  message(STATUS "install test: pkg-config not found, skipping the pkg-config check")
else()
  file(GLOB_RECURSE pc_files "${prefix}/*/coopdyn.pc")
  if(NOT pc_files)
    message(FATAL_ERROR "install test: coopdyn.pc was not installed under ${prefix}")
  endif()
  list(GET pc_files 0 pc_file)
  get_filename_component(pc_dir "${pc_file}" DIRECTORY)
  set(ENV{PKG_CONFIG_PATH} "${pc_dir}:$ENV{PKG_CONFIG_PATH}")
  execute_process(COMMAND "${PKG_CONFIG_EXECUTABLE}" --cflags coopdyn
    RESULT_VARIABLE rc OUTPUT_VARIABLE cflags ERROR_VARIABLE err
    OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: pkg-config --cflags coopdyn failed: ${err}")
  endif()
  message(STATUS "install test: pkg-config --cflags coopdyn: ${cflags}")
  # The include dir must resolve to <prefix>/include (compare real paths).
  set(found_include FALSE)
  separate_arguments(cflag_list UNIX_COMMAND "${cflags}")
  file(REAL_PATH "${prefix}/include" want_include)
  foreach(flag IN LISTS cflag_list)
    if(flag MATCHES "^-I(.+)$")
      file(REAL_PATH "${CMAKE_MATCH_1}" got_include)
      if(got_include STREQUAL want_include)
        set(found_include TRUE)
      endif()
    endif()
  endforeach()
  if(NOT found_include)
    message(FATAL_ERROR "install test: pkg-config cflags '${cflags}' lack -I${want_include}")
  endif()
  if(COOPDYN_VERSION)
    execute_process(COMMAND "${PKG_CONFIG_EXECUTABLE}" --modversion coopdyn
      OUTPUT_VARIABLE pc_version OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT pc_version STREQUAL COOPDYN_VERSION)
      message(FATAL_ERROR "install test: pkg-config version '${pc_version}' != ${COOPDYN_VERSION}")
    endif()
  endif()
  # Compile the consumer with the pkg-config flags alone.
  if(COOPDYN_CXX_COMPILER)
    run_step("compiling the consumer with pkg-config flags"
      "${COOPDYN_CXX_COMPILER}" -std=c++17 ${cflag_list} -fsyntax-only
      "${COOPDYN_CONSUMER_DIR}/main.cpp")
  endif()
endif()

message(STATUS "install test: OK")
