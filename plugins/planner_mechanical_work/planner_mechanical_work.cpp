// planner_mechanical_work: the path with the least mechanical work (Valencia et al.): sum of
// the positive increments of U = det((O^-1 + Sigma^-1)^-1) along the path. A baseline of
// thesis chapter 3, searched over the same candidate paths as expected_uncertainty.
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class MechanicalWorkPlanner final : public asf::planning::CriterionPlanner {
 public:
  MechanicalWorkPlanner() : CriterionPlanner(asf::planning::Criterion::MechanicalWork) {}
};

const asf::KeySpec kKeys[] = {
    ASF_EU_PATH_SEARCH_KEYS,
    ASF_EU_VORONOI_KEYS,
};

}  // namespace

ASF_PLUGIN(MechanicalWorkPlanner, asf::PluginKind::Planner, "mechanical_work", "1.0.0",
           "Path with the least mechanical work in uncertainty (Valencia et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
