# What asf::contract needs, and so every out-of-tree plugin: MRPT system, poses and config,
# and Eigen; a missing one stops configure naming the Debian package. Included by
# AsfDependencies.cmake (the whole of asf) and by an installed asfConfig.cmake.
include_guard(GLOBAL)

macro(asf_require _found _what _pkg)
  if(NOT ${_found})
    message(FATAL_ERROR "asf: ${_what} not found. Install it with:\n"
                        "  sudo apt-get install ${_pkg}\n"
                        "or run scripts/install-deps.sh (installs everything asf needs).")
  endif()
endmacro()

# MRPT 2.x ships one package per module (mrpt-<module>); its MRPT wrapper has no version file,
# so the version is checked on the modules.
foreach(_m core system config poses)
  find_package(mrpt-${_m} 2.5 CONFIG QUIET)
  asf_require(mrpt-${_m}_FOUND "MRPT >= 2.5 (module mrpt-${_m})" libmrpt-dev)
endforeach()

find_package(Eigen3 3.4 CONFIG QUIET)
asf_require(Eigen3_FOUND "Eigen >= 3.4" libeigen3-dev)
