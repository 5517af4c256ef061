#pragma once
/// \file config.h
/// MRPT-style INI configuration: parsed by MRPT (so @define, ${var}, $eval{}, $env{} work),
/// validated against the descriptors' key tables, with file:line in every error.
///
/// Sections and keys are case-insensitive (MRPT); full-line comments start with ';' or '#',
/// inline comments with '//'.
#include <asf/key_spec.h>
#include <asf/params.h>

#include <map>
#include <string>
#include <vector>

namespace asf {

class IniConfig {
 public:
  IniConfig() = default;
  /// The largest configuration file read (16 MiB): anything larger is refused unread.
  static constexpr std::size_t kMaxBytes = std::size_t{16} << 20;
  /// Throws ConfigError naming the file (and line for syntax errors); a file over kMaxBytes
  /// (or a device that never ends) is refused after reading kMaxBytes + 1 bytes.
  static IniConfig fromFile(const std::string& path);
  /// A leading UTF-8 byte order mark is skipped.
  static IniConfig fromText(const std::string& text, const std::string& name = "<text>");

  /// Applies one "section.key=value" override (the key is created if absent).
  void applyOverride(const std::string& assignment);
  void set(const std::string& section, const std::string& key, const std::string& value,
           const std::string& origin = "--set");

  const std::string& fileName() const { return name_; }
  /// Folder of the INI file (relative Path values resolve against it); "" for text.
  const std::string& baseDir() const { return base_dir_; }

  std::vector<std::string> sections() const;  ///< lowercase
  bool hasSection(const std::string& section) const;
  std::vector<std::string> keys(const std::string& section) const;  ///< lowercase
  bool has(const std::string& section, const std::string& key) const;
  std::string get(const std::string& section, const std::string& key) const;
  /// "file.ini:12" (or "file.ini" when the line is unknown, "--set" for overrides).
  std::string where(const std::string& section, const std::string& key = "") const;
  /// The one wording of an unknown section, for every reader of INI files:
  /// "file.ini:4: unknown section [s] (did you mean [k]?); <expected>", the hint from `known`
  /// when one is close, `expected` saying which sections the file may have.
  std::string unknownSection(const std::string& section, const std::vector<std::string>& known,
                             const std::string& expected) const;

  /// Validates a section against a key table: unknown keys (with "did you mean"), missing
  /// required keys, types, ranges, choices. Returns every key with its value or default;
  /// relative Path values are made absolute against baseDir(). Throws ConfigError listing
  /// every problem of the section.
  Params resolve(const std::string& section, const KeySpec* keys, std::size_t n) const;

 private:
  struct Entry {
    std::string value;
    std::string origin;  ///< file:line or --set
  };
  struct Section {
    std::string origin;
    std::map<std::string, Entry> entries;
  };
  std::string name_ = "<text>";
  std::string base_dir_;
  std::map<std::string, Section> sections_;
};

/// Closest candidate by edit distance, or "" if none is close enough to suggest.
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace asf
