#pragma once
/// \file text.h
/// Small text and timing helpers, defined once for the host, the libraries and the plugins.
#include <chrono>
#include <string>
#include <vector>

namespace asf {

/// `s` without leading and trailing white space (space, \t, \r, \n, \f, \v).
std::string trim(const std::string& s);

/// The items of `s` between the separators `sep`, trimmed, the empty ones left out
/// ("a; b;; c" -> a, b, c): INI lists such as an experiment's policies and overrides.
std::vector<std::string> splitTrimmed(const std::string& s, char sep);

/// `v` in fixed notation with `digits` decimals (printf's "%.*f"; "inf", "nan" as printf).
std::string formatFixed(double v, int digits);

/// `v` with `digits` significant digits, as an iostream prints it after setprecision(digits)
/// (printf's "%.*g").
std::string formatSignificant(double v, int digits);

/// `text` with & < > " escaped, for HTML and SVG text and attributes.
std::string htmlEscape(const std::string& text);

/// `s` with ASCII letters in lower case (INI sections, keys, file extensions).
std::string lowercase(std::string s);

/// Seconds elapsed since `t0` on the steady clock.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Milliseconds elapsed since `t0` on the steady clock.
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace asf
