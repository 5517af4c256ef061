#pragma once
// The scheduler of `asf reproduce` (the host's: it starts the stages as processes).
#include <asf/reproduce.h>

#include <vector>

namespace asf::reproduce {

/// Runs the stages not done yet, `s.jobs` cores at a time, each command's stderr in
/// OUT/<id>/stage.log; prints progress to stderr. Ctrl-C stops the running stages and returns
/// what finished. Results are in the order of `stages`.
std::vector<StageResult> run(const std::vector<Stage>& stages, const Settings& s);

/// The signal (SIGINT, SIGTERM) that stopped the last run(); 0 when none did.
int interruptingSignal();

}  // namespace asf::reproduce
