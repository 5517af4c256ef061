#pragma once
/// \file recorded_run.h
/// What a run folder recorded, read back to continue the run (`asf run --resume DIR`): the
/// source's sensor log with its ground truth, and the policy's decisions.
#include <asf/goal.h>
#include <asf/sensor_frame.h>

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace asf::io {

/// Streams the frames a source recorded as `<base>.rawlog` (RawlogWriter) with their ground
/// truth from `<base>.gt.txt` (line i is frame i, written together), up to the last frame both
/// hold: a run killed while writing leaves the rawlog a few frames shorter, or its last record
/// cut, and the frames readable before that are the run's. `fn` gets each frame with its
/// ground_truth set, and the observations of sensors besides the first laser in
/// observations3d (RawlogReaderOptions::observations3d). Returns the number of frames. Throws
/// InputError naming the file when either cannot be read, or when a ground-truth line's time is not
/// its frame's.
std::size_t forEachRecordedFrame(const std::string& base,
                                 const std::function<void(SensorFrame&)>& fn);

/// One row of a run's decisions.csv, fields by column name.
using DecisionRow = std::map<std::string, std::string>;
/// decisions.csv's rows (step, time_s, previous_status, decision, goal_x, goal_y, reason);
/// the last column (the reason) keeps any commas. `note` says why there are none (missing,
/// empty, no row).
std::vector<DecisionRow> readDecisionRows(const std::string& path, std::string& note);

/// One decision of a run's decisions.csv.
struct RecordedDecision {
  long step = 0;                         ///< frames processed when it was taken
  NavStatus previous = NavStatus::Idle;  ///< the outcome the policy was given
  bool done = false;
  double goal_x = 0, goal_y = 0;  ///< as written (6 significant digits); GoTo only
};

/// A run's decisions.csv. Throws InputError naming the file and line for a missing file or
/// a row that does not parse.
std::vector<RecordedDecision> readRecordedDecisions(const std::string& path);

}  // namespace asf::io
