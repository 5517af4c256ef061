// planner_sum_dopt: the path minimizing the sum over its nodes of the D-optimality of their
// marginal covariance (Carrillo et al.; thesis eq. 3.24). A baseline of thesis chapter 3,
// searched over the same candidate paths as expected_uncertainty.
#include <asf/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class SumDoptPlanner final : public asf::eu::CriterionPlanner {
 public:
  SumDoptPlanner() : CriterionPlanner(asf::eu::Criterion::SumDopt) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("scalar", "det", "det|trace|det_cbrt",
                 "D-optimality of a node covariance: det (thesis), det^(1/3), or trace (A-opt)"),
    asf::keyInt("max_paths", "10000", "Candidate simple paths evaluated at most", 1, 1e9),
    asf::keyBool("reduce", "true", "Search the reduced graph (degree-2 chains collapsed)"),
    asf::keyDouble("max_seconds", "10",
                   "Stop evaluating candidate paths after this long, keeping the best so far "
                   "(0: no limit) [s]",
                   0, 1e6),
};

}  // namespace

ASF_PLUGIN(SumDoptPlanner, asf::PluginKind::Planner, "sum_dopt", "1.0.0",
           "Path minimizing the sum of the nodes' D-optimality (Carrillo et al.)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
