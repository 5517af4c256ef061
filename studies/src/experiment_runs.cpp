#include "experiment_runs.h"

#include <asf/studies/experiment.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace asf::studies::detail {

namespace fs = std::filesystem;
using nlohmann::json;

std::string runDir(const ExperimentConfig& cfg, const std::string& policy, int seed) {
  return (fs::path(cfg.out_dir) / policy / ("seed_" + std::to_string(seed))).string();
}

std::vector<ExperimentRun> plannedRuns(const ExperimentConfig& cfg) {
  std::vector<ExperimentRun> runs;
  for (int r = 0; r < cfg.replications; ++r)
    for (const auto& p : cfg.policies) {
      ExperimentRun run;
      run.policy = p;
      run.seed = cfg.first_seed + r;
      run.dir = runDir(cfg, p, run.seed);
      runs.push_back(run);
    }
  return runs;
}

json readSummary(const std::string& dir, std::string& why) {
  const fs::path p = fs::path(dir) / "summary.json";
  std::ifstream in(p);
  if (!in) {
    why = "missing summary.json";
    return nullptr;
  }
  try {
    json j;
    in >> j;
    if (!j.is_object()) {
      why = "invalid summary.json (not an object)";
      return nullptr;
    }
    return j;
  } catch (const std::exception& e) {
    why = std::string("invalid summary.json (") + e.what() + ")";
    return nullptr;
  }
}

std::string runStatus(const json& s, const std::string& why) {
  if (s.is_null()) return why;
  if (!s.contains("stop_reason") || !s["stop_reason"].is_string())
    return "invalid summary.json (no stop_reason)";
  const std::string r = s["stop_reason"].get<std::string>();
  if (r == "interrupted" || r.rfind("error", 0) == 0) return r;
  return "finished";
}

double number(const json& s, const char* key) {
  if (!s.is_object() || !s.contains(key) || !s[key].is_number()) return NAN;
  return s[key].get<double>();
}

}  // namespace asf::studies::detail
