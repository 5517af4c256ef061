// Ground-truth files (see ground_truth.h).
#include <asf/errors.h>
#include <asf/io/ground_truth.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>

namespace asf::io {

using mrpt::poses::CPose2D;

std::vector<GroundTruthPose> readGroundTruth(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the ground-truth file");
  std::vector<GroundTruthPose> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    std::istringstream ls(line);
    double v[4];
    std::string extra;
    const auto where = path + ":" + std::to_string(n) + ": ";
    if (!(ls >> v[0] >> v[1] >> v[2] >> v[3]))
      throw InputError(where + "expected 'timestamp x y phi', got '" + line + "'");
    if (ls >> extra)
      throw InputError(where + "unexpected '" + extra + "' after 'timestamp x y phi'");
    for (double x : v)
      if (!std::isfinite(x)) throw InputError(where + "non-finite value");
    if (!out.empty() && !(v[0] > out.back().t))
      throw InputError(where + "timestamp " + std::to_string(v[0]) +
                       " is not after the previous line's " + std::to_string(out.back().t));
    out.push_back({v[0], CPose2D(v[1], v[2], v[3])});
  }
  return out;
}

std::optional<CPose2D> interpolateGroundTruth(const std::vector<GroundTruthPose>& gt, double t,
                                              double max_gap) {
  if (gt.empty() || !std::isfinite(t)) return std::nullopt;
  // Ground truth is usually logged at the sensor times but printed with 6 decimals: a frame
  // within that rounding of a line is at that line, also when a gap or an end follows.
  constexpr double kSameTime = 1e-6;
  auto hi = std::upper_bound(gt.begin(), gt.end(), t,
                             [](double x, const GroundTruthPose& g) { return x < g.t; });
  if (hi != gt.end() && hi->t - t <= kSameTime) return hi->pose;
  if (hi == gt.begin()) return std::nullopt;  // before the first line
  const auto lo = hi - 1;
  if (t - lo->t <= kSameTime) return lo->pose;
  if (hi == gt.end()) return std::nullopt;  // after the last line
  if (hi->t - lo->t > max_gap) return std::nullopt;
  const double s = (t - lo->t) / (hi->t - lo->t);
  const double dphi = mrpt::math::wrapToPi(hi->pose.phi() - lo->pose.phi());
  return CPose2D(lo->pose.x() + s * (hi->pose.x() - lo->pose.x()),
                 lo->pose.y() + s * (hi->pose.y() - lo->pose.y()),
                 mrpt::math::wrapToPi(lo->pose.phi() + s * dphi));
}

struct GroundTruthWriter::Impl {
  std::string path;
  std::FILE* f = nullptr;
};

GroundTruthWriter::GroundTruthWriter(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->f = std::fopen(path.c_str(), "w");
  if (!impl_->f) throw InputError(path + ": cannot create the ground-truth file");
  std::fprintf(impl_->f, "# timestamp x y phi (s, m, m, rad)\n");
  std::fflush(impl_->f);
}

GroundTruthWriter::~GroundTruthWriter() {
  if (impl_ && impl_->f) std::fclose(impl_->f);
}

void GroundTruthWriter::write(double t, const CPose2D& pose) {
  if (!impl_->f) throw Error(impl_->path + ": not open for writing (closed)");
  // Flushed per line: a crashed run keeps every pose written so far.
  if (std::fprintf(impl_->f, "%.9f %.9f %.9f %.9f\n", t, pose.x(), pose.y(), pose.phi()) < 0 ||
      std::fflush(impl_->f) != 0)
    throw Error(impl_->path + ": write failed");
}

void GroundTruthWriter::flush() {
  if (impl_->f) std::fflush(impl_->f);
}

void GroundTruthWriter::close() {
  if (!impl_->f) return;
  std::FILE* f = std::exchange(impl_->f, nullptr);
  if (std::fclose(f) != 0) throw Error(impl_->path + ": close failed");
}

}  // namespace asf::io
