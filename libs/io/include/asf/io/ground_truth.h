#pragma once
/// \file ground_truth.h
/// Ground-truth files: text, one pose per line, `timestamp x y phi` (seconds, metres,
/// radians); `#` starts a comment line.
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asf::io {

struct GroundTruthPose {
  double t = 0;
  mrpt::poses::CPose2D pose;
};

/// Reads a ground-truth file. Throws asf::InputError naming the file and line on a bad line.
/// Lines must have increasing timestamps.
std::vector<GroundTruthPose> readGroundTruth(const std::string& path);

/// Pose at time t by linear interpolation (angles on the circle) between the neighbouring
/// lines; std::nullopt outside [first, last] or in a gap wider than max_gap seconds.
/// A t within 1 us of a line (the resolution GT files are usually printed with) is that
/// line's pose, also next to a gap or just past an end.
std::optional<mrpt::poses::CPose2D> interpolateGroundTruth(const std::vector<GroundTruthPose>& gt,
                                                           double t, double max_gap = 0.5);

/// Writes a ground-truth file line by line (flushed as it goes, so a crash keeps the lines
/// written so far).
class GroundTruthWriter {
 public:
  explicit GroundTruthWriter(const std::string& path);  ///< throws asf::InputError
  ~GroundTruthWriter();
  /// Throws asf::Error naming the file when the write fails or the writer is closed.
  void write(double t, const mrpt::poses::CPose2D& pose);
  void flush();
  /// Closes the file; throws asf::Error naming it when the close failed. Closing again does
  /// nothing.
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf::io
