#pragma once
/// \file rawlog_io.h
/// Reading and writing robot logs as MRPT rawlogs, and ground-truth files.
///
/// A rawlog (MRPT's binary log format) comes in two layouts:
/// - action/sensory-frame pairs: CActionCollection (with a CActionRobotMovement2D, the
///   odometry increment and its Gaussian covariance) followed by a CSensoryFrame (the
///   observations of that step);
/// - observation-only: a time-ordered sequence of CObservation objects
///   (CObservationOdometry carries the absolute odometry pose, CObservation2DRangeScan the
///   scans).
/// Either may be gz-compressed. RawlogReader reads both and yields one SensorFrame per step;
/// RawlogWriter writes action/sensory-frame pairs, one per SensorFrame, so a replayed stream
/// equals the written one.
///
/// Ground-truth files: asf/ground_truth.h.
#include <asf/io/ground_truth.h>
#include <asf/mapping/map3d.h>
#include <asf/mapping/odometry_noise.h>
#include <asf/sensor_frame.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asf::io {

/// The cause in one of MRPT's exception texts (nested "Exception while parsing typed object"
/// frames around it, call traces, a "==== MRPT exception ====" banner), with the objects it
/// happened in: "(EOF?) Cannot read ... (in CSensoryFrame > CObservation2DRangeScan)".
std::string mrptExceptionCause(const std::string& what);

struct RawlogReaderOptions {
  /// Which CObservation2DRangeScan to use, by sensorLabel. Empty: the first laser seen;
  /// scans of other labels are skipped (and counted).
  std::string laser_label;
  /// Covariance of odometry increments for logs that carry none (observation-only logs).
  mapping::OdometryNoiseModel odometry_model;
  /// Optional ground-truth file: frames get the pose interpolated at their timestamp.
  std::string ground_truth_file;
  double ground_truth_max_gap = 0.5;  ///< seconds, see interpolateGroundTruth
  /// Attach the step's 3D observations to SensorFrame::observations3d: point clouds,
  /// Velodyne scans, 3D range scans, rotating scans, and 2D scans of lasers other than the
  /// chosen one (a tilted laser).
  bool observations3d = false;
  /// Frames come from a 3D sensor: its observations (label `label_3d`, empty: the first 3D
  /// observation seen) become the frames, their 2D scan the horizontalSlice() of their
  /// points; 2D laser scans are then not used as frame scans.
  bool scan_from_3d = false;
  std::string label_3d;
  mapping::SliceOptions slice;
};

/// Streams a rawlog, one SensorFrame per step:
/// - action/sensory-frame logs: one frame per pair; odometry from the CActionRobotMovement2D
///   (mean and covariance), the scan with the chosen label (or none);
/// - observation-only logs: one frame per chosen laser scan; odometry is the increment of the
///   CObservationOdometry poses between consecutive scans (the last reading at or before
///   each scan), its covariance from `odometry_model`;
/// - with scan_from_3d, the chosen 3D sensor's observations take the place of the chosen
///   laser scans above (one frame per sensory frame holding one, or per observation);
/// - with observations3d, a sensory frame's 3D observations go to its frame; in an
///   observation-only log they go to the next frame emitted (the next chosen scan).
/// A truncated or corrupt log ends the stream with asf::InputError naming the file and the
/// record index; every frame returned before stays valid.
///
/// Details:
/// - the frame time is the chosen scan's timestamp, else the movement's, else (no valid
///   time at all) the previous frame's; times are mrpt::Clock::toDouble of MRPT timestamps;
/// - a first sensory frame without a movement before it (and the first frame of an
///   observation-only log) has a zero increment with zero covariance; a later one gets a zero
///   increment with `odometry_model`'s covariance of standing still; two actions in a row are
///   composed (CPosePDFGaussian +=);
/// - a movement whose PDF is not Gaussian (MRPT's sample-based Thrun model) is replaced by its
///   raw odometry reading with `odometry_model`'s covariance (MRPT redraws those samples at
///   random on every load);
/// - observation-only logs: a reading timestamped after a scan is kept for the next scans even
///   when stored before it; without readings the increment is zero (model covariance);
/// - an empty file is a log without frames, not an error.
class RawlogReader {
 public:
  RawlogReader(const std::string& path, RawlogReaderOptions options = {});
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// Next frame, or std::nullopt at the end (and on every later call).
  std::optional<SensorFrame> next();
  /// Index of the last record read (0-based; each serialized object is one record).
  std::size_t recordIndex() const;
  /// Laser labels seen so far and scans skipped because of their label.
  std::vector<std::string> laserLabels() const;
  std::size_t skippedScans() const;
  /// 3D observations (range scans, point clouds, velodyne scans) read but not used: neither
  /// observations3d nor scan_from_3d was asked for.
  std::size_t unused3dObservations() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes SensorFrames as action/sensory-frame pairs: a CActionCollection holding a
/// CActionRobotMovement2D (odometry increment, its covariance as a CPosePDFGaussian, the
/// frame's timestamp) and a CSensoryFrame holding the scan (empty when the frame has none)
/// followed by the frame's observations3d (read back with RawlogReaderOptions::observations3d
/// and laser_label set to the scan's label).
/// A path ending in ".gz" is gz-compressed. Flushes every `flush_every` frames and on close.
///
/// Replay fidelity (what RawlogReader gives back): timestamps as
/// Clock::toDouble(Clock::fromDouble(t)) (100 ns ticks); odometry mean bit-identical; the
/// covariance bit-identical when it is exactly symmetric (MRPT stores one triangle); the scan
/// as serialized by MRPT, with its timestamp set to the frame's. The movement is written with
/// estimationMethod = emScan2DMatching: for emOdometry MRPT serializes only the raw reading and
/// recomputes the covariance from its motion model on load, which would lose ours.
/// Ground truth is not written here (use GroundTruthWriter). flush_every = 0: only flush() and
/// close flush.
class RawlogWriter {
 public:
  explicit RawlogWriter(const std::string& path, std::size_t flush_every = 50);
  ~RawlogWriter();  ///< closes (flushes) the file
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  /// Throws asf::Error naming the file when a write fails or the writer is closed.
  void write(const SensorFrame& frame);
  void flush();
  /// Closes the file; throws asf::Error naming it when anything written was lost (the
  /// destructor closes too, but cannot report).
  void close();
  std::size_t framesWritten() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf::io
