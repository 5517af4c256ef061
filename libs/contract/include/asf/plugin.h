#pragma once
/// \file plugin.h
/// What every plugin is: a class derived from one kind's interface (source.h, frontend.h,
/// backend.h, segmenter.h, planner.h, policy.h) plus one exported descriptor.
///
/// A plugin library (.so) exports exactly one C symbol, `asf_plugin_descriptor`, returning a
/// PluginDescriptor. Write it with the ASF_PLUGIN macro at the end of the plugin's .cpp:
/// \code
///   static const asf::KeySpec kKeys[] = {
///       asf::keyDouble("step", "0.5", "Step length [m]", 0.01, 10.0),
///   };
///   ASF_PLUGIN(MyPolicy, asf::PluginKind::Policy, "my_policy", "1.0.0",
///              "One line saying what it does", asf::ThreadSafety::ThreadCompatible, kKeys)
/// \endcode
#include <asf/abi.h>
#include <asf/key_spec.h>
#include <asf/params.h>
#include <mrpt/system/COutputLogger.h>

#include <cstdint>
#include <iterator>
#include <memory>
#include <string>

namespace asf {

enum class PluginKind : std::uint32_t {
  Source = 0,
  Frontend = 1,
  Backend = 2,
  Segmenter = 3,
  Planner = 4,
  Policy = 5,
};
constexpr int kNumPluginKinds = 6;
const char* kindName(PluginKind k);
/// Parses "source", "frontend", ...; returns false if unknown.
bool parseKind(const std::string& s, PluginKind& out);

/// What callers may assume about concurrent use (checked by the conformance kit).
enum class ThreadSafety : std::uint32_t {
  /// Distinct instances may be used from distinct threads at once; one instance from one
  /// thread at a time (the usual C++ guarantee, like std::vector).
  ThreadCompatible = 0,
  /// Instances share hidden state: use from one thread only.
  SingleThreaded = 1,
};
const char* threadSafetyName(ThreadSafety t);

/// What the host hands a plugin when configuring it.
struct PluginContext {
  /// Every random draw of the plugin derives from this (the run's seed mixed with the
  /// plugin's slot), so runs are reproducible.
  std::uint64_t seed = 0;
  /// Folder for files the plugin writes itself (may be empty: write nothing).
  std::string output_dir;
};

/// Base of every plugin. Log with MRPT's macros (MRPT_LOG_INFO_STREAM(...)); the host sets
/// the logger name and verbosity.
class Plugin : public mrpt::system::COutputLogger {
 public:
  Plugin();
  ~Plugin() override;
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  /// Called once, before any other call, with the section's values already validated
  /// against the descriptor (types, ranges, choices). Throws asf::ConfigError (use
  /// params.fail(key, why)) for invalid combinations.
  virtual void configure(const Params& params, const PluginContext& ctx) = 0;

  virtual PluginKind kind() const = 0;
};

/// The exported description of a plugin. Layout rule: `abi_version` and `descriptor_size`
/// stay the first two fields forever, so any host can read them from any plugin.
struct PluginDescriptor {
  std::uint32_t abi_version;
  std::uint32_t descriptor_size;
  const char* name;         ///< unique among plugins, lower_snake_case
  PluginKind kind;
  const char* version;      ///< the plugin's own version, "MAJOR.MINOR.PATCH"
  const char* description;  ///< one line
  ThreadSafety thread_safety;
  const KeySpec* keys;
  std::size_t num_keys;
  /// Creates an unconfigured instance; may throw.
  std::unique_ptr<Plugin> (*create)();
};

}  // namespace asf

#define ASF_PLUGIN_IMPL_(CLASS, KIND, NAME, VERSION, DESC, TS, KEYS, NKEYS)              \
  extern "C" ASF_EXPORT const ::asf::PluginDescriptor* asf_plugin_descriptor() {         \
    static const ::asf::PluginDescriptor d{                                              \
        ASF_ABI_VERSION, sizeof(::asf::PluginDescriptor), NAME, KIND, VERSION, DESC, TS, \
        KEYS, NKEYS, []() -> std::unique_ptr<::asf::Plugin> {                           \
          return std::make_unique<CLASS>();                                              \
        }};                                                                              \
    return &d;                                                                           \
  }

/// Defines the plugin's entry point. KEYS: a static array of asf::KeySpec.
#define ASF_PLUGIN(CLASS, KIND, NAME, VERSION, DESC, TS, KEYS) \
  ASF_PLUGIN_IMPL_(CLASS, KIND, NAME, VERSION, DESC, TS, KEYS, std::size(KEYS))

/// Same, for a plugin without INI keys.
#define ASF_PLUGIN_NO_KEYS(CLASS, KIND, NAME, VERSION, DESC, TS) \
  ASF_PLUGIN_IMPL_(CLASS, KIND, NAME, VERSION, DESC, TS, nullptr, 0)
