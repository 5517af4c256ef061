#pragma once
/// \file plan_eval.h
/// The unreliable-path-avoidance protocol of thesis Table 3.1 (ch. 3.5.1) on a SLAM run, as
/// `asf plan-eval` runs it: for each feature-void zone and covariance factor of the
/// [plan_eval] section, the zone's scans are ignored (its links become wheel odometry with
/// the covariance times the factor, its loop closures go, nobody recognizes it), the graph
/// is re-optimized, its marginals and cross-covariances recovered, place recognition
/// estimated by Monte Carlo ICP on each node's scan, and every planner plans every
/// start/goal pair of a node subset outside the zone. Error rate: share of the pairs whose
/// path crosses the zone.
#include <asf/config.h>
#include <asf/key_spec.h>
#include <asf/framework/registry.h>

#include <cstddef>
#include <string>

namespace asf::studies {

/// Keys of the [plan_eval] section.
const KeySpec* planEvalKeys(std::size_t& n);

struct PlanEvalOutput {
  std::string markdown;            ///< plan_eval.md's text
  std::string md_file, json_file;  ///< written
};

/// Runs the protocol of `ini` ([plan_eval], the back-end's and each planner's sections) with
/// the plugins `reg` holds; writes plan_eval.md, plan_eval.json (every chosen path),
/// scenario_<X>.svg (thesis Fig. 3.4) and error_example_<X>.svg (Fig. 3.5) into
/// `out_override` or [plan_eval] out; progress on stderr. `config_name` is recorded in the
/// JSON. Throws ConfigError naming the key for an inconsistent configuration.
PlanEvalOutput runPlanEval(const IniConfig& ini, framework::Registry& reg,
                           const std::string& out_override, const std::string& config_name);

}  // namespace asf::studies
