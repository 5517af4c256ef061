#pragma once
/// \file kit.h
/// Internals of the conformance kit: the test fixtures (one per plugin kind), the traces
/// used to compare runs, and the synthetic inputs every kind is tested on.
#include <asf/backend.h>
#include <asf/conformance.h>
#include <asf/frontend.h>
#include <asf/planner.h>
#include <asf/policy.h>
#include <asf/framework/registry.h>
#include <asf/segmenter.h>
#include <asf/source.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace asf::conformance::detail {

using InfoPtr = std::shared_ptr<const framework::PluginInfo>;

/// The seed every instance is configured with (the kit checks determinism under it).
constexpr std::uint64_t kSeed = 20240917;

// ---------------------------------------------------------------------------------------
// Traces: a flat, labelled record of what a plugin produced on its kind's standard input.
// Two runs are "identical" when their traces are equal number for number (bitwise).

class Trace {
 public:
  void num(const std::string& label, double v);
  void pose(const std::string& label, const mrpt::poses::CPose2D& p);
  void mat(const std::string& label, const Eigen::Matrix3d& m);
  void text(const std::string& label, const std::string& s);
  std::size_t size() const { return entries_.size(); }

  /// "" when identical, else a description of the first difference.
  friend std::string firstDifference(const Trace& a, const Trace& b);

 private:
  struct Entry {
    std::string label;
    double value = 0;
    std::string text;
  };
  std::vector<Entry> entries_;
};
std::string firstDifference(const Trace& a, const Trace& b);

/// what() of an exception_ptr (with its type when it is an asf error).
std::string describeException(std::exception_ptr e);

// ---------------------------------------------------------------------------------------
// Matrix checks.

bool allFinite(const Eigen::Matrix3d& m);
/// Symmetric within a relative tolerance and with eigenvalues >= -tol * max(1, |m|).
testing::AssertionResult isSymmetricPsd(const Eigen::Matrix3d& m, double tol = 1e-9);
/// Symmetric and positive definite (smallest eigenvalue > 0).
testing::AssertionResult isSymmetricPd(const Eigen::Matrix3d& m);
bool samePose(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b, double tol);
double angleDiff(double a, double b);  ///< wrapped to [-pi, pi]

// ---------------------------------------------------------------------------------------
// Configuration with defaults.

/// Values for the plugin's required keys (default_value == nullptr) except those in `given`
/// (set by the --config INI): numbers get a value within range, enums their first choice,
/// bools false. Returns false (and why) when a required key cannot be synthesized (strings,
/// paths, lists).
bool synthesizeRequired(const PluginDescriptor& d, std::map<std::string, std::string>& out,
                        std::string& why, const std::set<std::string>& given = {});

/// An out-of-range value for a numeric key with a finite bound, or "" if none can be made.
std::string outOfRangeValue(const KeySpec& k, bool below);

// ---------------------------------------------------------------------------------------
// Fixtures. Every test of a suite "<kind>/<name>" is created through the fixture type
// PluginTest (GoogleTest requires one fixture class per suite); kind-specific behaviour
// lives in KindTest<T>, the analogue of a typed test suite per kind.

class PluginTest : public testing::Test {
 public:
  explicit PluginTest(InfoPtr info) : info_(std::move(info)) {}
  const framework::PluginInfo& info() const { return *info_; }
  const PluginDescriptor& descriptor() const { return *info_->descriptor; }
  const InfoPtr& infoPtr() const { return info_; }
  /// INI section name used in the kit's Params (the kind, as in a pipeline INI).
  std::string section() const { return kindName(info_->kind()); }
  /// The INI given with --config when it has a section for this plugin, else nullptr.
  const IniConfig* config() const;
  /// Keys set in that section (lowercase).
  std::set<std::string> givenKeys() const;
  /// Every default, the --config values, synthesized values for the required keys left,
  /// then `extra` (throws ConfigError).
  Params defaultParams(const std::map<std::string, std::string>& extra = {}) const;

 protected:
  InfoPtr info_;
};

template <class T>
class KindTest : public PluginTest {
 public:
  using PluginTest::PluginTest;

  /// A new instance of the plugin, not configured, logging warnings and errors only.
  framework::PluginHandle<T> create() const {
    framework::PluginHandle<T> h = framework::Registry::create<T>(info_);
    h->setLoggerName(std::string("conformance/") + info_->name());
    h->setMinLoggingLevel(mrpt::system::LVL_WARN);
    return h;
  }
  /// A new instance configured with defaults (see defaultParams) and `seed`.
  framework::PluginHandle<T> make(std::uint64_t seed = kSeed) const {
    framework::PluginHandle<T> h = create();
    PluginContext ctx;
    ctx.seed = seed;
    h->configure(defaultParams(), ctx);
    return h;
  }
};

/// What a test needs before its body runs.
enum class Needs {
  Nothing,   ///< descriptor checks: run for every plugin
  Instance,  ///< a configured instance: skipped when required keys cannot be synthesized
};

/// Skips the current test (returns true) when the plugin cannot be configured by the kit.
bool skipUnconfigurable(const PluginTest& t, std::string& why);

template <class T>
class FunctionTest final : public KindTest<T> {
 public:
  using Body = std::function<void(KindTest<T>&)>;
  FunctionTest(InfoPtr info, Needs needs, Body body)
      : KindTest<T>(std::move(info)), needs_(needs), body_(std::move(body)) {}

  void TestBody() override {
    if (needs_ == Needs::Instance) {
      std::string why;
      if (skipUnconfigurable(*this, why)) GTEST_SKIP() << why;
    }
    try {
      body_(*this);
    } catch (...) {
      ADD_FAILURE() << "exception escaped from plugin '" << this->info().name()
                    << "': " << describeException(std::current_exception());
    }
  }

 private:
  Needs needs_;
  Body body_;
};

/// Registers test `name` in suite "<kind>/<plugin name>".
template <class T>
void addTest(const InfoPtr& info, const std::string& name, Needs needs,
             typename FunctionTest<T>::Body body, const char* file = __builtin_FILE(),
             int line = __builtin_LINE()) {
  const std::string suite = std::string(kindName(info->kind())) + "/" + info->name();
  testing::RegisterTest(suite.c_str(), name.c_str(), nullptr, nullptr, file, line,
                        [info, needs, body]() -> PluginTest* {
                          return new FunctionTest<T>(info, needs, body);
                        });
}

// ---------------------------------------------------------------------------------------
// Standard input of each kind: the run whose output must be deterministic and the same
// when instances run concurrently. May throw (reported by the caller).

Trace standardRun(Source& p);
Trace standardRun(Frontend& p);
Trace standardRun(Backend& p);
Trace standardRun(Segmenter& p);
Trace standardRun(Planner& p);
Trace standardRun(Policy& p);

/// Kind-specific tests, one function per kind (in <kind>_tests.cpp).
void registerSourceTests(const InfoPtr& info);
void registerFrontendTests(const InfoPtr& info);
void registerBackendTests(const InfoPtr& info);
void registerSegmenterTests(const InfoPtr& info);
void registerPlannerTests(const InfoPtr& info);
void registerPolicyTests(const InfoPtr& info);

}  // namespace asf::conformance::detail
