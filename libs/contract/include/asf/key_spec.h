#pragma once
/// \file key_spec.h
/// Declaration of the INI keys a plugin accepts. The list in a plugin's descriptor is the
/// single source for validation (unknown/missing keys, types, ranges), `asf config` and docs.
#include <cstdint>
#include <limits>

namespace asf {

enum class KeyType : std::uint32_t {
  Bool = 0,    ///< true/false, 1/0, yes/no, on/off
  Int = 1,     ///< integer (64-bit)
  Double = 2,  ///< real number
  String = 3,  ///< free text
  Enum = 4,    ///< one of `choices` ('|'-separated)
  Path = 5,    ///< file or folder; relative paths resolve against the INI file's folder
  DoubleList = 6,  ///< whitespace or comma separated reals
};

const char* keyTypeName(KeyType t);

/// One INI key. Plain data so descriptors can be static constants in a plugin.
struct KeySpec {
  const char* name;           ///< lower_snake_case
  KeyType type;
  const char* default_value;  ///< nullptr: the key is required
  const char* doc;            ///< one line: meaning and unit
  double min = -std::numeric_limits<double>::infinity();  ///< Int/Double/DoubleList items
  double max = std::numeric_limits<double>::infinity();
  const char* choices = nullptr;  ///< Enum only: "a|b|c"
};

// Helpers that read well in a descriptor's key table.
constexpr KeySpec keyBool(const char* name, const char* def, const char* doc) {
  return KeySpec{name, KeyType::Bool, def, doc};
}
constexpr KeySpec keyInt(const char* name, const char* def, const char* doc,
                         double min = -std::numeric_limits<double>::infinity(),
                         double max = std::numeric_limits<double>::infinity()) {
  return KeySpec{name, KeyType::Int, def, doc, min, max};
}
constexpr KeySpec keyDouble(const char* name, const char* def, const char* doc,
                            double min = -std::numeric_limits<double>::infinity(),
                            double max = std::numeric_limits<double>::infinity()) {
  return KeySpec{name, KeyType::Double, def, doc, min, max};
}
constexpr KeySpec keyString(const char* name, const char* def, const char* doc) {
  return KeySpec{name, KeyType::String, def, doc};
}
constexpr KeySpec keyEnum(const char* name, const char* def, const char* choices,
                          const char* doc) {
  return KeySpec{name, KeyType::Enum, def, doc, -std::numeric_limits<double>::infinity(),
                 std::numeric_limits<double>::infinity(), choices};
}
constexpr KeySpec keyPath(const char* name, const char* def, const char* doc) {
  return KeySpec{name, KeyType::Path, def, doc};
}
constexpr KeySpec keyDoubleList(const char* name, const char* def, const char* doc,
                                double min = -std::numeric_limits<double>::infinity(),
                                double max = std::numeric_limits<double>::infinity()) {
  return KeySpec{name, KeyType::DoubleList, def, doc, min, max};
}

}  // namespace asf
