// planner_mechanical_work: the path with the least mechanical work (Valencia et al.): sum of
// the positive increments of U = det((O^-1 + Sigma^-1)^-1) along the path. A baseline of
// thesis chapter 3, searched over the same candidate paths as expected_uncertainty.
#include <asf/errors.h>
#include <asf/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class MechanicalWorkPlanner final : public asf::Planner {
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
      r = asf::eu::planBest(req, asf::eu::Criterion::MechanicalWork, options_, search_, &note);
    } catch (const asf::Error& e) {
      r = asf::PlanResult{};
      r.criterion = "work";
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
    asf::keyInt("max_paths", "10000", "Candidate simple paths evaluated at most", 1, 1e9),
    asf::keyBool("reduce", "true", "Search the reduced graph (degree-2 chains collapsed)"),
};

}  // namespace

ASF_PLUGIN(MechanicalWorkPlanner, asf::PluginKind::Planner, "mechanical_work", "1.0.0",
           "Path with the least mechanical work in uncertainty (Valencia et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
