#pragma once
/// \file errors.h
/// Exceptions thrown by the framework. Every message carries its context (file, line,
/// section, key, plugin) so the host can print it as is.
///
/// The classes are exported and have their destructor defined in the framework library (the
/// key function), so their vtables and type information live there and nowhere else. A
/// plugin (built with hidden visibility) that throws one then refers to the framework's
/// copy: the exception stays valid after the registry unloads the plugin while it unwinds.
#include <asf/abi.h>

#include <stdexcept>
#include <string>

namespace asf {

/// Base of every asf error.
class ASF_EXPORT Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  ~Error() override;
};

/// Bad configuration: INI syntax, unknown/missing key, bad value. what() names file:line.
class ASF_EXPORT ConfigError : public Error {
 public:
  using Error::Error;
  ~ConfigError() override;
};

/// A plugin file that cannot be used: not a plugin, ABI mismatch, duplicate, factory failure.
class ASF_EXPORT PluginError : public Error {
 public:
  using Error::Error;
  ~PluginError() override;
};

/// Bad input data (a malformed file or record). what() names the file and line/record.
class ASF_EXPORT InputError : public Error {
 public:
  using Error::Error;
  ~InputError() override;
};

}  // namespace asf
