# zbrdf_precompile_common_headers(TARGET KIND [EXTRA...]): the standard, Eigen and JSON headers
# most sources include (and EXTRA), parsed once instead of once per source: a clean build on 2
# cores spent most of its time parsing them. One host target per KIND ("library", "test";
# cmake/pch_host.cc, no compile definitions) compiles the header and every target of that kind
# reuses it: GCC takes a precompiled header only if the macros defined when it was made are
# defined the same way where it is used, so the host defines none (a consumer's own definitions,
# such as ZBRDF_SOURCE_DATA_DIR, do not appear in these headers). Sources still include what
# they use; the layering and write-site tests read the sources, not this list. -DZBRDF_PCH=OFF
# turns it off.
option(ZBRDF_PCH "precompile the common headers (one per kind of target)" ON)
function(zbrdf_precompile_common_headers target kind)
  if(NOT ZBRDF_PCH)
    return()
  endif()
  set(host zbrdf_pch_${kind})
  if(NOT TARGET ${host})
    add_library(${host} OBJECT "${PROJECT_SOURCE_DIR}/cmake/pch_host.cc")
    target_link_libraries(${host} PRIVATE Eigen3::Eigen Threads::Threads ${ARGN})
    target_precompile_headers(${host} PRIVATE
      <algorithm> <array> <cmath> <cstdint> <functional> <map> <memory> <string> <vector>
      <Eigen/Dense> <nlohmann/json.hpp>)
    if(kind STREQUAL "test")
      target_precompile_headers(${host} PRIVATE <gtest/gtest.h> <filesystem>)
    endif()
  endif()
  target_precompile_headers(${target} REUSE_FROM ${host})
endfunction()

# zbrdf_library(NAME DEPS...): a static library from every .cc file in the calling folder.
# Sources are globbed so that adding a file pair needs no CMake edit; CONFIGURE_DEPENDS makes
# the build notice new files.
function(zbrdf_library name)
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cc")
  if(sources)
    add_library(${name} STATIC ${sources})
    target_include_directories(${name} PUBLIC "${PROJECT_SOURCE_DIR}")
    target_link_libraries(${name} PUBLIC ${ARGN})
    zbrdf_precompile_common_headers(${name} library)
  else()  # a folder whose sources have not landed yet
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE "${PROJECT_SOURCE_DIR}")
    target_link_libraries(${name} INTERFACE ${ARGN})
  endif()
endfunction()

# zbrdf_test_folder(NAME DEPS...): one GoogleTest binary from every *_test.cc in the calling
# folder, each test registered with CTest.
function(zbrdf_test_folder name)
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc")
  if(NOT sources)
    return()
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE ${ARGN} GTest::gtest GTest::gtest_main Threads::Threads)
  zbrdf_precompile_common_headers(${name} test GTest::gtest)
  # Test sources compile at -O1 (about 30% faster than -O3, measured on conversion_test.cc and
  # crash_test.cc); the libraries they test keep the build type's optimization.
  if(CMAKE_BUILD_TYPE STREQUAL "Release")
    target_compile_options(${name} PRIVATE -O1)
  endif()
  target_compile_definitions(${name} PRIVATE
    ZBRDF_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ZBRDF_TEST_DATA_DIR="${PROJECT_SOURCE_DIR}/tests/data"
    ZBRDF_BINARY_DIR="${PROJECT_BINARY_DIR}")
  # Every test process shares the build tree's cache (direction maps, light transports, true
  # coefficients): a transport one test builds, the next one with the same rig, material and seed
  # reads (entries are written by atomic rename, so concurrent tests are safe).
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${name}
                       ENVIRONMENT "ZBRDF_CACHE_DIR=${PROJECT_BINARY_DIR}/test-cache")
endfunction()
