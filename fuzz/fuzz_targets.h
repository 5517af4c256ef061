#pragma once
/// \file fuzz_targets.h
/// One entry per parser a user feeds asf (issue 20): the bytes of a file in, through the
/// reader asf uses for it. A rejection is an asf::Error (it names the file); anything else
/// escaping an entry (another exception, a crash, a sanitizer report) is a defect.
///
/// The same entries run under libFuzzer (fuzz/fuzz_main.cpp, scripts/fuzz.sh) and as a test
/// that replays the seed corpus and the regressions found by fuzzing
/// (tests/test_fuzz_corpus.cpp, fuzz/corpus/<name>/, fuzz/regressions/<name>/).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace asf::fuzz {

struct Target {
  const char* name;  ///< also the corpus folder's name
  /// Feeds `data` to the parser; returns whether it was accepted (false: an asf::Error).
  bool (*run)(const std::uint8_t* data, std::size_t size);
  const char* what;  ///< one line: which reader, for `scripts/fuzz.sh` and docs
};

/// Every target, in a fixed order.
const std::vector<Target>& targets();
/// The target called `name`, or nullptr.
const Target* findTarget(const std::string& name);

}  // namespace asf::fuzz
