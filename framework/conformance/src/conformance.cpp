/// \file conformance.cpp
/// The kit's entry points, the helpers shared by every kind, and the tests every plugin
/// gets whatever its kind: descriptor rules, configuration, kind, determinism, threads.
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/text.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "kit.h"

namespace asf::conformance {
namespace detail {

// ---- Trace ----------------------------------------------------------------------------

void Trace::num(const std::string& label, double v) { entries_.push_back({label, v, {}}); }

void Trace::pose(const std::string& label, const mrpt::poses::CPose2D& p) {
  num(label + ".x", p.x());
  num(label + ".y", p.y());
  num(label + ".phi", p.phi());
}

void Trace::mat(const std::string& label, const Eigen::Matrix3d& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      num(label + "(" + std::to_string(r) + "," + std::to_string(c) + ")", m(r, c));
}

void Trace::text(const std::string& label, const std::string& s) {
  entries_.push_back({label, 0, s});
}

namespace {
bool sameNumber(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return a == b;
}
}  // namespace

std::string firstDifference(const Trace& a, const Trace& b) {
  const std::size_t n = std::min(a.entries_.size(), b.entries_.size());
  for (std::size_t i = 0; i < n; ++i) {
    const auto& x = a.entries_[i];
    const auto& y = b.entries_[i];
    if (x.label != y.label)
      return "output #" + std::to_string(i) + " differs in kind: '" + x.label + "' vs '" + y.label +
             "'";
    if (!sameNumber(x.value, y.value) || x.text != y.text)
      return "output #" + std::to_string(i) + " '" + x.label + "' differs: " +
             (x.text.empty() && y.text.empty()
                  ? formatSignificant(x.value, 17) + " vs " + formatSignificant(y.value, 17)
                  : "'" + x.text + "' vs '" + y.text + "'");
  }
  if (a.entries_.size() != b.entries_.size())
    return "the runs produced " + std::to_string(a.entries_.size()) + " vs " +
           std::to_string(b.entries_.size()) + " outputs (first extra: '" +
           (a.entries_.size() > n ? a.entries_[n].label : b.entries_[n].label) + "')";
  return {};
}

std::string describeException(std::exception_ptr e) {
  try {
    std::rethrow_exception(e);
  } catch (const ConfigError& x) {
    return std::string("asf::ConfigError: ") + x.what();
  } catch (const InputError& x) {
    return std::string("asf::InputError: ") + x.what();
  } catch (const PluginError& x) {
    return std::string("asf::PluginError: ") + x.what();
  } catch (const Error& x) {
    return std::string("asf::Error: ") + x.what();
  } catch (const std::exception& x) {
    return std::string("std::exception: ") + x.what();
  } catch (...) {
    return "an exception not derived from std::exception";
  }
}

// ---- matrices -------------------------------------------------------------------------

bool allFinite(const Eigen::Matrix3d& m) { return m.allFinite(); }

namespace {
/// Symmetric, and its smallest eigenvalue above -tol * scale (PSD) or above 0 (PD).
testing::AssertionResult checkSymmetricDefinite(const Eigen::Matrix3d& m, bool strict, double tol) {
  if (!m.allFinite()) return testing::AssertionFailure() << "not finite:\n" << m;
  const double mag = m.cwiseAbs().maxCoeff();
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * mag + 1e-15)
    return testing::AssertionFailure() << "not symmetric:\n" << m;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (m + m.transpose()),
                                                    Eigen::EigenvaluesOnly);
  const double lo = es.eigenvalues().minCoeff();
  if (strict ? !(lo > 0) : lo < -tol * std::max(1.0, mag))
    return testing::AssertionFailure()
           << "not positive " << (strict ? "" : "semi-") << "definite (eigenvalue " << lo << "):\n"
           << m;
  return testing::AssertionSuccess();
}
}  // namespace

testing::AssertionResult isSymmetricPsd(const Eigen::Matrix3d& m, double tol) {
  return checkSymmetricDefinite(m, false, tol);
}

testing::AssertionResult isSymmetricPd(const Eigen::Matrix3d& m) {
  return checkSymmetricDefinite(m, true, 0);
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

bool samePose(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b, double tol) {
  return std::abs(a.x() - b.x()) <= tol && std::abs(a.y() - b.y()) <= tol &&
         std::abs(angleDiff(a.phi(), b.phi())) <= tol;
}

// ---- configuration --------------------------------------------------------------------

namespace {

std::vector<std::string> splitChoices(const char* choices) {
  std::vector<std::string> out;
  if (!choices) return out;
  std::string s = choices, c;
  std::istringstream is(s);
  while (std::getline(is, c, '|')) out.push_back(c);
  if (!s.empty() && s.back() == '|') out.push_back("");
  return out;
}

bool inRange(const KeySpec& k, double v) { return v >= k.min && v <= k.max; }

}  // namespace

bool synthesizeRequired(const PluginDescriptor& d, std::map<std::string, std::string>& out,
                        std::string& why, const std::set<std::string>& given) {
  out.clear();
  for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
    const KeySpec& k = d.keys[i];
    if (k.default_value) continue;
    const std::string name = k.name ? k.name : "";
    if (given.count(name)) continue;
    switch (k.type) {
      case KeyType::Bool:
        out[name] = "false";
        break;
      case KeyType::Int: {
        double v = 1;
        if (!inRange(k, v)) v = std::isfinite(k.min) ? std::ceil(k.min) : std::floor(k.max);
        if (!inRange(k, v) || std::abs(v) > 1e15) {
          why = "required key '" + name + "' has an empty integer range";
          return false;
        }
        out[name] = std::to_string(static_cast<long long>(v));
        break;
      }
      case KeyType::Double: {
        double v = 1;
        if (!inRange(k, v)) {
          if (std::isfinite(k.min) && std::isfinite(k.max))
            v = 0.5 * (k.min + k.max);
          else if (std::isfinite(k.min))
            v = k.min + 1;
          else
            v = k.max - 1;
        }
        if (!inRange(k, v)) {
          why = "required key '" + name + "' has an empty range";
          return false;
        }
        out[name] = formatSignificant(v, 17);
        break;
      }
      case KeyType::Enum: {
        auto c = splitChoices(k.choices);
        if (c.empty() || c.front().empty()) {
          why = "required enum key '" + name + "' has no choices";
          return false;
        }
        out[name] = c.front();
        break;
      }
      case KeyType::String:
      case KeyType::Path:
      case KeyType::DoubleList:
      default:
        why = "the plugin has a required key '" + name + "' (" + keyTypeName(k.type) +
              ", no default) for which the kit cannot make up a value; give it one with "
              "`asf conformance --config FILE.ini` (section [" +
              std::string(d.name ? d.name : "") + "])";
        return false;
    }
  }
  return true;
}

std::string outOfRangeValue(const KeySpec& k, bool below) {
  if (k.type != KeyType::Int && k.type != KeyType::Double && k.type != KeyType::DoubleList)
    return {};
  const double bound = below ? k.min : k.max;
  if (!std::isfinite(bound)) return {};
  if (k.type == KeyType::Int) {
    if (std::abs(bound) > 1e15) return {};
    const double v = below ? std::ceil(bound) - 1 : std::floor(bound) + 1;
    return std::to_string(static_cast<long long>(v));
  }
  const double step = std::max(1.0, std::abs(bound));
  const double v = below ? bound - step : bound + step;
  if (!std::isfinite(v)) return {};
  return formatSignificant(v, 17);
}

namespace {

/// The --config INIs of the plugins that have a section in one, by descriptor (filled by
/// registerTests before any test runs).
std::map<const PluginDescriptor*, std::shared_ptr<const IniConfig>>& givenConfigs() {
  static std::map<const PluginDescriptor*, std::shared_ptr<const IniConfig>> m;
  return m;
}

/// `ini`'s section for the plugin plus `values`, resolved like a pipeline section.
Params resolveWith(const IniConfig& ini, const PluginDescriptor& d,
                   const std::map<std::string, std::string>& values) {
  IniConfig merged = ini;
  for (const auto& [k, v] : values) merged.set(d.name, k, v, "conformance kit");
  return merged.resolve(d.name, d.keys, d.num_keys);
}

}  // namespace

const IniConfig* PluginTest::config() const {
  auto it = givenConfigs().find(info_->descriptor);
  return it == givenConfigs().end() ? nullptr : it->second.get();
}

std::set<std::string> PluginTest::givenKeys() const {
  const IniConfig* c = config();
  if (!c) return {};
  const auto keys = c->keys(descriptor().name);
  return {keys.begin(), keys.end()};
}

Params PluginTest::defaultParams(const std::map<std::string, std::string>& extra) const {
  std::map<std::string, std::string> ov;
  std::string why;
  synthesizeRequired(descriptor(), ov, why, givenKeys());
  for (const auto& [k, v] : extra) ov[k] = v;
  if (const IniConfig* c = config()) return resolveWith(*c, descriptor(), ov);
  return Params::fromSpecs(section(), descriptor().keys, descriptor().num_keys, ov);
}

bool skipUnconfigurable(const PluginTest& t, std::string& why) {
  std::map<std::string, std::string> ov;
  if (!synthesizeRequired(t.descriptor(), ov, why, t.givenKeys())) return true;
  if (ov.empty() && !t.config()) return false;
  // Values were made up for required keys (or given in --config): a plugin may reject them
  // for reasons of its own (cross-key checks, a data file missing here), which is not a
  // conformance failure.
  std::string list;
  for (const auto& [k, v] : ov) list += (list.empty() ? "" : ", ") + k + " = " + v;
  if (t.config())
    list = "[" + std::string(t.descriptor().name) + "] of " + t.config()->fileName() +
           (list.empty() ? "" : ", and made up: " + list);
  try {
    auto p = framework::Registry::instantiate(t.info());
    p->setMinLoggingLevel(mrpt::system::LVL_ERROR);
    PluginContext ctx;
    ctx.seed = kSeed;
    p->configure(t.defaultParams(), ctx);
  } catch (const ConfigError& e) {
    why = "the plugin rejected the values the kit configured it with (" + list + "): " + e.what();
    return true;
  } catch (...) {
    // Reported by the test itself.
  }
  return false;
}

// ---- tests common to every kind -------------------------------------------------------

namespace {

const std::regex kSnake("^[a-z][a-z0-9]*(_[a-z0-9]+)*$");
const std::regex kSemver("^(0|[1-9][0-9]*)\\.(0|[1-9][0-9]*)\\.(0|[1-9][0-9]*)$");

bool isSnake(const char* s) { return s && std::regex_match(s, kSnake); }
std::string show(const char* s) { return s ? "'" + std::string(s) + "'" : "(null)"; }

/// Descriptor tests: they read the descriptor only, so they run for every plugin (as do the
/// key table tests).
void registerDescriptorTests(const InfoPtr& info) {
  // The kind does not matter for these; use the Source fixture for all of them (the suite's
  // fixture type is PluginTest whatever the template argument).
  using K = Source;
  addTest<K>(info, "descriptor_abi_version_and_size", Needs::Nothing, [](PluginTest& t) {
    const auto& d = t.descriptor();
    EXPECT_EQ(d.abi_version, ASF_ABI_VERSION)
        << "the plugin was built against another asf ABI: rebuild it";
    EXPECT_EQ(d.descriptor_size, sizeof(PluginDescriptor))
        << "descriptor_size must be sizeof(asf::PluginDescriptor) (use ASF_PLUGIN)";
  });
  addTest<K>(info, "descriptor_name_is_lower_snake_case", Needs::Nothing, [](PluginTest& t) {
    EXPECT_TRUE(isSnake(t.descriptor().name))
        << "name " << show(t.descriptor().name) << " must match [a-z][a-z0-9]*(_[a-z0-9]+)*";
  });
  addTest<K>(info, "descriptor_version_is_major_minor_patch", Needs::Nothing, [](PluginTest& t) {
    const char* v = t.descriptor().version;
    EXPECT_TRUE(v && std::regex_match(v, kSemver))
        << "version " << show(v) << " must be MAJOR.MINOR.PATCH, e.g. \"1.0.0\"";
  });
  addTest<K>(info, "descriptor_description_is_one_nonempty_line", Needs::Nothing,
             [](PluginTest& t) {
               const char* s = t.descriptor().description;
               ASSERT_NE(s, nullptr) << "description is null";
               const std::string d = s;
               EXPECT_NE(d.find_first_not_of(" \t"), std::string::npos) << "description is empty";
               EXPECT_EQ(d.find_first_of("\r\n"), std::string::npos)
                   << "description must be one line: " << show(s);
             });
  addTest<K>(
      info, "descriptor_kind_thread_safety_and_factory_are_set", Needs::Nothing, [](PluginTest& t) {
        const auto& d = t.descriptor();
        EXPECT_LT(static_cast<std::uint32_t>(d.kind), static_cast<std::uint32_t>(kNumPluginKinds))
            << "unknown kind";
        EXPECT_TRUE(d.thread_safety == ThreadSafety::ThreadCompatible ||
                    d.thread_safety == ThreadSafety::SingleThreaded)
            << "unknown thread_safety value " << static_cast<int>(d.thread_safety);
        EXPECT_NE(d.create, nullptr) << "create (the factory) is null";
        if (d.num_keys > 0) {
          EXPECT_NE(d.keys, nullptr) << "num_keys > 0 but keys is null";
        }
      });
}

/// Key table tests: names, docs, enum choices and defaults of the ASF_PLUGIN key table.
void registerKeyTableTests(const InfoPtr& info) {
  using K = Source;  // as in registerDescriptorTests: the fixture type does not matter
  addTest<K>(info, "descriptor_key_names_are_unique_lower_snake_case", Needs::Nothing,
             [](PluginTest& t) {
               const auto& d = t.descriptor();
               std::set<std::string> seen;
               for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
                 const char* n = d.keys[i].name;
                 EXPECT_TRUE(isSnake(n))
                     << "key #" << i << " name " << show(n) << " must be lower_snake_case";
                 if (n) {
                   EXPECT_TRUE(seen.insert(n).second) << "key '" << n << "' is declared twice";
                 }
               }
             });
  addTest<K>(info, "descriptor_key_docs_are_nonempty_lines", Needs::Nothing, [](PluginTest& t) {
    const auto& d = t.descriptor();
    for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
      const KeySpec& k = d.keys[i];
      const std::string doc = k.doc ? k.doc : "";
      EXPECT_NE(doc.find_first_not_of(" \t"), std::string::npos)
          << "key " << show(k.name) << " has no doc";
      EXPECT_EQ(doc.find_first_of("\r\n"), std::string::npos)
          << "key " << show(k.name) << ": doc must be one line";
    }
  });
  addTest<K>(info, "descriptor_enum_keys_have_choices", Needs::Nothing, [](PluginTest& t) {
    const auto& d = t.descriptor();
    for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
      const KeySpec& k = d.keys[i];
      if (k.type != KeyType::Enum) {
        EXPECT_EQ(k.choices, nullptr)
            << "key " << show(k.name) << " is a " << keyTypeName(k.type) << " but has choices";
        continue;
      }
      const auto c = splitChoices(k.choices);
      ASSERT_FALSE(c.empty()) << "enum key " << show(k.name) << " has no choices";
      std::set<std::string> seen;
      for (const auto& s : c) {
        EXPECT_FALSE(s.empty()) << "enum key " << show(k.name) << " has an empty choice in "
                                << show(k.choices);
        EXPECT_TRUE(seen.insert(s).second)
            << "enum key " << show(k.name) << " lists '" << s << "' twice";
      }
    }
  });
  addTest<K>(info, "descriptor_defaults_are_valid", Needs::Nothing, [](PluginTest& t) {
    const auto& d = t.descriptor();
    for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
      const KeySpec& k = d.keys[i];
      EXPECT_FALSE(std::isnan(k.min) || std::isnan(k.max))
          << "key " << show(k.name) << ": NaN bound";
      EXPECT_LE(k.min, k.max) << "key " << show(k.name) << ": min > max";
      if (!k.default_value) continue;  // required key
      const std::string why = validateValue(k, k.default_value);
      EXPECT_EQ(why, "") << "key " << show(k.name) << ": default " << show(k.default_value)
                         << " is not a valid " << keyTypeName(k.type);
    }
  });
}

/// The descriptor and configure(): kind, defaults, out-of-range values.
template <class T>
void registerDescriptorTests(const InfoPtr& info) {
  addTest<T>(info, "kind_matches_descriptor", Needs::Nothing, [](KindTest<T>& t) {
    auto p = framework::Registry::instantiate(t.info());
    ASSERT_NE(p, nullptr) << "the factory returned null";
    EXPECT_EQ(p->kind(), t.descriptor().kind)
        << "the object is a " << kindName(p->kind()) << ", the descriptor says "
        << kindName(t.descriptor().kind);
    EXPECT_NE(dynamic_cast<T*>(p.get()), nullptr)
        << "the object does not derive from asf::" << kindName(T::kStaticKind);
  });

  addTest<T>(info, "configure_with_defaults_succeeds", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.create();
    PluginContext ctx;
    ctx.seed = kSeed;
    try {
      h->configure(t.defaultParams(), ctx);
    } catch (...) {
      FAIL() << "configure() with the default values failed: "
             << describeException(std::current_exception());
    }
  });

  addTest<T>(info, "configure_rejects_out_of_range_values", Needs::Nothing, [](KindTest<T>& t) {
    const auto& d = t.descriptor();
    std::map<std::string, std::string> made_up;  // made up again by defaultParams() below
    std::string why;
    const bool configurable = synthesizeRequired(d, made_up, why, t.givenKeys());
    for (std::size_t i = 0; i < d.num_keys && d.keys; ++i) {
      const KeySpec& k = d.keys[i];
      for (bool below : {true, false}) {
        const std::string bad = outOfRangeValue(k, below);
        if (bad.empty()) continue;
        const std::string name = k.name ? k.name : "";
        SCOPED_TRACE("key '" + name + "' = " + bad);
        EXPECT_NE(validateValue(k, bad), "") << "asf::validateValue accepted an out-of-range value";
        if (!configurable) continue;
        try {
          const Params p = t.defaultParams({{name, bad}});
          auto h = t.create();
          PluginContext ctx;
          ctx.seed = kSeed;
          h->configure(p, ctx);
          ADD_FAILURE() << "an out-of-range value was accepted";
        } catch (const ConfigError& e) {
          const std::regex word("(^|[^A-Za-z0-9_])" + name + "([^A-Za-z0-9_]|$)");
          EXPECT_TRUE(std::regex_search(std::string(e.what()), word))
              << "the ConfigError does not name the key: " << e.what();
        } catch (...) {
          ADD_FAILURE() << "expected asf::ConfigError, got "
                        << describeException(std::current_exception());
        }
      }
    }
  });
}

/// The standard input: no exception, determinism, thread-compatibility.
template <class T>
void registerBehaviourTests(const InfoPtr& info) {
  addTest<T>(info, "standard_input_raises_no_exception", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    try {
      standardRun(*h);
    } catch (...) {
      FAIL() << "exception on the kit's standard " << kindName(T::kStaticKind)
             << " input: " << describeException(std::current_exception());
    }
  });

  addTest<T>(info, "same_seed_gives_identical_output", Needs::Instance, [](KindTest<T>& t) {
    auto a = t.make(kSeed);
    const Trace ta = standardRun(*a);
    auto b = t.make(kSeed);
    const Trace tb = standardRun(*b);
    EXPECT_GT(ta.size(), 0u);
    EXPECT_EQ(firstDifference(ta, tb), "")
        << "two instances configured with the same seed gave different outputs";
  });

  addTest<T>(info, "concurrent_instances_match_sequential_runs", Needs::Instance,
             [](KindTest<T>& t) {
               if (t.descriptor().thread_safety != ThreadSafety::ThreadCompatible)
                 GTEST_SKIP() << "the plugin declares itself SingleThreaded";
               Trace sequential;
               {
                 auto a = t.make();
                 sequential = standardRun(*a);
               }
               auto b = t.make();
               auto c = t.make();
               Trace tb, tc;
               std::string eb, ec;
               const auto runIn = [](T& p, Trace& out, std::string& err) {
                 try {
                   out = standardRun(p);
                 } catch (...) {
                   err = describeException(std::current_exception());
                 }
               };
               std::thread th1(runIn, std::ref(*b), std::ref(tb), std::ref(eb));
               std::thread th2(runIn, std::ref(*c), std::ref(tc), std::ref(ec));
               th1.join();
               th2.join();
               ASSERT_EQ(eb, "") << "exception in thread 1";
               ASSERT_EQ(ec, "") << "exception in thread 2";
               EXPECT_EQ(firstDifference(sequential, tb), "")
                   << "thread 1 differs from a sequential run (hidden shared state?)";
               EXPECT_EQ(firstDifference(sequential, tc), "")
                   << "thread 2 differs from a sequential run (hidden shared state?)";
             });
}

template <class T>
void registerCommonTests(const InfoPtr& info) {
  registerDescriptorTests<T>(info);
  registerBehaviourTests<T>(info);
}

template <class T>
void registerKind(const InfoPtr& info, void (*kindTests)(const InfoPtr&)) {
  registerCommonTests<T>(info);
  kindTests(info);
}

}  // namespace
}  // namespace detail

void registerTests(const std::shared_ptr<const framework::PluginInfo>& plugin,
                   const IniConfig* config) {
  using namespace detail;
  if (!plugin || !plugin->descriptor)
    throw PluginError("asf::conformance::registerTests: no plugin (null descriptor)");
  const PluginDescriptor& d = *plugin->descriptor;
  if (config && d.name && config->hasSection(d.name)) {
    // Checked now, so a typo in the INI is one clear error rather than failing tests.
    std::map<std::string, std::string> made_up;
    std::string why;
    synthesizeRequired(d, made_up, why, [&] {
      const auto k = config->keys(d.name);
      return std::set<std::string>(k.begin(), k.end());
    }());
    resolveWith(*config, d, made_up);
    givenConfigs()[plugin->descriptor] = std::make_shared<IniConfig>(*config);
  }
  registerDescriptorTests(plugin);
  registerKeyTableTests(plugin);
  switch (plugin->kind()) {
    case PluginKind::Source:
      registerKind<Source>(plugin, registerSourceTests);
      break;
    case PluginKind::Frontend:
      registerKind<Frontend>(plugin, registerFrontendTests);
      break;
    case PluginKind::Backend:
      registerKind<Backend>(plugin, registerBackendTests);
      break;
    case PluginKind::Segmenter:
      registerKind<Segmenter>(plugin, registerSegmenterTests);
      break;
    case PluginKind::Planner:
      registerKind<Planner>(plugin, registerPlannerTests);
      break;
    case PluginKind::Policy:
      registerKind<Policy>(plugin, registerPolicyTests);
      break;
    default:
      break;  // descriptor_kind_thread_safety_and_factory_are_set fails
  }
}

int run(const std::vector<std::shared_ptr<const framework::PluginInfo>>& plugins, int argc,
        char** argv, const IniConfig* config) {
  testing::InitGoogleTest(&argc, argv);
  std::set<const PluginDescriptor*> done;
  for (const auto& p : plugins)
    if (p && done.insert(p->descriptor).second) registerTests(p, config);
  return RUN_ALL_TESTS();
}

}  // namespace asf::conformance
