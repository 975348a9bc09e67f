# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -P check_install.cmake
# Installs the build tree into a scratch prefix, configures and builds
# examples/stream_frame against it with find_package(ceilnav) and runs it:
# the installed package is complete enough for a consumer outside the tree.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f IN ITEMS lib/cmake/ceilnav/ceilnavConfig.cmake include/ceilnav/host/driver.hpp
                   include/ceilnav/ceilnav/regs.hpp include/ceilnav/ceilnav/ceilnav_regs.h
                   bin/ceilnav)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/stream_frame -B ${WORK_DIR}/example -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/example)
run(${WORK_DIR}/example/stream_frame)
message(STATUS "example output:\n${run_out}")
if(NOT run_out MATCHES "status ok")
  message(FATAL_ERROR "the example did not report a pose with status ok")
endif()
