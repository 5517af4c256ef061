# asf_add_plugin(<target> SOURCES <files...> [LIBRARIES <libs...>] [NO_CONFORMANCE]
#                [CONFORMANCE_CONFIG <file.ini>])
#
# Builds an asf plugin: a MODULE library <target>.so, linked against asf::contract and
# LIBRARIES (asf::framework for the runtime's services), that exports only its descriptor,
# written to the plugin folder (build tree: lib/asf/plugins, or ASF_PLUGIN_OUTPUT_DIRECTORY)
# and installed to <libdir>/asf/plugins. With testing enabled it also adds the CTest test
# conformance.<target>, which runs the conformance kit (`asf conformance <file>`) on it;
# CONFORMANCE_CONFIG passes an INI whose [<plugin name>] section configures the plugin there
# (`asf conformance --config`: for keys the kit cannot make up, such as a data file).
include_guard(GLOBAL)
include(GNUInstallDirs)

function(asf_add_plugin target)
  cmake_parse_arguments(ARG "NO_CONFORMANCE" "CONFORMANCE_CONFIG" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "asf_add_plugin(${target}): SOURCES is required")
  endif()
  add_library(${target} MODULE ${ARG_SOURCES})
  # asf_runtime (the top-level CMakeLists) builds the host and every plugin, nothing else.
  set_property(GLOBAL APPEND PROPERTY ASF_PLUGIN_TARGETS ${target})
  # The contract alone; a plugin using more of asf names it (LIBRARIES asf::framework).
  if(TARGET asf_contract)
    target_link_libraries(${target} PRIVATE asf_contract ${ARG_LIBRARIES})
  else()
    target_link_libraries(${target} PRIVATE asf::contract ${ARG_LIBRARIES})
  endif()
  # Every symbol resolved at link time: a library missing from LIBRARIES is a link error here,
  # not a failed dlopen in the host. (Not under sanitizers: their runtime is the executable's.)
  if(NOT ASF_SANITIZE)
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
  if(NOT ASF_PLUGIN_OUTPUT_DIRECTORY)
    set(ASF_PLUGIN_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/lib/asf/plugins)
  endif()
  if(NOT ASF_PLUGIN_INSTALL_DIR)
    set(ASF_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/asf/plugins)
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY ${ASF_PLUGIN_OUTPUT_DIRECTORY}
    INSTALL_RPATH "$ORIGIN/../..;$ORIGIN")
  install(TARGETS ${target} LIBRARY DESTINATION ${ASF_PLUGIN_INSTALL_DIR})

  if(NOT ARG_NO_CONFORMANCE AND BUILD_TESTING_ASF_CONFORMANCE)
    # The host runs the kit, so the test also exercises loading through the registry.
    if(TARGET asf)
      set(_asf_exe $<TARGET_FILE:asf>)
    else()
      set(_asf_exe ${ASF_EXECUTABLE})
    endif()
    set(_asf_conf_args)
    if(ARG_CONFORMANCE_CONFIG)
      set(_asf_conf_args --config ${ARG_CONFORMANCE_CONFIG})
    endif()
    add_test(NAME conformance.${target}
             COMMAND ${_asf_exe} conformance ${_asf_conf_args} $<TARGET_FILE:${target}>)
  endif()
endfunction()
