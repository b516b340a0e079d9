# Builds and runs tests/consumer against rgvc, as ctest's consumer:* tests do (tests/CMakeLists.txt):
#   cmake -DMODE=package -DRGVC_BUILD_DIR=<rgvc build> -DWORK_DIR=<scratch> [-DGL=ON] -DVERSION=<x.y.z>
#         -DCMAKE_COMMAND_PATH=<cmake> -P run_consumer.cmake
#     installs that build (cmake --install --prefix WORK_DIR/prefix), configures the consumer with
#     CMAKE_PREFIX_PATH=WORK_DIR/prefix, builds and runs it; then, when pkg-config is there, compiles
#     main.cpp with `pkg-config --cflags --libs rgvc` alone.
#   cmake -DMODE=subdirectory -DRGVC_SOURCE_DIR=<rgvc source> -DWORK_DIR=<scratch> -DVERSION=<x.y.z> -P ...
#     configures the consumer with add_subdirectory(rgvc) (rgvc's subproject defaults), builds, runs.
# WORK_DIR is emptied first, so every run starts clean. JOBS (default 2) for the nested builds.
cmake_minimum_required(VERSION 3.20)

foreach(var MODE WORK_DIR VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT DEFINED JOBS)
  set(JOBS 2)
endif()
if(NOT DEFINED GL)
  set(GL OFF)
endif()
set(consumer_source ${CMAKE_CURRENT_LIST_DIR})

function(run)
  string(REPLACE ";" " " shown "${ARGN}")
  message(STATUS "run_consumer: ${shown}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "run_consumer: failed (${rc}): ${shown}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(build ${WORK_DIR}/consumer-build)

if(MODE STREQUAL "package")
  set(prefix ${WORK_DIR}/prefix)
  run(${CMAKE_COMMAND} --install ${RGVC_BUILD_DIR} --prefix ${prefix})
  if(EXISTS ${prefix}/include/rgvc/grid/ConservativeRaster.hpp)
    message(FATAL_ERROR "run_consumer: the private headers (grid/internal) were installed")
  endif()
  run(${CMAKE_COMMAND} -S ${consumer_source} -B ${build} -DRGVC_CONSUMER_MODE=package
    -DCMAKE_PREFIX_PATH=${prefix} -DRGVC_CONSUMER_GL=${GL} -DRGVC_CONSUMER_EXPECTED_VERSION=${VERSION}
    -DCMAKE_BUILD_TYPE=Release)
elseif(MODE STREQUAL "subdirectory")
  # No CMAKE_BUILD_TYPE: the consumer checks that rgvc does not set one in its cache.
  run(${CMAKE_COMMAND} -S ${consumer_source} -B ${build} -DRGVC_CONSUMER_MODE=subdirectory
    -DRGVC_SOURCE_DIR=${RGVC_SOURCE_DIR} -DRGVC_CONSUMER_EXPECTED_VERSION=${VERSION})
else()
  message(FATAL_ERROR "run_consumer.cmake: MODE is package or subdirectory, got '${MODE}'")
endif()
run(${CMAKE_COMMAND} --build ${build} -j${JOBS})
run(${build}/game)

# The pkg-config file: the same program with the flags rgvc.pc gives and nothing else.
if(MODE STREQUAL "package" AND NOT GL)
  find_program(PKG_CONFIG_EXECUTABLE pkg-config)
  find_program(CXX_FOR_PC NAMES c++ g++)
  if(PKG_CONFIG_EXECUTABLE AND CXX_FOR_PC)
    set(pcdirs)
    file(GLOB_RECURSE pcfiles ${prefix}/*/rgvc.pc)
    foreach(pc ${pcfiles})
      get_filename_component(dir ${pc} DIRECTORY)
      list(APPEND pcdirs ${dir})
    endforeach()
    if(NOT pcdirs)
      message(FATAL_ERROR "run_consumer: rgvc.pc was not installed under ${prefix}")
    endif()
    list(JOIN pcdirs ":" pcpath)
    set(ENV{PKG_CONFIG_PATH} "${pcpath}:$ENV{PKG_CONFIG_PATH}")
    execute_process(COMMAND ${PKG_CONFIG_EXECUTABLE} --cflags --libs rgvc
      OUTPUT_VARIABLE pcflags OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "run_consumer: pkg-config --cflags --libs rgvc failed")
    endif()
    separate_arguments(pcflags UNIX_COMMAND "${pcflags}")
    run(${CXX_FOR_PC} -O1 ${consumer_source}/main.cpp -o ${WORK_DIR}/game-pc
      "-DRGVC_CONSUMER_EXPECTED_VERSION=\"${VERSION}\"" ${pcflags})
    run(${WORK_DIR}/game-pc)
  else()
    message(STATUS "run_consumer: no pkg-config or c++; rgvc.pc not checked")
  endif()
endif()
message(STATUS "run_consumer: ${MODE} consumer passed")
