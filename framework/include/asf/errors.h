#pragma once
/// \file errors.h
/// Exceptions thrown by the framework. Every message carries its context (file, line,
/// section, key, plugin) so the host can print it as is.
#include <stdexcept>
#include <string>

namespace asf {

/// Base of every asf error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad configuration: INI syntax, unknown/missing key, bad value. what() names file:line.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// A plugin file that cannot be used: not a plugin, ABI mismatch, duplicate, factory failure.
class PluginError : public Error {
 public:
  using Error::Error;
};

/// Bad input data (a malformed file or record). what() names the file and line/record.
class InputError : public Error {
 public:
  using Error::Error;
};

}  // namespace asf
