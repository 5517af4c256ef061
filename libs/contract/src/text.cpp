#include <asf/text.h>

#include <cctype>
#include <cstdio>
#include <sstream>

namespace asf {

std::string trim(const std::string& s) {
  const char* const space = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(space);
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(space) - b + 1);
}

std::vector<std::string> splitTrimmed(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, sep);)
    if (!trim(item).empty()) out.push_back(trim(item));
  return out;
}

std::string formatFixed(double v, int digits) {
  char b[512];  // %.*f of 1e308 with 17 decimals fits
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

std::string formatSignificant(double v, int digits) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

std::string htmlEscape(const std::string& text) {
  std::string o;
  o.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

std::string lowercase(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace asf
