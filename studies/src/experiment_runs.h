#pragma once
// What the experiment's scheduler (experiment.cpp) and its summary (experiment_summary.cpp)
// both read of a run folder. Private to the framework.
#include <asf/studies/experiment.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace asf::studies::detail {

std::string runDir(const ExperimentConfig& cfg, const std::string& policy, int seed);
/// Every (policy, seed) of cfg, seeds outer and policies inner (an interrupted experiment
/// has comparable runs per policy), with their folders; none marked skipped.
std::vector<ExperimentRun> plannedRuns(const ExperimentConfig& cfg);
/// summary.json of a run, or null with `why` set.
nlohmann::json readSummary(const std::string& dir, std::string& why);
/// "finished", or why the run does not count (missing/invalid file, interrupted, error).
std::string runStatus(const nlohmann::json& s, const std::string& why);
/// A number of summary.json; NaN when absent.
double number(const nlohmann::json& s, const char* key);

}  // namespace asf::studies::detail
