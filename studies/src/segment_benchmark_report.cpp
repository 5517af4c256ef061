// The report of `asf segment-eval` (asf/studies/segment_benchmark.h): the JSON with every
// map's scores and the per-variant summaries, and the table and summary lines it prints.
#include <asf/studies/segment_benchmark.h>
#include <asf/text.h>

#include <algorithm>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace asf::studies {

namespace {

using nlohmann::json;
using MapResult = BenchmarkMapResult;

json thesisJson(const evaluation::ThesisProtocolScore& t) {
  return {{"precision", t.precision},
          {"recall", t.recall},
          {"rooms", t.rooms},
          {"segments", t.segments}};
}

json scoreJson(const evaluation::SegmentationScore& s) {
  return {{"precision", s.precision},
          {"recall", s.recall},
          {"precision_pooled", s.precision_pooled},
          {"recall_pooled", s.recall_pooled},
          {"mcc", s.mcc},
          {"segments", s.segments},
          {"rooms", s.rooms}};
}

json agreementJson(const evaluation::SegmentationAgreement& a) {
  return {{"iou", a.iou_reference},
          {"iou_segments", a.iou_segmentation},
          {"ari", a.ari},
          {"segments", a.segments},
          {"reference_regions", a.reference_regions},
          {"pixels_compared", a.pixels_compared}};
}

json incrementalJson(const evaluation::IncrementalResult& r,
                     const evaluation::ThesisProtocolScore& t) {
  json j = scoreJson(r.final_score);
  j["thesis_protocol"] = thesisJson(t);
  j["updates"] = r.update_ms.size();
  j["update_ms"] = r.update_ms;
  j["median_ms"] = percentile(r.update_ms, 50);
  j["p95_ms"] = percentile(r.update_ms, 95);
  j["max_ms"] = percentile(r.update_ms, 100);
  j["mean_ms"] = meanStd(r.update_ms).mean;
  j["coverage"] = r.coverage;
  j["path_length_m"] = r.path_length_m;
  return j;
}

/// Means and population stds of one variant's maps (and of their incremental runs).
json summaryJson(const std::vector<MapResult>& all, const std::string& variant) {
  std::map<std::string, std::vector<double>> v, inc;
  std::vector<double> updates;
  for (const auto& m : all) {
    if (m.variant != variant) continue;
    v["precision"].push_back(m.score.precision);
    v["recall"].push_back(m.score.recall);
    v["precision_pooled"].push_back(m.score.precision_pooled);
    v["recall_pooled"].push_back(m.score.recall_pooled);
    v["mcc"].push_back(m.score.mcc);
    v["segments"].push_back(m.score.segments);
    v["time_ms"].push_back(m.time_ms);
    v["thesis_precision"].push_back(m.thesis.precision);
    v["thesis_recall"].push_back(m.thesis.recall);
    if (m.has_reference) {
      v["reference_iou"].push_back(m.agreement.iou_reference);
      v["reference_iou_segments"].push_back(m.agreement.iou_segmentation);
      v["reference_ari"].push_back(m.agreement.ari);
      v["reference_precision"].push_back(m.reference_score.precision);
      v["reference_recall"].push_back(m.reference_score.recall);
      v["reference_thesis_precision"].push_back(m.reference_thesis.precision);
      v["reference_thesis_recall"].push_back(m.reference_thesis.recall);
    }
    if (!m.incremental) continue;
    if (m.has_inc_reference) {
      inc["reference_iou"].push_back(m.inc_agreement.iou_reference);
      inc["reference_ari"].push_back(m.inc_agreement.ari);
    }
    inc["thesis_precision"].push_back(m.inc_thesis.precision);
    inc["thesis_recall"].push_back(m.inc_thesis.recall);
    inc["precision"].push_back(m.inc.final_score.precision);
    inc["recall"].push_back(m.inc.final_score.recall);
    inc["precision_pooled"].push_back(m.inc.final_score.precision_pooled);
    inc["recall_pooled"].push_back(m.inc.final_score.recall_pooled);
    inc["mcc"].push_back(m.inc.final_score.mcc);
    inc["coverage"].push_back(m.inc.coverage);
    // The thesis reports each map's mean time per update (Fig. 4.2).
    inc["map_mean_ms"].push_back(meanStd(m.inc.update_ms).mean);
    updates.insert(updates.end(), m.inc.update_ms.begin(), m.inc.update_ms.end());
  }
  json j;
  j["maps"] = v["precision"].size();
  for (const auto& [k, vals] : v) {
    const MeanStd ms = meanStd(vals);
    j[k + "_mean"] = ms.mean;
    j[k + "_std"] = ms.std;
  }
  if (!v["reference_iou"].empty()) {
    j["reference_maps"] = v["reference_iou"].size();
    j["reference_iou_min"] = *std::min_element(v["reference_iou"].begin(), v["reference_iou"].end());
  }
  if (!inc.empty()) {
    json i;
    i["maps"] = inc["precision"].size();
    // Update times pooled over every update of every map.
    i["updates"] = updates.size();
    i["median_ms"] = percentile(updates, 50);
    i["p95_ms"] = percentile(updates, 95);
    i["max_ms"] = percentile(updates, 100);
    i["mean_ms"] = meanStd(updates).mean;
    for (const auto& [k, vals] : inc) {
      const MeanStd ms = meanStd(vals);
      i[k + "_mean"] = ms.mean;
      i[k + "_std"] = ms.std;
    }
    j["incremental"] = i;
  }
  return j;
}

}  // namespace

std::string benchmarkReportJson(const std::vector<MapResult>& all, const std::string& segmenter,
                                const Params& params, const std::string& exploration,
                                const std::string& error) {
  json j;
  j["segmenter"] = segmenter;
  if (!exploration.empty()) j["exploration"] = exploration;
  json keys = json::object();
  for (const auto& [k, v] : params.values()) keys[k] = v.text;
  j["params"] = keys;
  j["maps"] = json::array();
  for (const auto& m : all) {
    json e = scoreJson(m.score);
    e["name"] = m.name;
    e["variant"] = m.variant;
    e["time_ms"] = m.time_ms;
    e["thesis_protocol"] = thesisJson(m.thesis);
    if (m.incremental) e["incremental"] = incrementalJson(m.inc, m.inc_thesis);
    if (m.has_reference) {
      json r = agreementJson(m.agreement);
      r["score"] = scoreJson(m.reference_score);
      r["thesis_protocol"] = thesisJson(m.reference_thesis);
      e["reference"] = r;
    }
    if (m.has_inc_reference) e["incremental"]["reference"] = agreementJson(m.inc_agreement);
    j["maps"].push_back(e);
  }
  json summary;
  for (const char* v : {"plain", "furnished"})
    if (std::any_of(all.begin(), all.end(), [&](const MapResult& m) { return m.variant == v; }))
      summary[v] = summaryJson(all, v);
  j["summary"] = summary;
  j["complete"] = error.empty();
  if (!error.empty()) j["error"] = error;
  return j.dump(2) + "\n";
}

std::string benchmarkReportText(const std::vector<MapResult>& all) {
  std::ostringstream out;
  out << std::left << std::setw(20) << "map" << std::setw(11) << "variant" << std::right
      << std::setw(7) << "prec" << std::setw(7) << "rec" << std::setw(8) << "prec_p" << std::setw(8)
      << "rec_p" << std::setw(7) << "mcc" << std::setw(6) << "segs" << std::setw(6) << "rooms"
      << std::setw(10) << "time_ms"
      << "\n";
  for (const auto& m : all) {
    out << std::left << std::setw(20) << m.name << std::setw(11) << m.variant << std::right
        << std::setw(7) << formatFixed(m.score.precision, 3) << std::setw(7)
        << formatFixed(m.score.recall, 3) << std::setw(8)
        << formatFixed(m.score.precision_pooled, 3) << std::setw(8)
        << formatFixed(m.score.recall_pooled, 3) << std::setw(7) << formatFixed(m.score.mcc, 3)
        << std::setw(6) << m.score.segments << std::setw(6) << m.score.rooms << std::setw(10)
        << formatFixed(m.time_ms, 1) << "\n";
    if (m.incremental)
      out << "  incremental: " << m.inc.update_ms.size() << " updates, median "
          << formatFixed(percentile(m.inc.update_ms, 50), 1) << " ms, p95 "
          << formatFixed(percentile(m.inc.update_ms, 95), 1) << " ms, max "
          << formatFixed(percentile(m.inc.update_ms, 100), 1) << " ms; final precision "
          << formatFixed(m.inc.final_score.precision, 3) << ", recall "
          << formatFixed(m.inc.final_score.recall, 3) << ", coverage "
          << formatFixed(m.inc.coverage, 3) << "\n";
    if (m.has_reference)
      out << "  against the reference: IoU " << formatFixed(m.agreement.iou_reference, 3)
          << " (its regions), " << formatFixed(m.agreement.iou_segmentation, 3)
          << " (these segments), ARI " << formatFixed(m.agreement.ari, 3) << "; "
          << m.agreement.reference_regions << " reference regions, scored: precision "
          << formatFixed(m.reference_score.precision, 3) << ", recall "
          << formatFixed(m.reference_score.recall, 3) << "\n";
    if (m.has_inc_reference)
      out << "  incremental against the reference's: IoU "
          << formatFixed(m.inc_agreement.iou_reference, 3) << ", ARI "
          << formatFixed(m.inc_agreement.ari, 3) << "\n";
  }
  for (const char* v : {"plain", "furnished"}) {
    const json s = summaryJson(all, v);
    if (s["maps"].get<std::size_t>() == 0) continue;
    auto pm = [&](const std::string& k, int digits = 3) {
      return formatFixed(s[k + "_mean"].get<double>(), digits) + " +- " +
             formatFixed(s[k + "_std"].get<double>(), digits);
    };
    out << "summary " << v << " (" << s["maps"] << " maps): precision " << pm("precision")
        << ", recall " << pm("recall") << ", precision_pooled " << pm("precision_pooled")
        << ", recall_pooled " << pm("recall_pooled") << ", mcc " << pm("mcc") << ", segments "
        << pm("segments", 1) << ", time_ms " << pm("time_ms", 1) << "\n";
    out << "summary " << v << " thesis protocol: precision (per room) " << pm("thesis_precision")
        << ", recall (per segment) " << pm("thesis_recall");
    if (s.contains("incremental"))
      out << "; incremental final: precision "
          << formatFixed(s["incremental"]["thesis_precision_mean"].get<double>(), 3) << " +- "
          << formatFixed(s["incremental"]["thesis_precision_std"].get<double>(), 3) << ", recall "
          << formatFixed(s["incremental"]["thesis_recall_mean"].get<double>(), 3) << " +- "
          << formatFixed(s["incremental"]["thesis_recall_std"].get<double>(), 3);
    out << "\n";
    if (s.contains("reference_maps"))
      out << "summary " << v << " against the reference (" << s["reference_maps"]
          << " maps): IoU " << pm("reference_iou") << " (min "
          << formatFixed(s["reference_iou_min"].get<double>(), 3) << "), from the segments' side "
          << pm("reference_iou_segments") << ", ARI " << pm("reference_ari")
          << "; the reference scored: precision " << pm("reference_precision") << ", recall "
          << pm("reference_recall") << ", thesis protocol precision (per room) "
          << pm("reference_thesis_precision") << ", recall (per segment) "
          << pm("reference_thesis_recall") << "\n";
    if (s.contains("incremental") && s["incremental"].contains("reference_iou_mean"))
      out << "summary " << v << " incremental against the reference's: IoU "
          << formatFixed(s["incremental"]["reference_iou_mean"].get<double>(), 3) << " +- "
          << formatFixed(s["incremental"]["reference_iou_std"].get<double>(), 3) << ", ARI "
          << formatFixed(s["incremental"]["reference_ari_mean"].get<double>(), 3) << " +- "
          << formatFixed(s["incremental"]["reference_ari_std"].get<double>(), 3) << "\n";
    if (s.contains("incremental")) {
      const json& i = s["incremental"];
      auto ipm = [&](const std::string& k) {
        return formatFixed(i[k + "_mean"].get<double>(), 3) + " +- " +
               formatFixed(i[k + "_std"].get<double>(), 3);
      };
      out << "summary " << v << " incremental (" << i["maps"] << " maps, " << i["updates"]
          << " updates): median " << formatFixed(i["median_ms"].get<double>(), 1) << " ms, p95 "
          << formatFixed(i["p95_ms"].get<double>(), 1) << " ms, max "
          << formatFixed(i["max_ms"].get<double>(), 1) << " ms; final precision "
          << ipm("precision") << ", recall " << ipm("recall") << ", coverage " << ipm("coverage")
          << "; per-map mean update " << ipm("map_mean_ms") << " ms\n";
    }
  }
  return out.str();
}

}  // namespace asf::studies
