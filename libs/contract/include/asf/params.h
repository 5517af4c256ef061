#pragma once
/// \file params.h
/// The validated values of one INI section, every key of the plugin's descriptor present
/// (given or default). Getters throw asf::ConfigError naming file:line, section and key.
#include <asf/key_spec.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace asf {

class Params {
 public:
  struct Value {
    std::string text;     ///< the value as written (or the default)
    KeyType type = KeyType::String;
    bool is_default = true;
    std::string origin;   ///< "file.ini:12", "--set", or "default"
  };

  Params() = default;
  /// \param section the INI section these values come from (for messages)
  explicit Params(std::string section) : section_(std::move(section)) {}

  const std::string& section() const { return section_; }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  bool isDefault(const std::string& key) const { return at(key).is_default; }

  bool getBool(const std::string& key) const;
  std::int64_t getInt(const std::string& key) const;
  double getDouble(const std::string& key) const;
  std::string getString(const std::string& key) const;
  std::vector<double> getDoubleList(const std::string& key) const;

  /// Throws ConfigError "<origin>: [section] key = value: <why>"; plugins use it for
  /// checks across keys that a range cannot express.
  [[noreturn]] void fail(const std::string& key, const std::string& why) const;

  /// Sets a value (used by the config loader and by tests).
  void set(const std::string& key, Value v) { values_[key] = std::move(v); }
  const std::map<std::string, Value>& values() const { return values_; }

  /// Builds Params from a key table with every default filled in (no INI file); throws
  /// ConfigError if `overrides` names a key the table lacks or a value does not parse.
  static Params fromSpecs(const std::string& section, const KeySpec* keys, std::size_t n,
                          const std::map<std::string, std::string>& overrides = {});

 private:
  const Value& at(const std::string& key) const;
  std::string section_;
  std::map<std::string, Value> values_;
};

/// Checks one value against its spec; returns an empty string when valid, else why not.
std::string validateValue(const KeySpec& spec, const std::string& text);

}  // namespace asf
