// planner_sum_dopt: the path minimizing the sum over its nodes of the D-optimality of their
// marginal covariance (Carrillo et al.; thesis eq. 3.24). A baseline of thesis chapter 3,
// searched over the same candidate paths as expected_uncertainty.
#include <asf/errors.h>
#include <asf/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class SumDoptPlanner final : public asf::Planner {
 public:
  void configure(const asf::Params& params, const asf::PluginContext& ctx) override {
    options_ = asf::eu::criterionOptionsFrom(params, ctx.seed);
    search_.max_paths = static_cast<std::size_t>(params.getInt("max_paths"));
    search_.reduce = params.getBool("reduce");
  }

  asf::PlanResult plan(const asf::PlanRequest& req) override {
    std::string note;
    asf::PlanResult r;
    try {
      r = asf::eu::planBest(req, asf::eu::Criterion::SumDopt, options_, search_, &note);
    } catch (const asf::Error& e) {
      r = asf::PlanResult{};
      r.criterion = "sum_dopt";
      r.reason = e.what();
    }
    if (!note.empty()) MRPT_LOG_WARN_STREAM(note);
    return r;
  }

 private:
  asf::eu::CriterionOptions options_;
  asf::eu::PathSearchOptions search_;
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("scalar", "det", "det|trace|det_cbrt",
                 "D-optimality of a node covariance: det (thesis), det^(1/3), or trace (A-opt)"),
    asf::keyInt("max_paths", "10000", "Candidate simple paths evaluated at most", 1, 1e9),
    asf::keyBool("reduce", "true", "Search the reduced graph (degree-2 chains collapsed)"),
};

}  // namespace

ASF_PLUGIN(SumDoptPlanner, asf::PluginKind::Planner, "sum_dopt", "1.0.0",
           "Path minimizing the sum of the nodes' D-optimality (Carrillo et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
