#pragma once
// Helpers shared by the framework tests.
#include <functional>
#include <string>

namespace asf_test {

/// The message of the E that fn throws, or a text no expectation matches.
template <class E>
std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const E& e) {
    return e.what();
  }
  return "(no exception of the expected type thrown)";
}

inline bool has(const std::string& hay, const std::string& needle) {
  return hay.find(needle) != std::string::npos;
}

}  // namespace asf_test
