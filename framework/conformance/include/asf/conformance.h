#pragma once
/// \file conformance.h
/// The plugin conformance kit: GoogleTest suites, one per plugin kind, that check a plugin
/// against the contract of its interface (see source.h ... policy.h) and the descriptor
/// rules. Run it with `asf conformance FILE.so|NAME...`, or from your own test binary:
/// \code
///   int main(int argc, char** argv) {
///     auto info = asf::Registry::loadFile("my_policy.so");
///     return asf::conformance::run({info}, argc, argv);
///   }
/// \endcode
#include <asf/registry.h>

#include <memory>
#include <vector>

namespace asf::conformance {

/// Registers the kit's tests for one plugin with GoogleTest (suite "<kind>/<name>").
/// Call after testing::InitGoogleTest and before RUN_ALL_TESTS.
void registerTests(const std::shared_ptr<const PluginInfo>& plugin);

/// InitGoogleTest(argc, argv) (so --gtest_filter etc. work), registerTests for each plugin,
/// RUN_ALL_TESTS. Returns its exit code (0 = every test passed).
int run(const std::vector<std::shared_ptr<const PluginInfo>>& plugins, int argc, char** argv);

}  // namespace asf::conformance
