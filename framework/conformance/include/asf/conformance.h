#pragma once
/// \file conformance.h
/// The plugin conformance kit: GoogleTest suites, one per plugin kind, that check a plugin
/// against the contract of its interface (see source.h ... policy.h) and the descriptor
/// rules. Run it with `asf conformance FILE.so|NAME...`, or from your own test binary:
/// \code
///   int main(int argc, char** argv) {
///     auto info = asf::framework::Registry::loadFile("my_policy.so");
///     return asf::conformance::run({info}, argc, argv);
///   }
/// \endcode
#include <asf/config.h>
#include <asf/framework/registry.h>

#include <memory>
#include <vector>

namespace asf::conformance {

/// Registers the kit's tests for one plugin with GoogleTest (suite "<kind>/<name>").
/// Call after testing::InitGoogleTest and before RUN_ALL_TESTS.
///
/// `config` (optional, `asf conformance --config FILE.ini`): its section named after the
/// plugin, as in a pipeline INI, gives values the kit configures every instance with; the
/// kit makes up values only for the required keys it leaves out. It is how a plugin with a
/// key the kit cannot invent (a log source's data file) gets tested. The section is checked
/// against the plugin's key table here (throws ConfigError); relative paths resolve against
/// the INI's folder. Plugins without a section are configured as without `config`.
void registerTests(const std::shared_ptr<const framework::PluginInfo>& plugin,
                   const IniConfig* config = nullptr);

/// InitGoogleTest(argc, argv) (so --gtest_filter etc. work), registerTests for each plugin,
/// RUN_ALL_TESTS. Returns its exit code (0 = every test passed).
int run(const std::vector<std::shared_ptr<const framework::PluginInfo>>& plugins, int argc,
        char** argv, const IniConfig* config = nullptr);

}  // namespace asf::conformance
