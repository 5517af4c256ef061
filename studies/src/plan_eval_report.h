#pragma once
// The report of `asf plan-eval`.
#include <nlohmann/json.hpp>
#include <string>

namespace asf::studies {

/// plan_eval.md from plan_eval.json's content: the error-rate table (scenario x planner),
/// the zones and recognition probabilities, planning times, planner warnings.
std::string planEvalMarkdown(const nlohmann::json& j);

}  // namespace asf::studies
