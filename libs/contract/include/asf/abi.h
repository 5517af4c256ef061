#pragma once
/// \file abi.h
/// Framework ABI version and symbol visibility. The ABI version changes whenever a plugin
/// interface, a shared data type or the descriptor layout changes; the registry refuses
/// plugins built against another version.
#include <cstdint>

#define ASF_ABI_VERSION 7u
#define ASF_VERSION_STRING "0.1.0"

#define ASF_EXPORT __attribute__((visibility("default")))

/// Name of the one symbol every plugin exports (see ASF_PLUGIN in plugin.h).
#define ASF_PLUGIN_ENTRY_SYMBOL "asf_plugin_descriptor"
