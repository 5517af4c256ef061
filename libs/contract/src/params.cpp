#include <asf/config.h>
#include <asf/errors.h>
#include <asf/params.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace asf {

const char* keyTypeName(KeyType t) {
  switch (t) {
    case KeyType::Bool: return "bool";
    case KeyType::Int: return "int";
    case KeyType::Double: return "double";
    case KeyType::String: return "string";
    case KeyType::Enum: return "enum";
    case KeyType::Path: return "path";
    case KeyType::DoubleList: return "double-list";
  }
  return "unknown";
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool parseBool(const std::string& t, bool& out) {
  const std::string s = lower(t);
  if (s == "true" || s == "1" || s == "yes" || s == "on") return out = true, true;
  if (s == "false" || s == "0" || s == "no" || s == "off") return out = false, true;
  return false;
}

bool parseInt(const std::string& t, std::int64_t& out) {
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (errno == 0 && *end == '\0') {
    out = v;
    return true;
  }
  // MRPT's $eval{} prints reals ("4.000000e+01"): accept those that are whole numbers.
  errno = 0;
  const double d = std::strtod(t.c_str(), &end);
  if (errno != 0 || *end != '\0' || d != std::floor(d) || std::abs(d) > 9.0e15) return false;
  out = static_cast<std::int64_t>(d);
  return true;
}

bool parseDouble(const std::string& t, double& out) {
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (errno == ERANGE || *end != '\0' || !std::isfinite(v)) return false;
  out = v;
  return true;
}

bool parseDoubleList(const std::string& t, std::vector<double>& out) {
  out.clear();
  std::string s = t;
  std::replace(s.begin(), s.end(), ',', ' ');
  std::istringstream is(s);
  std::string tok;
  while (is >> tok) {
    double v;
    if (!parseDouble(tok, v)) return false;
    out.push_back(v);
  }
  return true;
}

std::string fmtNum(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string rangeCheck(const KeySpec& spec, double v) {
  if (v < spec.min || v > spec.max) {
    std::string r = "out of range [";
    r += std::isinf(spec.min) ? "-inf" : fmtNum(spec.min);
    r += ", ";
    r += std::isinf(spec.max) ? "inf" : fmtNum(spec.max);
    return r + "]";
  }
  return {};
}

}  // namespace

std::string validateValue(const KeySpec& spec, const std::string& text) {
  switch (spec.type) {
    case KeyType::Bool: {
      bool b;
      return parseBool(text, b) ? "" : "not a bool (true/false, 1/0, yes/no, on/off)";
    }
    case KeyType::Int: {
      std::int64_t v;
      if (!parseInt(text, v)) return "not an integer";
      return rangeCheck(spec, static_cast<double>(v));
    }
    case KeyType::Double: {
      double v;
      if (!parseDouble(text, v)) return "not a number";
      return rangeCheck(spec, v);
    }
    case KeyType::DoubleList: {
      std::vector<double> v;
      if (!parseDoubleList(text, v)) return "not a list of numbers";
      for (double x : v)
        if (auto r = rangeCheck(spec, x); !r.empty()) return "item " + fmtNum(x) + " " + r;
      return {};
    }
    case KeyType::Enum: {
      const std::string choices = spec.choices ? spec.choices : "";
      std::istringstream is(choices);
      std::string c;
      while (std::getline(is, c, '|'))
        if (c == text) return {};
      return "not one of " + choices;
    }
    case KeyType::String:
    case KeyType::Path:
      return {};
  }
  return "unknown key type";
}

const Params::Value& Params::at(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end())
    throw ConfigError("[" + section_ + "] key '" + key +
                      "' is not declared in the plugin's key table (a plugin bug)");
  return it->second;
}

void Params::fail(const std::string& key, const std::string& why) const {
  auto it = values_.find(key);
  std::string origin = it == values_.end() ? std::string("default") : it->second.origin;
  std::string text = it == values_.end() ? std::string() : it->second.text;
  throw ConfigError(origin + ": [" + section_ + "] " + key + " = '" + text + "': " + why);
}

bool Params::getBool(const std::string& key) const {
  bool b = false;
  if (!parseBool(at(key).text, b)) fail(key, "not a bool");
  return b;
}

std::int64_t Params::getInt(const std::string& key) const {
  std::int64_t v = 0;
  if (!parseInt(at(key).text, v)) fail(key, "not an integer");
  return v;
}

double Params::getDouble(const std::string& key) const {
  double v = 0;
  if (!parseDouble(at(key).text, v)) fail(key, "not a number");
  return v;
}

std::string Params::getString(const std::string& key) const { return at(key).text; }

std::vector<double> Params::getDoubleList(const std::string& key) const {
  std::vector<double> v;
  if (!parseDoubleList(at(key).text, v)) fail(key, "not a list of numbers");
  return v;
}

Params Params::fromSpecs(const std::string& section, const KeySpec* keys, std::size_t n,
                         const std::map<std::string, std::string>& overrides) {
  // The same validation as an INI file gets, so both report the same errors.
  IniConfig ini;
  for (const auto& [key, value] : overrides) ini.set(section, key, value, "override");
  return ini.resolve(section, keys, n);
}

}  // namespace asf
