// planner_expected_uncertainty: the path whose expected covariance at the goal is smallest
// (thesis chapter 3, Algorithm 1) among all simple paths of the reduced pose graph.
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>

namespace {

class ExpectedUncertaintyPlanner final : public asf::planning::CriterionPlanner {
 public:
  ExpectedUncertaintyPlanner() : CriterionPlanner(asf::planning::Criterion::ExpectedUncertainty) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("scalar", "det", "det|trace|det_cbrt",
                 "Scalar of the expected goal covariance E[C]: det, trace or det^(1/3)"),
    asf::keyDouble("window_x", "0.3", "Half width of the localization window in x [m]", 1e-6,
                   1e6),
    asf::keyDouble("window_y", "0.3", "Half width of the localization window in y [m]", 1e-6,
                   1e6),
    asf::keyDouble("window_phi_deg", "30", "Half width of the localization window in angle [deg]",
                   1e-6, 180),
    asf::keyDouble("p_recognition", "1",
                   "Place-recognition probability of nodes not in p_recognition_file", 0, 1),
    asf::keyPath("p_recognition_file", "",
                 "Optional file of 'node_id probability' lines (place recognition per node)"),
    asf::keyInt("recognition_samples", "0",
                "> 0: p_recognition of nodes with a scan by Monte Carlo, this many ICP "
                "relocalizations each (nodes in p_recognition_file keep theirs); 0: the constant",
                0, 100000),
    asf::keyDouble("recognition_map_radius", "6.0",
                   "Monte Carlo: the local map holds the other nodes' scans within this [m]", 0.1,
                   1000),
    asf::keyInt("qmc_points", "128", "Lattice points of the Gaussian window integral", 2, 1e6),
    asf::keyInt("qmc_shifts", "8", "Random lattice shifts (error estimate) of the integral", 2,
                1000),
    asf::keyBool("use_cross", "true",
                 "Use robot/node cross-covariances from the marginals (else independent)"),
    asf::keyDouble("prune_below", "1e-12",
                   "Drop hypotheses whose probability falls below this (0: exact O(m^2))", 0, 1),
    asf::keyInt("seed", "0", "Seed of the lattice shifts (0: the run's seed)", 0, 9.0e15),
    ASF_EU_PATH_SEARCH_KEYS,
    ASF_EU_VORONOI_KEYS,
};

}  // namespace

ASF_PLUGIN(ExpectedUncertaintyPlanner, asf::PluginKind::Planner, "expected_uncertainty", "1.0.0",
           "Path minimizing the expected goal covariance under relocalization (Algorithm 1)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
