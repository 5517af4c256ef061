// The report of `asf reproduce`: report.json (everything, for scripts), report.md (the rows
// and links to the figures) and report.html (self-contained: SVGs inline, PNGs embedded).
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/studies/reproduce.h>
#include <asf/evaluation/run_report.h>
#include <asf/text.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>

namespace asf::studies::reproduce {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* statusName(StageResult::Status s) {
  switch (s) {
    case StageResult::kDone:
      return "done";
    case StageResult::kReused:
      return "done before";
    case StageResult::kFailed:
      return "FAILED";
    case StageResult::kSkipped:
      return "skipped";
    case StageResult::kNotRun:
      return "not run";
  }
  return "?";
}

/// Sections in the order of their first row, then those with figures only.
std::vector<std::string> sectionOrder(const Report& r) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const auto& row : r.rows)
    if (seen.insert(row.section).second) order.push_back(row.section);
  for (const auto& f : r.figures)
    if (seen.insert(f.section).second) order.push_back(f.section);
  return order;
}

std::string sectionNote(const Report& r, const std::string& section) {
  for (const auto& [name, text] : r.sections)
    if (name == section) return text;
  return "";
}

std::string mdCell(std::string s) {
  for (std::size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  return s.empty() ? "–" : s;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// An inline SVG (its XML declaration dropped) or an embedded PNG.
std::string embedded(const std::string& path, const std::string& alt) {
  if (fs::path(path).extension() == ".png") return evaluation::report::embeddedPng(path, alt);
  std::string svg = readFile(path);
  const auto start = svg.find("<svg");
  return start == std::string::npos ? "" : svg.substr(start);
}

}  // namespace

std::size_t Report::missing() const {
  std::size_t n = 0;
  for (const auto& row : rows) n += row.asf.empty();
  return n;
}

void write(const Settings& s, const Report& r, const std::vector<Stage>& stages,
           const std::vector<StageResult>& results) {
  json j;
  j["asf_version"] = ASF_VERSION_STRING;
  j["settings"] = {{"quick", s.quick},
                   {"pairs", s.pairs},
                   {"recognition_samples", s.recognition_samples},
                   {"figure_samples", s.figure_samples},
                   {"replications", s.replications},
                   {"max_distance", s.max_distance},
                   {"jobs", s.jobs},
                   {"shared", s.shared},
                   {"configs", s.configs}};
  for (std::size_t i = 0; i < stages.size(); ++i)
    j["stages"].push_back({{"id", stages[i].id},
                           {"title", stages[i].title},
                           {"status", statusName(results[i].status)},
                           {"seconds", results[i].seconds},
                           {"why", results[i].why}});
  for (const auto& [name, text] : r.sections)
    j["sections"].push_back({{"name", name}, {"note", text}});
  j["rows"] = json::array();
  for (const auto& row : r.rows)
    j["rows"].push_back({{"section", row.section},
                         {"item", row.item},
                         {"thesis", row.thesis},
                         {"asf", row.asf},
                         {"difference", row.difference},
                         {"note", row.note},
                         {"stage", row.stage}});
  j["figures"] = json::array();
  for (const auto& f : r.figures)
    j["figures"].push_back({{"section", f.section}, {"caption", f.caption}, {"file", f.file}});
  writeFileAtomically(s.out + "/report.json", j.dump(1) + "\n");

  const std::size_t missing = r.missing();
  const std::string title = "The thesis' chapters 3-6 reproduced by asf";
  std::ostringstream md;
  md << "# " << title << "\n\n";
  if (s.quick)
    md << "**--quick**: smoke-run sizes (a few pairs, samples and one short run per policy). These "
          "values show that every step runs, not what the thesis' experiments give.\n\n";
  md << r.rows.size() << " rows, " << missing << " without an asf value. asf " << ASF_VERSION_STRING
     << "; data " << s.shared << ".\n\n| stage | status | time [s] | note |\n|---|---|---:|---|\n";
  for (std::size_t i = 0; i < stages.size(); ++i)
    md << "| " << stages[i].id << " | " << statusName(results[i].status) << " | "
       << static_cast<long>(results[i].seconds + 0.5) << " | " << mdCell(results[i].why) << " |\n";

  std::ostringstream html;
  html << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>" << title << "</title><style>"
       << evaluation::report::css() << "</style></head><body><h1>" << title << "</h1>";
  if (s.quick)
    html << "<p><b>--quick</b>: smoke-run sizes. These values show that every step runs, not what "
            "the "
            "thesis' experiments give.</p>";
  html << "<p>" << r.rows.size() << " rows, " << missing << " without an asf value. asf "
       << ASF_VERSION_STRING << "; data " << htmlEscape(s.shared) << ".</p>";

  for (const auto& section : sectionOrder(r)) {
    const std::string note = sectionNote(r, section);
    md << "\n## " << section << "\n\n" << (note.empty() ? "" : note + "\n\n");
    html << "<h2>" << htmlEscape(section) << "</h2>"
         << (note.empty() ? "" : "<p>" + htmlEscape(note) + "</p>");
    bool any = false;
    for (const auto& row : r.rows) {
      if (row.section != section) continue;
      if (!any) {
        md << "| figure | thesis value | asf value | difference | note |\n|---|---|---|---|---|\n";
        html << "<table><tr><th>figure</th><th>thesis value</th><th>asf "
                "value</th><th>difference</th>"
                "<th>note</th></tr>";
        any = true;
      }
      md << "| " << mdCell(row.item) << " | " << mdCell(row.thesis) << " | " << mdCell(row.asf)
         << " | " << mdCell(row.difference) << " | " << mdCell(row.note) << " |\n";
      html << "<tr><td>" << htmlEscape(row.item) << "</td><td>" << htmlEscape(row.thesis)
           << "</td><td>" << htmlEscape(row.asf) << "</td><td>" << htmlEscape(row.difference)
           << "</td><td>" << htmlEscape(row.note) << "</td></tr>";
    }
    if (any) html << "</table>";
    for (const auto& f : r.figures) {
      if (f.section != section) continue;
      md << "\n![" << f.caption << "](" << f.file << ")\n";
      const std::string img = embedded(s.out + "/" + f.file, f.caption);
      if (!img.empty())
        html << "<div><figure>" << img << "<figcaption>" << htmlEscape(f.caption) << " ("
             << htmlEscape(f.file) << ")</figcaption></figure></div>";
    }
  }
  html << "<h2>Stages</h2><table><tr><th>stage</th><th>what</th><th>status</th><th>time [s]</th>"
          "<th>note</th></tr>";
  for (std::size_t i = 0; i < stages.size(); ++i)
    html << "<tr><td>" << stages[i].id << "</td><td>" << htmlEscape(stages[i].title) << "</td><td>"
         << statusName(results[i].status) << "</td><td>"
         << static_cast<long>(results[i].seconds + 0.5) << "</td><td>" << htmlEscape(results[i].why)
         << "</td></tr>";
  html << "</table></body></html>\n";
  writeFileAtomically(s.out + "/report.md", md.str());
  writeFileAtomically(s.out + "/report.html", html.str());
}

}  // namespace asf::studies::reproduce
