// The live source's state, independent of DDS (live_core.h).
#include "live_core.h"

#include <asf/statistics.h>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

namespace asf::ros2live {

using mrpt::poses::CPose2D;

bool PoseHistory::add(double t, const CPose2D& p) {
  if (!poses_.empty() && t < poses_.back().first) return false;
  if (!poses_.empty() && t == poses_.back().first) {
    poses_.back().second = p;  // a repeated stamp: the later message wins
    return true;
  }
  poses_.emplace_back(t, p);
  while (poses_.size() > capacity_) poses_.pop_front();
  return true;
}

std::optional<CPose2D> PoseHistory::at(double t, double tolerance) const {
  if (poses_.empty()) return std::nullopt;
  if (t <= poses_.front().first) {
    if (poses_.front().first - t > tolerance) return std::nullopt;
    return poses_.front().second;
  }
  if (t >= poses_.back().first) {
    if (t - poses_.back().first > tolerance) return std::nullopt;
    return poses_.back().second;
  }
  // The first pose not before t; the one before it is before t.
  std::size_t lo = 0, hi = poses_.size() - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (poses_[mid].first < t ? lo : hi) = mid;
  }
  const auto& [ta, a] = poses_[lo];
  const auto& [tb, b] = poses_[hi];
  if (tb - ta <= 0) return b;
  // Interpolation on SE(2) by the increment: a (+) s * (a^-1 (+) b).
  const double s = (t - ta) / (tb - ta);
  const CPose2D d = b - a;
  return a + CPose2D(s * d.x(), s * d.y(), s * d.phi());
}

void TransformTree::set(const std::string& parent, const std::string& child,
                        const mrpt::poses::CPose3D& p) {
  parent_of_[child] = {parent, p};
}

std::optional<mrpt::poses::CPose3D> TransformTree::lookup(const std::string& base,
                                                          const std::string& frame) const {
  mrpt::poses::CPose3D acc;  // frame in the current ancestor
  std::string at = frame;
  for (int links = 0; links <= 16; ++links) {
    if (at == base) return acc;
    const auto it = parent_of_.find(at);
    if (it == parent_of_.end()) return std::nullopt;
    acc = it->second.second + acc;
    at = it->second.first;
  }
  return std::nullopt;
}

std::string TransformTree::describe() const {
  if (parent_of_.empty()) return "none";
  std::ostringstream os;
  bool first = true;
  for (const auto& [child, pp] : parent_of_) {
    os << (first ? "" : ", ") << pp.first << " -> " << child;
    first = false;
  }
  return os.str();
}

namespace {
bool terminal(std::int8_t s) {
  return s == static_cast<std::int8_t>(ros2::GoalState::Succeeded) ||
         s == static_cast<std::int8_t>(ros2::GoalState::Canceled) ||
         s == static_cast<std::int8_t>(ros2::GoalState::Aborted);
}
}  // namespace

void GoalTracker::sent(double wall_time) {
  pending_ = true;
  ours_.reset();
  state_ = 0;
  state_after_scans_ = 0;
  sent_at_ = wall_time;
  why_.clear();
}

void GoalTracker::statusArrived(const std::vector<GoalStatusEntry>& list,
                                std::uint64_t scans_arrived) {
  if (pending_ && !ours_)
    for (const GoalStatusEntry& e : list)
      if (!seen_.count(e.id)) {
        ours_ = e.id;
        break;
      }
  if (pending_ && ours_)
    for (const GoalStatusEntry& e : list)
      if (e.id == *ours_ && e.status != state_) {
        state_ = e.status;
        if (terminal(state_)) state_after_scans_ = scans_arrived;
      }
  for (const GoalStatusEntry& e : list) seen_.insert(e.id);
}

NavStatus GoalTracker::status(std::uint64_t scans_returned, double wall_time,
                              double accept_timeout, double goal_timeout) {
  if (!pending_) return last_;
  std::ostringstream why;
  if (!ours_ && wall_time - sent_at_ > accept_timeout) {
    why << "no navigation goal was accepted within " << accept_timeout
        << " s of sending it (is a navigator running and publishing its status?)";
    last_ = NavStatus::Unreachable;
  } else if (ours_ && terminal(state_) && scans_returned >= state_after_scans_) {
    why << "the navigator says " << ros2::goalStateName(state_);
    last_ = state_ == static_cast<std::int8_t>(ros2::GoalState::Succeeded) ? NavStatus::Reached
            : state_ == static_cast<std::int8_t>(ros2::GoalState::Aborted) ? NavStatus::Unreachable
                                                                            : NavStatus::Blocked;
  } else if (goal_timeout > 0 && wall_time - sent_at_ > goal_timeout) {
    why << "the goal took longer than goal_timeout_s = " << goal_timeout << " s";
    last_ = NavStatus::Blocked;
  } else {
    return NavStatus::Moving;
  }
  pending_ = false;
  why_ = why.str();
  return last_;
}

OperatorRequest::Kind parseOperatorCommand(const std::string& text) {
  std::string t;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c)))
      t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  using Kind = OperatorRequest::Kind;
  if (t == "start" || t == "resume") return Kind::Resume;
  if (t == "pause") return Kind::Pause;
  if (t == "stop") return Kind::Stop;
  if (t == "return_home") return Kind::ReturnHome;
  return Kind::None;
}

void OperatorInbox::arrived(const std::string& topic, const std::string& text) {
  const OperatorRequest::Kind k = parseOperatorCommand(text);
  std::lock_guard<std::mutex> lock(mu_);
  if (k == OperatorRequest::Kind::None)
    unknown_.push_back(text);
  else
    requests_.push_back({k, "topic " + topic + ": '" + text + "'"});
}

void OperatorInbox::push(OperatorRequest r) {
  std::lock_guard<std::mutex> lock(mu_);
  requests_.push_back(std::move(r));
}

OperatorRequest OperatorInbox::take() {
  std::lock_guard<std::mutex> lock(mu_);
  if (requests_.empty()) return {};
  OperatorRequest r = std::move(requests_.front());
  requests_.pop_front();
  return r;
}

std::vector<std::string> OperatorInbox::takeUnknown() {
  std::lock_guard<std::mutex> lock(mu_);
  return std::exchange(unknown_, {});
}

void ScanQueue::push(ros2::LaserScan msg) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    q_.push_back({std::move(msg), ++arrived_, std::chrono::steady_clock::now()});
    while (q_.size() > capacity_) {
      q_.pop_front();
      ++dropped_;
    }
  }
  cv_.notify_one();
}

std::optional<ArrivedScan> ScanQueue::pop(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mu_);
  if (!cv_.wait_for(lock, timeout, [&] { return !q_.empty(); })) return std::nullopt;
  ArrivedScan s = std::move(q_.front());
  q_.pop_front();
  return s;
}

std::uint64_t ScanQueue::arrived() const {
  std::lock_guard<std::mutex> lock(mu_);
  return arrived_;
}

std::uint64_t ScanQueue::dropped() const {
  std::lock_guard<std::mutex> lock(mu_);
  return dropped_;
}

std::string latencySummary(const std::vector<double>& ms) {
  if (ms.empty()) return "none";
  std::ostringstream os;
  os << "median " << percentile(ms, 50) << " ms, p95 " << percentile(ms, 95) << " ms, max "
     << *std::max_element(ms.begin(), ms.end()) << " ms over " << ms.size();
  return os.str();
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::map<std::string, double> otherThreadsCpuByName() {
  namespace fs = std::filesystem;
  const double tick = static_cast<double>(sysconf(_SC_CLK_TCK));
  const std::string self = std::to_string(static_cast<long>(syscall(SYS_gettid)));
  std::map<std::string, double> by_name;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/self/task", ec)) {
    if (e.path().filename() == self) continue;
    std::ifstream f(e.path() / "stat");
    std::string line;
    if (!std::getline(f, line)) continue;
    // After the command name in parentheses: state (field 3) ... utime (14), stime (15).
    const std::size_t lp = line.find('('), rp = line.rfind(')');
    if (lp == std::string::npos || rp == std::string::npos || rp < lp) continue;
    std::istringstream is(line.substr(rp + 1));
    std::string skip;
    for (int field = 3; field <= 13; ++field) is >> skip;
    long ut = 0, st = 0;
    if (is >> ut >> st)
      by_name[line.substr(lp + 1, rp - lp - 1)] += static_cast<double>(ut + st) / tick;
  }
  return by_name;
}

bool isCycloneThread(const std::string& n) {
  for (const char* p : {"recv", "tev", "dq.", "gc", "lease", "xmit", "dds_"})
    if (n.rfind(p, 0) == 0) return true;
  return false;
}

double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string bridgeCpuLine(const std::map<std::string, double>& threads, double run_thread_s,
                          double recording_s) {
  double dds = 0, other = 0;
  std::ostringstream names;
  for (const auto& [name, s] : threads) {
    if (!isCycloneThread(name)) {
      other += s;
      continue;
    }
    names << (names.tellp() > 0 ? ", " : "") << name << " " << s;
    dds += s;
  }
  std::ostringstream os;
  os << "bridge CPU: " << run_thread_s << " s on the run's thread (conversions, publishing, "
     << "the bag; the rawlog's " << recording_s << " s apart), " << dds
     << " s on Cyclone DDS's threads (" << names.str() << "), of " << processCpuSeconds()
     << " s for the whole run (" << other << " s on its other threads)";
  return os.str();
}

}  // namespace asf::ros2live
