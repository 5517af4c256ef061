# asf_add_library(<target> EXPORT_NAME <name> EXPORT_SET <set> SOURCES <files...>)
#
# One of asf's shared libraries (asf::<name>): versioned like the project, public headers in
# <dir>/include installed to include/asf, every symbol resolved at link time
# (--no-undefined, except under sanitizers, whose runtime is the executable's), installed
# into the export set. Link its dependencies with target_link_libraries afterwards.
include_guard(GLOBAL)

function(asf_add_library target)
  cmake_parse_arguments(ARG "" "EXPORT_NAME;EXPORT_SET" "SOURCES" ${ARGN})
  add_library(${target} SHARED ${ARG_SOURCES})
  add_library(asf::${ARG_EXPORT_NAME} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${ARG_EXPORT_NAME}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(NOT ASF_SANITIZE)
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
  install(TARGETS ${target} EXPORT ${ARG_EXPORT_SET} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/asf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
