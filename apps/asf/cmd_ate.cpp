// asf ate: absolute trajectory error of any trajectory file against a ground-truth file; the
// command behind the SLAM accuracy figures (asf's keyframes.txt, icp-slam's estimated path).
#include <asf/atomic_file.h>
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/evaluation/trajectory_eval.h>
#include <tclap/CmdLine.h>

#include <cmath>
#include <sstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"

namespace asf::app {

namespace {

/// --frame-times: the estimate's first column holds 0-based frame indices of `rawlog` (MRPT
/// icp-slam's log_estimated_path.txt); each becomes the time of its frame.
void timeFramesByRawlog(std::vector<evaluation::TimedPose>& estimate,
                        const std::string& estimate_file, const std::string& rawlog) {
  std::vector<double> times;
  io::RawlogReader log(rawlog);
  while (auto f = log.next()) times.push_back(f->timestamp);
  for (evaluation::TimedPose& p : estimate) {
    const double k = p.t;
    if (k < 0 || k != std::floor(k) || k >= static_cast<double>(times.size()))
      throw InputError(estimate_file + ": frame index " + std::to_string(k) +
                       " is not one of the " + std::to_string(times.size()) + " frames of " +
                       rawlog);
    p.t = times[static_cast<std::size_t>(k)];
  }
}

/// --errors: each matched pose's time and position error, one per line.
void writePoseErrors(const std::string& file, const evaluation::TrajectoryError& r) {
  std::ostringstream f;
  f << "# t error_m (after " << (r.aligned ? "SE(2) alignment" : "no alignment") << ")\n"
    << std::setprecision(17);
  for (std::size_t i = 0; i < r.errors_m.size(); ++i)
    f << r.times[i] << ' ' << r.errors_m[i] << '\n';
  writeFileAtomically(file, f.str(), "pose errors");
}

void printAteJson(const std::string& estimate, const std::string& ground_truth,
                  const evaluation::TrajectoryError& r) {
  nlohmann::json j;
  j["estimate"] = estimate;
  j["ground_truth"] = ground_truth;
  j["poses"] = r.poses;
  j["unmatched"] = r.unmatched;
  j["ate_rmse_m"] = r.ate_rmse_m;
  j["ate_mean_m"] = r.ate_mean_m;
  j["ate_max_m"] = r.ate_max_m;
  j["rot_rmse_deg"] = r.rot_rmse_deg;
  j["aligned"] = r.aligned;
  j["alignment"] = {r.alignment.x(), r.alignment.y(), r.alignment.phi()};
  std::cout << j.dump(2) << "\n";
}

void printAteText(const evaluation::TrajectoryError& r) {
  std::cout << "asf ate: " << r.poses << " poses (" << r.unmatched
            << " without ground truth), ATE RMSE " << r.ate_rmse_m << " m, mean "
            << r.ate_mean_m << " m, max " << r.ate_max_m << " m, heading RMSE "
            << r.rot_rmse_deg << " deg" << (r.aligned ? " (after SE(2) alignment)" : "")
            << "\n";
}

}  // namespace

int cmdAte(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Absolute trajectory error (ATE) of an estimated trajectory against ground truth: each "
      "estimated pose is paired with the ground truth interpolated at its time, the estimate "
      "is aligned by the rigid SE(2) transform minimising the error (unless --no-align), and "
      "the RMSE, mean and max position errors and the heading RMSE are printed. Both files: "
      "text lines 't x y phi' (s, m, m, rad; more columns ignored; '#'/'%' comments), e.g. a "
      "run's keyframes.txt or MRPT icp-slam's log_estimated_path.txt.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> est("estimate", "Estimated trajectory", true, "",
                                            "ESTIMATE.txt", cmd);
  TCLAP::UnlabeledValueArg<std::string> gt("ground_truth", "Ground-truth file", true, "",
                                           "GT.txt", cmd);
  TCLAP::ValueArg<double> gap("g", "max-gap",
                              "Widest ground-truth gap to interpolate across (s)", false, 0.5,
                              "SECONDS", cmd);
  TCLAP::ValueArg<std::string> frame_times(
      "f", "frame-times",
      "The estimate's first column is a 0-based frame index of this rawlog (as asf reads it, "
      "one frame per scan), not a time: MRPT icp-slam's log_estimated_path.txt",
      false, "", "LOG.rawlog", cmd);
  TCLAP::ValueArg<std::string> per_pose("e", "errors",
                                        "Write each matched pose's time and position error "
                                        "(after alignment) to this file",
                                        false, "", "OUT.txt", cmd);
  TCLAP::SwitchArg no_align("n", "no-align", "Compare in the frames as given", cmd);
  TCLAP::SwitchArg json("j", "json",
                        "Print one JSON object: poses, unmatched, ate_rmse_m, ate_mean_m, "
                        "ate_max_m, rot_rmse_deg, alignment [x, y, phi]",
                        cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  auto estimate = evaluation::readTrajectory(est.getValue());
  if (!frame_times.getValue().empty())
    timeFramesByRawlog(estimate, est.getValue(), frame_times.getValue());
  const auto truth = io::readGroundTruth(gt.getValue());
  const evaluation::TrajectoryError r =
      evaluation::evaluateTrajectory(estimate, truth, gap.getValue(), !no_align.getValue());
  // Finite inputs can still overflow (coordinates near 1e200 m): no figure rather than "inf".
  for (const double v : {r.ate_rmse_m, r.ate_mean_m, r.ate_max_m, r.rot_rmse_deg})
    if (!std::isfinite(v))
      throw InputError(est.getValue() + " against " + gt.getValue() +
                       ": the error is not a finite number (coordinates too large to square: "
                       "not a robot's trajectory in metres?)");
  if (!per_pose.getValue().empty()) writePoseErrors(per_pose.getValue(), r);
  if (json.getValue())
    printAteJson(est.getValue(), gt.getValue(), r);
  else
    printAteText(r);
  return kOk;
}

}  // namespace asf::app
