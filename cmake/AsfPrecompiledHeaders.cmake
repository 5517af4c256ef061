# asf_precompile_headers(<target> <header>...)
#
# Precompiles the headers most of <target>'s sources include (MRPT, Eigen, nlohmann/json,
# TCLAP, GoogleTest, the standard library): each translation unit then loads them instead of
# parsing them again (1-3 s of a 4-10 s compile here; the rest is code generation). The lists
# name only headers outside the repository, so editing asf's own headers never rebuilds a
# precompiled header. Turned off with -DASF_PRECOMPILED_HEADERS=OFF (every source still compiles without
# them: they only add includes a source already has).
include_guard(GLOBAL)
option(ASF_PRECOMPILED_HEADERS "Precompile the third-party headers of the larger targets" ON)

function(asf_precompile_headers target)
  if(ASF_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()

# Every test executable reuses one precompiled header (they compile with the same flags),
# built by this object library; asf_add_gtest points each test at it.
function(asf_add_test_headers)
  if(NOT ASF_PRECOMPILED_HEADERS)
    return()
  endif()
  set(_anchor ${PROJECT_BINARY_DIR}/asf_test_headers.cpp)
  if(NOT EXISTS ${_anchor})
    file(WRITE ${_anchor} "// Anchor of the tests' precompiled header (cmake/AsfPrecompiledHeaders.cmake).\n")
  endif()
  add_library(asf_test_headers OBJECT ${_anchor})
  # Compiled as the executables are (-fPIE, not an object library's -fPIC): GCC refuses a
  # precompiled header made with the other.
  set_target_properties(asf_test_headers PROPERTIES POSITION_INDEPENDENT_CODE OFF)
  target_compile_options(asf_test_headers PRIVATE -fPIE)
  target_link_libraries(asf_test_headers PRIVATE asf_framework GTest::gtest nlohmann_json::nlohmann_json)
  asf_test_definitions(asf_test_headers)
  target_precompile_headers(asf_test_headers PRIVATE
    <gtest/gtest.h> <nlohmann/json.hpp> <Eigen/Core> <mrpt/poses/CPose2D.h>
    <algorithm> <cmath> <filesystem> <fstream> <map> <sstream> <string> <vector>)
endfunction()
