# SPDX-License-Identifier: Apache-2.0
# cmake -DDVI_SOURCE_DIR=… -DDVI_BINARY_DIR=… -DWORK_DIR=… -P packaging_test.cmake
# Builds and runs tests/packaging/consumer three ways: find_package against
# an install of DVI_BINARY_DIR into a temporary prefix, pkg-config against
# the same install, and add_subdirectory of the sources (the one nested build
# of the library; ccache, when the outer build used it, makes it a replay).
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
set(consumer ${CMAKE_CURRENT_LIST_DIR}/consumer)

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}")
  endif()
  message(STATUS "${what}: ok")
endfunction()

run_step("install into ${prefix}" ${CMAKE_COMMAND} --install ${DVI_BINARY_DIR} --prefix ${prefix})

foreach(way package pkg-config subdirectory)
  set(build ${WORK_DIR}/${way})
  set(args -DDVI_CONSUME=${way} -DDVI_SOURCE_DIR=${DVI_SOURCE_DIR} -DCMAKE_BUILD_TYPE=Release
           -DCMAKE_PREFIX_PATH=${prefix})
  if(DEFINED LAUNCHER AND NOT LAUNCHER STREQUAL "")
    list(APPEND args -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
  endif()
  if(way STREQUAL "pkg-config")
    # Only the installed dvi.pc, found through the prefix (CMAKE_PREFIX_PATH).
    set(ENV{PKG_CONFIG_PATH} "")
  endif()
  run_step("${way}: configure" ${CMAKE_COMMAND} -S ${consumer} -B ${build} ${args})
  # Only the consumer and what it links (not dvi::ensemble, say).
  run_step("${way}: build" ${CMAKE_COMMAND} --build ${build} -j2 --target dvi)
  run_step("${way}: run" ${build}/dvi)
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
