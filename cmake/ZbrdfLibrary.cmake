# zbrdf_precompile_common_headers(TARGET KIND [EXTRA...]): the standard, Eigen and JSON headers
# most sources include (and EXTRA), parsed once instead of once per source: a clean build on 2
# cores spent most of its time parsing them. The first target of a KIND ("library", "test")
# compiles the header and the others of that kind reuse it (their compile flags are the same).
# Sources still include what they use; the layering and write-site tests read the sources, not
# this list. -DZBRDF_PCH=OFF turns it off.
option(ZBRDF_PCH "precompile the common headers (one per kind of target)" ON)
function(zbrdf_precompile_common_headers target kind)
  if(NOT ZBRDF_PCH)
    return()
  endif()
  get_property(host GLOBAL PROPERTY ZBRDF_PCH_HOST_${kind})
  if(host)
    target_precompile_headers(${target} REUSE_FROM ${host})
  else()
    target_precompile_headers(${target} PRIVATE
      <algorithm> <array> <cmath> <cstdint> <functional> <map> <memory> <string> <vector>
      <Eigen/Dense> <nlohmann/json.hpp> ${ARGN})
    set_property(GLOBAL PROPERTY ZBRDF_PCH_HOST_${kind} ${target})
  endif()
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
  zbrdf_precompile_common_headers(${name} test <gtest/gtest.h> <filesystem>)
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
