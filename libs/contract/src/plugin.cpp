// Plugin kinds, names, and the interfaces' out-of-line destructors: defining them here
// anchors each interface's vtable and typeinfo in libasf_framework.so, shared by all plugins.
#include <asf/backend.h>
#include <asf/frontend.h>
#include <asf/goal.h>
#include <asf/planner.h>
#include <asf/plugin.h>
#include <asf/policy.h>
#include <asf/segmenter.h>
#include <asf/source.h>

namespace asf {

namespace {
const char* const kKindNames[kNumPluginKinds] = {"source", "frontend", "backend",
                                                 "segmenter", "planner", "policy"};
}

const char* kindName(PluginKind k) {
  auto i = static_cast<std::uint32_t>(k);
  return i < kNumPluginKinds ? kKindNames[i] : "unknown-kind";
}

bool parseKind(const std::string& s, PluginKind& out) {
  for (int i = 0; i < kNumPluginKinds; ++i)
    if (s == kKindNames[i]) {
      out = static_cast<PluginKind>(i);
      return true;
    }
  return false;
}

const char* threadSafetyName(ThreadSafety t) {
  switch (t) {
    case ThreadSafety::ThreadCompatible: return "thread-compatible";
    case ThreadSafety::SingleThreaded: return "single-threaded";
  }
  return "unknown";
}

const char* navStatusName(NavStatus s) {
  switch (s) {
    case NavStatus::Idle: return "idle";
    case NavStatus::Moving: return "moving";
    case NavStatus::Reached: return "reached";
    case NavStatus::Unreachable: return "unreachable";
    case NavStatus::Blocked: return "blocked";
  }
  return "unknown";
}

Plugin::Plugin() : mrpt::system::COutputLogger("asf-plugin") {}
Plugin::~Plugin() = default;
Source::~Source() = default;
Frontend::~Frontend() = default;
Backend::~Backend() = default;
Segmenter::~Segmenter() = default;
Planner::~Planner() = default;
Policy::~Policy() = default;

}  // namespace asf
