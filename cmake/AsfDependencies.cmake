# Finds the dependencies of the whole of asf (the contract's first); a missing one stops
# configure naming the Debian package. Used by the build tree and by an installed
# asfConfig.cmake when a component beyond the contract is asked for.
include_guard(GLOBAL)
include(${CMAKE_CURRENT_LIST_DIR}/AsfContractDependencies.cmake)

# The other MRPT modules. slam: CICP (icp_graph); graphslam: the mrpt_levmarq baseline back-end;
# gui: the live view of `asf run --gui` (apps/asf/live_window.cpp, loaded only then).
set(ASF_MRPT_MODULES obs maps graphs slam graphslam gui)
foreach(_m ${ASF_MRPT_MODULES})
  find_package(mrpt-${_m} 2.5 CONFIG QUIET)
  asf_require(mrpt-${_m}_FOUND "MRPT >= 2.5 (module mrpt-${_m})" libmrpt-dev)
endforeach()

# ximgproc (opencv_contrib; Debian's libopencv-dev depends on libopencv-contrib-dev): the
# GVG's thinning (framework/src/voronoi_graph.cpp).
find_package(OpenCV 4 QUIET COMPONENTS core imgproc imgcodecs ximgproc)
asf_require(OpenCV_FOUND "OpenCV 4 (core, imgproc, imgcodecs, ximgproc)" libopencv-dev)

find_package(octomap CONFIG QUIET)
asf_require(octomap_FOUND "OctoMap" liboctomap-dev)

# SuiteSparse 5 (bookworm) ships no CMake package: find CHOLMOD by hand.
find_path(ASF_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(ASF_CHOLMOD_LIBRARY cholmod)
if(ASF_CHOLMOD_INCLUDE_DIR AND ASF_CHOLMOD_LIBRARY)
  set(ASF_CHOLMOD_FOUND TRUE)
endif()
asf_require(ASF_CHOLMOD_FOUND "SuiteSparse CHOLMOD" libsuitesparse-dev)
if(NOT TARGET asf_deps::cholmod)
  add_library(asf_deps::cholmod INTERFACE IMPORTED)
  set_target_properties(asf_deps::cholmod PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES ${ASF_CHOLMOD_INCLUDE_DIR}
    INTERFACE_LINK_LIBRARIES ${ASF_CHOLMOD_LIBRARY})
endif()

find_package(Threads REQUIRED)

# The conformance kit (part of the installed framework) is GoogleTest based.
find_package(GTest CONFIG QUIET)
if(NOT GTest_FOUND)
  find_package(GTest QUIET)
endif()
asf_require(GTest_FOUND "GoogleTest" "libgtest-dev libgmock-dev")

find_package(nlohmann_json 3 CONFIG QUIET)
asf_require(nlohmann_json_FOUND "nlohmann-json 3" nlohmann-json3-dev)

# bzip2 (C API): the Rawseeds streams are distributed as .csv.bz2 (asf rawseeds2rawlog).
find_package(BZip2 QUIET)
asf_require(BZIP2_FOUND "bzip2 library (libbz2)" libbz2-dev)
# zlib (C API): gzip-compressed text logs (CARMEN .log.gz), with truncation detected.
find_package(ZLIB QUIET)
asf_require(ZLIB_FOUND "zlib" zlib1g-dev)
# SQLite (C API): ROS 2 bags (rosbag2's sqlite3 storage; asf bag2rawlog).
find_package(SQLite3 QUIET)
asf_require(SQLite3_FOUND "SQLite 3" libsqlite3-dev)
# MCAP chunks: Zstandard and LZ4 (frame format), C APIs.
find_library(ASF_ZSTD_LIB zstd)
find_path(ASF_ZSTD_INCLUDE zstd.h)
asf_require(ASF_ZSTD_LIB "Zstandard (libzstd)" libzstd-dev)
find_library(ASF_LZ4_LIB lz4)
find_path(ASF_LZ4_INCLUDE lz4frame.h)
asf_require(ASF_LZ4_LIB "LZ4 (liblz4)" liblz4-dev)
# ROS 1 bags: the official ROS 1 library (Debian's librosbag-storage). Found by hand: its
# catkin CMake package pulls in ament's Python tools, which need not be there.
find_path(ASF_ROSBAG_INCLUDE_DIR rosbag/bag.h)
find_library(ASF_ROSBAG_STORAGE_LIB rosbag_storage)
find_library(ASF_ROSCPP_SERIALIZATION_LIB roscpp_serialization)
find_library(ASF_ROSTIME_LIB rostime)
find_library(ASF_CPP_COMMON_LIB cpp_common)
set(ASF_ROSBAG_FOUND FALSE)
if(ASF_ROSBAG_INCLUDE_DIR AND ASF_ROSBAG_STORAGE_LIB AND ASF_ROSCPP_SERIALIZATION_LIB
   AND ASF_ROSTIME_LIB AND ASF_CPP_COMMON_LIB)
  set(ASF_ROSBAG_FOUND TRUE)
endif()
set(ASF_ROSBAG_LIBRARIES ${ASF_ROSBAG_STORAGE_LIB} ${ASF_ROSCPP_SERIALIZATION_LIB}
    ${ASF_ROSTIME_LIB} ${ASF_CPP_COMMON_LIB})
set(ASF_ROSBAG_INCLUDE_DIRS ${ASF_ROSBAG_INCLUDE_DIR})
# rosbag/bag.h includes pluginlib, which Debian installs ROS 2 style (include/<pkg>/<pkg>/...).
foreach(_h pluginlib/class_loader.hpp class_loader/multi_library_class_loader.hpp
        rcpputils/shared_library.hpp rcutils/shared_library.h
        ament_index_cpp/get_package_prefix.hpp)
  string(REGEX REPLACE "/.*" "" _pkg "${_h}")
  find_path(ASF_ROSBAG_INC_${_pkg} ${_h} PATH_SUFFIXES ${_pkg})
  if(ASF_ROSBAG_INC_${_pkg})
    list(APPEND ASF_ROSBAG_INCLUDE_DIRS ${ASF_ROSBAG_INC_${_pkg}})
  else()
    set(ASF_ROSBAG_FOUND FALSE)
  endif()
endforeach()
asf_require(ASF_ROSBAG_FOUND "ROS 1 rosbag_storage" librosbag-storage-dev)

