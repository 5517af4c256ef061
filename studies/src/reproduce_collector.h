#pragma once
// Internal to `asf reproduce`: how the rows are collected (reproduce_rows*.cpp, one file per
// chapter of the thesis) and the number formats they share.
#include <asf/studies/reproduce.h>
#include <asf/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace asf::studies::reproduce {

namespace fs = std::filesystem;
using nlohmann::json;

/// A table cell: fixed decimals, "n/a" for a value the run did not produce (NaN, inf).
inline std::string fmt(double v, int digits = 1) {
  return std::isfinite(v) ? formatFixed(v, digits) : "n/a";
}
inline std::string sci(double v) { return formatSignificant(v, 3); }
inline std::string pm(double mean, double sd, int digits) {
  return fmt(mean, digits) + " ± " + fmt(sd, digits);
}
inline std::string points(double asf, double thesis) {
  return (asf >= thesis ? "+" : "") + fmt(asf - thesis) + " points";
}
inline std::string ratio(double asf, double thesis) { return "× " + fmt(asf / thesis, 2); }

/// Collects rows; a stage's JSON output read once, null when missing or unreadable.
class Collector {
 public:
  Collector(const Settings& s, const std::vector<Stage>& stages,
            const std::vector<StageResult>& results)
      : s_(s) {
    for (std::size_t i = 0; i < stages.size(); ++i) status_[stages[i].id] = results[i];
  }

  json read(const std::string& stage, const std::string& file) {
    const std::string path = s_.out + "/" + stage + "/" + file;
    std::ifstream in(path);
    if (!in) return nullptr;
    try {
      return json::parse(in);
    } catch (const std::exception&) {
      return nullptr;
    }
  }

  /// A row from `stage`; an empty asf value gets a note saying why.
  void row(const std::string& stage, const std::string& section, const std::string& item,
           const std::string& thesis, const std::string& asf, const std::string& diff,
           const std::string& note = "") {
    Row r{section, item, thesis, asf, diff, note, stage};
    if (asf.empty()) {
      const auto it = status_.find(stage);
      std::string why = "not produced";
      if (it != status_.end() && !it->second.why.empty())
        why += ": " + it->second.why;
      else if (it != status_.end() && it->second.status == StageResult::kNotRun)
        why += ": not run";
      r.difference = "";
      r.note = "stage " + stage + " " + why;
    }
    report.rows.push_back(r);
  }

  void figure(const std::string& section, const std::string& caption, const std::string& file) {
    if (fs::exists(s_.out + "/" + file)) report.figures.push_back({section, caption, file});
  }
  /// The distances d of a run's snapshots (OUT/<stage>/run/snapshots/at_<d>m_map.png), as
  /// written in the file names, nearest first.
  std::vector<std::string> snapshotDistances(const std::string& stage) const {
    std::vector<std::string> d;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(s_.out + "/" + stage + "/run/snapshots", ec)) {
      const std::string f = e.path().filename().string();
      if (f.size() > 11 && f.rfind("at_", 0) == 0 && f.substr(f.size() - 8) == "_map.png")
        d.push_back(f.substr(3, f.size() - 12));  // between "at_" and "m_map.png"
    }
    std::sort(d.begin(), d.end(), [](const std::string& a, const std::string& b) {
      return std::stod(a) < std::stod(b);
    });
    return d;
  }
  void section(const std::string& name, const std::string& text) {
    report.sections.push_back({name, text});
  }

  const Settings& s_;
  std::map<std::string, StageResult> status_;
  Report report;
};

inline double num(const json& j, const std::vector<std::string>& path) {
  const json* p = &j;
  for (const auto& k : path) {
    if (!p->is_object() || !p->contains(k)) return NAN;
    p = &(*p)[k];
  }
  return p->is_number() ? p->get<double>() : NAN;
}

/// The rows of each chapter (reproduce_rows_ch3.cpp, reproduce_rows_ch45.cpp,
/// reproduce_rows.cpp), with their sections' notes.
void chapter3(Collector& c);
void chapters4and5(Collector& c);
void chapter6(Collector& c);

}  // namespace asf::studies::reproduce
