# zbrdf_library(NAME DEPS...): a static library from every .cc file in the calling folder.
# Sources are globbed so that adding a file pair needs no CMake edit; CONFIGURE_DEPENDS makes
# the build notice new files.
function(zbrdf_library name)
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cc")
  if(sources)
    add_library(${name} STATIC ${sources})
    target_include_directories(${name} PUBLIC "${PROJECT_SOURCE_DIR}")
    target_link_libraries(${name} PUBLIC ${ARGN})
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
