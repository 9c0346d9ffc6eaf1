# zbrdf_precompile_common_headers(TARGET [EXTRA...]): the standard, Eigen and JSON headers most
# sources include (and EXTRA), parsed once per target instead of once per source. Eigen and JSON
# come through basis/eigen_instances.h and basis/json_instances.h, which also keep Eigen's dense
# kernels and decompositions and JSON's serializer and parser from being compiled again in every
# source that uses them (basis/eigen_instances.cc and basis/json_instances.cc have them). GCC
# takes a precompiled header only if it was made with the same code-generation flags (-fPIE/-fPIC,
# -O, -pthread's _REENTRANT) and with no command-line macro the user lacks, so headers are shared
# only between targets compiled alike: every library reuses one (zbrdf_library_pch below), every
# test binary another. Sources still include what they use; the layering and write-site tests
# read the sources. -DZBRDF_PCH=OFF turns it off.
option(ZBRDF_PCH "precompile the common headers" ON)
function(zbrdf_precompile_common_headers target)
  if(ZBRDF_PCH)
    target_precompile_headers(${target} PRIVATE
      <algorithm> <array> <cmath> <cstdint> <functional> <map> <memory> <string> <vector>
      "${PROJECT_SOURCE_DIR}/basis/eigen_instances.h" "${PROJECT_SOURCE_DIR}/basis/json_instances.h"
      ${ARGN})
  endif()
endfunction()

# zbrdf_share_common_headers(TARGET GROUP [EXTRA...]): TARGET takes the precompiled header of the
# first target of GROUP, which makes it (zbrdf_precompile_common_headers with EXTRA). Only for
# targets compiled alike (flags, -O, PIE/PIC, macros; a target may define more): the tests share
# one, the benchmarks another.
function(zbrdf_share_common_headers target group)
  get_property(host GLOBAL PROPERTY ZBRDF_PCH_HOST_${group})
  if(ZBRDF_PCH AND host)
    target_precompile_headers(${target} REUSE_FROM ${host})
  else()
    zbrdf_precompile_common_headers(${target} ${ARGN})
    set_property(GLOBAL PROPERTY ZBRDF_PCH_HOST_${group} ${target})
  endif()
endfunction()

# The libraries' shared precompiled header: made once, by an object library with no sources of
# its own and no command-line macros (a header made with -DX is refused by a source compiled
# without it; one made without is taken by sources that define more), compiled as the libraries
# are (Release flags, -fPIC from CMAKE_POSITION_INDEPENDENT_CODE) and with -pthread, which every
# library is given below. Measured: ten headers of ~5 s of CPU each became one, and
# -Winvalid-pch (CMake's default) stays silent.
function(zbrdf_use_library_pch target)
  target_compile_options(${target} PRIVATE -pthread)
  if(NOT ZBRDF_PCH)
    return()
  endif()
  # Clang also refuses a header made with another default visibility, which GCC takes: a target
  # compiled with -fvisibility=hidden (pybind11 sets it for the Python module) parses its headers
  # itself under clang (one source there: a header of its own would cost more than it saves).
  get_target_property(visibility ${target} CXX_VISIBILITY_PRESET)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang" AND visibility STREQUAL "hidden")
    return()
  endif()
  if(NOT TARGET zbrdf_library_pch)
    add_library(zbrdf_library_pch OBJECT "${PROJECT_SOURCE_DIR}/cmake/library_pch.cc")
    target_link_libraries(zbrdf_library_pch PRIVATE Eigen3::Eigen nlohmann_json::nlohmann_json)
    target_compile_options(zbrdf_library_pch PRIVATE -pthread)
    zbrdf_precompile_common_headers(zbrdf_library_pch)
  endif()
  target_precompile_headers(${target} REUSE_FROM zbrdf_library_pch)
endfunction()

# zbrdf_unity_build(TARGET): TARGET's sources compile eight to a compiler run, so that the templates
# and inline functions they share (Eigen's, the standard library's, JSON's, OpenCV's, the
# libraries' headers) are instantiated and optimized once per batch instead of once per source.
# Measured on a clean build: the libraries 617 -> 399 s of compiler CPU (-35%). A unity batch is one
# translation unit, so a library's sources must not give two file-local helpers the same name
# (two `Since` or `kFormat` in anonymous namespaces would clash, or worse, overload each other):
# tests/unity_names_test.cc holds every library to that. -DZBRDF_UNITY_BUILD=OFF compiles one
# source per run (quicker rebuilds of a single edited file, and a check that each source includes
# what it uses, which a batch can hide).
option(ZBRDF_UNITY_BUILD "compile the libraries' sources in batches of eight" ON)
function(zbrdf_unity_build target)
  if(ZBRDF_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
    # GCC takes a source included by the batch file for a header, and warns when a class defined
    # there (a pimpl's Impl) has a member of a type from the file's anonymous namespace; in a
    # source that is the usual pattern, so that warning is off for unity targets (and only it).
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
    endif()
  endif()
endfunction()

# zbrdf_library(NAME DEPS...): a static library from every .cc file in the calling folder.
# Sources are globbed so that adding a file pair needs no CMake edit; CONFIGURE_DEPENDS makes
# the build notice new files.
function(zbrdf_library name)
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cc")
  if(sources)
    add_library(${name} STATIC ${sources})
    zbrdf_unity_build(${name})
    target_include_directories(${name} PUBLIC "${PROJECT_SOURCE_DIR}")
    target_link_libraries(${name} PUBLIC ${ARGN})
    zbrdf_use_library_pch(${name})
  else()  # a folder whose sources have not landed yet
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE "${PROJECT_SOURCE_DIR}")
    target_link_libraries(${name} INTERFACE ${ARGN})
  endif()
endfunction()

# zbrdf_compile_as_test(TARGET): compiles a test executable's sources the way every test binary's
# are (zbrdf_test_folder below; the drivers', the GigE capture's and the source checks' binaries,
# made by hand for their own CTest properties, call it too).
function(zbrdf_compile_as_test name)
  # Unity build: eight test files per compiler run, so that the templates and inline functions
  # they share (GoogleTest's, Eigen's, the libraries' headers) are instantiated and compiled once
  # per batch instead of once per file. Measured on tests/brdf with the precompiled header: 51 s
  # of CPU -> 37 s. Each file keeps its own names: its anonymous namespace holds a namespace
  # named ZBRDF_TEST_FILE_ID, which CMake defines to a value unique to the file, so two files'
  # helpers (a kZone, a Fitter()) never meet. A new test file follows the same pattern:
  #   namespace zbrdf { namespace { namespace ZBRDF_TEST_FILE_ID { ... } } }
  set_target_properties(${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8
                                           UNITY_BUILD_UNIQUE_ID ZBRDF_TEST_FILE_ID)
  # The test binaries share one precompiled header (the first test folder's): unlike the
  # libraries, they are compiled with the same flags and macros (a binary may define more, as the
  # drivers' tests do). -pthread (which defines _REENTRANT) is given to every one, since some get
  # it from the libraries they link and GCC would reject the header in those. Measured on a clean
  # build: 345 s of CPU for the tests with one header per binary, about 175 s with the shared one.
  target_compile_options(${name} PRIVATE -pthread)
  # main(): GoogleTest's, after the process setup the zbrdf CLI does (tests/test_main.cc), in
  # place of GTest::gtest_main.
  target_sources(${name} PRIVATE "${PROJECT_SOURCE_DIR}/tests/test_main.cc")
  target_include_directories(${name} PRIVATE "${PROJECT_SOURCE_DIR}")  # binaries linking no library
  zbrdf_share_common_headers(${name} tests <gtest/gtest.h> <filesystem>)
  # The header's Eigen and JSON includes need their include paths (header-only targets).
  target_link_libraries(${name} PRIVATE Eigen3::Eigen nlohmann_json::nlohmann_json)
  # Test sources compile at -O1 (about 30% faster than -O3, measured on conversion_test.cc and
  # crash_test.cc); the libraries they test keep the build type's optimization.
  if(CMAKE_BUILD_TYPE STREQUAL "Release")
    target_compile_options(${name} PRIVATE -O1)
  endif()
  target_compile_definitions(${name} PRIVATE
    ZBRDF_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ZBRDF_TEST_DATA_DIR="${PROJECT_SOURCE_DIR}/tests/data"
    ZBRDF_BINARY_DIR="${PROJECT_BINARY_DIR}")
endfunction()

# zbrdf_test_folder(NAME DEPS...): one GoogleTest binary from every *_test.cc in the calling
# folder, each test registered with CTest.
function(zbrdf_test_folder name)
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc")
  if(NOT sources)
    return()
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE ${ARGN} GTest::gtest Threads::Threads)
  zbrdf_compile_as_test(${name})
  # Every test process shares the build tree's cache (direction maps, light transports, true
  # coefficients): a transport one test builds, the next one with the same rig, material and seed
  # reads (entries are written by atomic rename, so concurrent tests are safe).
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${name}
                       ENVIRONMENT "ZBRDF_CACHE_DIR=${PROJECT_BINARY_DIR}/test-cache")
endfunction()
