# asf_add_gtest(<name> SOURCES <files...> [LIBRARIES <libs...>] [DEPENDS <targets...>])
#
# A GoogleTest executable registered with CTest (tests discovered at test time). Compile
# definitions every test may use:
#   ASF_TEST_PLUGIN_DIR  folder of the built plugins (load them with asf::Registry::loadFile)
#   ASF_TEST_BINARY_DIR  the build tree's top folder
#   ASF_TEST_SOURCE_DIR  the source tree's top folder
#   ASF_TEST_SHARED_DIR  ../shared beside the repository (may not exist: GTEST_SKIP then)
include_guard(GLOBAL)
include(GoogleTest)
include(AsfPrecompiledHeaders)

# The definitions every test compiles with (also the tests' precompiled header's).
function(asf_test_definitions target)
  target_compile_definitions(${target} PRIVATE
    ASF_TEST_PLUGIN_DIR="${ASF_PLUGIN_OUTPUT_DIRECTORY}"
    ASF_TEST_BINARY_DIR="${PROJECT_BINARY_DIR}"
    ASF_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ASF_TEST_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared")
endfunction()

function(asf_add_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;DEPENDS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE asf_framework GTest::gtest GTest::gtest_main ${ARG_LIBRARIES})
  asf_test_definitions(${name})
  if(TARGET asf_test_headers)
    target_precompile_headers(${name} REUSE_FROM asf_test_headers)
  endif()
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  if(ARG_DEPENDS)
    add_dependencies(${name} ${ARG_DEPENDS})
  endif()
  gtest_discover_tests(${name} DISCOVERY_MODE PRE_TEST
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
endfunction()
