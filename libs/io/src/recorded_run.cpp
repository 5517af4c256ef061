// A run folder's recorded log and decisions, read back to continue the run (recorded_run.h).
#include <asf/errors.h>
#include <asf/io/ground_truth.h>
#include <asf/io/rawlog_io.h>
#include <asf/io/recorded_run.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace asf::io {

std::size_t forEachRecordedFrame(const std::string& base,
                                 const std::function<void(SensorFrame&)>& fn) {
  const std::string log = base + ".rawlog", gt_file = base + ".gt.txt";
  if (!std::filesystem::exists(log)) throw InputError(log + ": no recorded log");
  const std::vector<GroundTruthPose> gt = readGroundTruth(gt_file);
  RawlogReaderOptions options;
  options.observations3d = true;  // a recording's other sensors too (a tilted laser)
  RawlogReader reader(log, options);
  std::size_t n = 0;
  while (n < gt.size()) {
    std::optional<SensorFrame> f;
    try {
      f = reader.next();
    } catch (const InputError&) {
      break;  // a record cut by a kill: the frames before it are the run's
    }
    if (!f) break;
    if (std::abs(f->timestamp - gt[n].t) > 1e-6)
      throw InputError(gt_file + ": line " + std::to_string(n + 1) + " is for time " +
                       std::to_string(gt[n].t) + " s, frame " + std::to_string(n) + " of " + log +
                       " for " + std::to_string(f->timestamp) + " s: not the same recording");
    f->ground_truth = gt[n].pose;
    fn(*f);
    ++n;
  }
  return n;
}

namespace {

NavStatus parseStatus(const std::string& s, const std::string& where) {
  for (NavStatus st : {NavStatus::Idle, NavStatus::Moving, NavStatus::Reached,
                       NavStatus::Unreachable, NavStatus::Blocked})
    if (s == navStatusName(st)) return st;
  throw InputError(where + ": previous_status '" + s + "' is not a navigation status");
}

double parseNumber(const std::string& s, const std::string& where, const char* column) {
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (s.empty() || pos != s.size() || !std::isfinite(v))
    throw InputError(where + ": " + column + " '" + s + "' is not a number");
  return v;
}

}  // namespace

std::vector<DecisionRow> readDecisionRows(const std::string& path, std::string& note) {
  std::vector<DecisionRow> rows;
  std::ifstream in(path);
  std::string line;
  if (!in) {
    note = "decisions.csv: missing";
    return rows;
  }
  if (!std::getline(in, line)) {
    note = "decisions.csv: empty";
    return rows;
  }
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) header.push_back(f);
  }
  while (std::getline(in, line)) {
    if (line.empty() || header.empty()) continue;
    DecisionRow row;
    std::stringstream ss(line);
    std::string x;
    for (std::size_t i = 0; i + 1 < header.size() && std::getline(ss, x, ','); ++i)
      row[header[i]] = x;
    if (std::getline(ss, x)) row[header.back()] = x;  // the rest of the line
    rows.push_back(std::move(row));
  }
  if (rows.empty()) note = "decisions.csv: no decision recorded";
  return rows;
}

std::vector<RecordedDecision> readRecordedDecisions(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": missing");
  std::string note;
  const std::vector<DecisionRow> rows = readDecisionRows(path, note);
  std::vector<RecordedDecision> out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const auto get = [&](const char* k) {
      const auto it = r.find(k);
      return it == r.end() ? std::string() : it->second;
    };
    const std::string where = path + ":" + std::to_string(i + 2);
    RecordedDecision d;
    d.step = static_cast<long>(parseNumber(get("step"), where, "step"));
    d.previous = parseStatus(get("previous_status"), where);
    const std::string kind = get("decision");
    if (kind != "goto" && kind != "done")
      throw InputError(where + ": decision '" + kind + "' is neither goto nor done");
    d.done = kind == "done";
    if (!d.done) {
      d.goal_x = parseNumber(get("goal_x"), where, "goal_x");
      d.goal_y = parseNumber(get("goal_y"), where, "goal_y");
    }
    out.push_back(d);
  }
  return out;
}

}  // namespace asf::io
