// planner_mechanical_work: the path with the least mechanical work (Valencia et al.): sum of
// the positive increments of U = det((O^-1 + Sigma^-1)^-1) along the path. A baseline of
// thesis chapter 3, searched over the same candidate paths as expected_uncertainty.
#include <asf/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class MechanicalWorkPlanner final : public asf::eu::CriterionPlanner {
 public:
  MechanicalWorkPlanner() : CriterionPlanner(asf::eu::Criterion::MechanicalWork) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyInt("max_paths", "10000", "Candidate simple paths evaluated at most", 1, 1e9),
    asf::keyBool("reduce", "true", "Search the reduced graph (degree-2 chains collapsed)"),
    asf::keyDouble("max_seconds", "10",
                   "Stop evaluating candidate paths after this long, keeping the best so far "
                   "(0: no limit) [s]",
                   0, 1e6),
};

}  // namespace

ASF_PLUGIN(MechanicalWorkPlanner, asf::PluginKind::Planner, "mechanical_work", "1.0.0",
           "Path with the least mechanical work in uncertainty (Valencia et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
