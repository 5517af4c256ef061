// planner_sum_dopt: the path minimizing the sum over its nodes of the D-optimality of their
// marginal covariance (Carrillo et al.; thesis eq. 3.24). A baseline of thesis chapter 3,
// searched over the same candidate paths as expected_uncertainty.
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class SumDoptPlanner final : public asf::planning::CriterionPlanner {
 public:
  SumDoptPlanner() : CriterionPlanner(asf::planning::Criterion::SumDopt) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("scalar", "det", "det|trace|det_cbrt",
                 "D-optimality of a node covariance: det (thesis), det^(1/3), or trace (A-opt)"),
    ASF_EU_PATH_SEARCH_KEYS,
    ASF_EU_VORONOI_KEYS,
};

}  // namespace

ASF_PLUGIN(SumDoptPlanner, asf::PluginKind::Planner, "sum_dopt", "1.0.0",
           "Path minimizing the sum of the nodes' D-optimality (Carrillo et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
