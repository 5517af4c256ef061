#pragma once
/// \file segment_benchmark.h
/// The protocol of `asf segment-eval` as a library: a segmenter scored on the room
/// segmentation benchmark (Bormann et al., ICRA 2016) as ../shared/docs/roomseg-eval.md
/// describes, per map and variant (plain, furnished), optionally also incrementally while the
/// map is revealed (a simulated laser, or the thesis' raster of disks).
#include <asf/framework/registry.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/segmenter.h>

#include <functional>
#include <string>
#include <vector>

namespace asf::studies {

struct SegmentBenchmarkOptions {
  std::string plain_dir, gt_dir;  ///< <name>.png; <name>_gt_segmentation.png
  std::string furnished_dir;      ///< <name>_furnitures.png; empty: plain maps only
  std::string images_dir;         ///< overlays and label images; empty: none
  /// The reference DuDe's own outputs (one colour per region): <name>_DuDe.png and
  /// <name>_DuDe_furnitures.png, incrementally <name>_Inc.png and <name>_Inc_furnitures.png;
  /// each segmentation is compared with its counterpart region by region. Empty: none.
  std::string reference_dir;
  double resolution = 0.05;       ///< metres per pixel
  bool incremental = false;
  std::string exploration = "frontier";  ///< frontier | raster_disks
  std::string incremental_on = "plain";  ///< plain | furnished | both
  evaluation::ExplorationOptions explore;            ///< exploration = frontier
};

/// One map variant's scores.
struct BenchmarkMapResult {
  std::string name, variant;
  evaluation::SegmentationScore score;
  evaluation::ThesisProtocolScore thesis;  ///< the thesis' own scoring (Table 4.1)
  double time_ms = 0;
  bool incremental = false;
  evaluation::IncrementalResult inc;  ///< update_ms and final_score when `incremental`
  evaluation::ThesisProtocolScore inc_thesis;
  /// With a reference: the agreement with its output, and its output scored as asf's is.
  bool has_reference = false;
  evaluation::SegmentationAgreement agreement;
  evaluation::SegmentationScore reference_score;
  evaluation::ThesisProtocolScore reference_thesis;
  bool has_inc_reference = false;  ///< incremental and a reference: the final segmentation's
  evaluation::SegmentationAgreement inc_agreement;
};

/// The plain maps' names, sorted, or `only` (each checked to exist). Throws InputError for a
/// missing folder or map, or no map at all.
std::vector<std::string> benchmarkMapNames(const SegmentBenchmarkOptions& o,
                                           const std::vector<std::string>& only);

/// A fresh, configured segmenter (segmenters keep id state between calls).
using SegmenterFactory = std::function<framework::PluginHandle<Segmenter>()>;
/// Receives the progress lines of a benchmark (one per variant, incremental every 5 s).
using ProgressSink = std::function<void(const std::string&)>;

/// Scores map `name` (plain, then furnished when configured), appending one result per
/// variant and calling `scored` after each. `current` names the map and variant being
/// scored, for an error's message. Throws InputError for unreadable or inconsistent files.
void scoreBenchmarkMap(const std::string& name, const std::string& prefix,
                       const SegmentBenchmarkOptions& o, const SegmenterFactory& segmenter,
                       const ProgressSink& progress, std::vector<BenchmarkMapResult>& results,
                       std::string& current, const std::function<void()>& scored);

/// The JSON report of `asf segment-eval --json` (indented, newline-terminated): the segmenter
/// and its parameters, each map's scores (and its incremental run), and per variant the means
/// and population standard deviations; "complete" false and "error" when `error` is set.
std::string benchmarkReportJson(const std::vector<BenchmarkMapResult>& all,
                                const std::string& segmenter, const Params& params,
                                const std::string& exploration, const std::string& error);

/// The same as `asf segment-eval` prints it: a table of the maps, then the summary lines.
std::string benchmarkReportText(const std::vector<BenchmarkMapResult>& all);

/// A segmentation as an image raster; checks the segmenter's contract on the size (`who`
/// names the map in the error).
io::LabelRaster segmentationRaster(const Segmentation& seg, const io::GrayImage& image,
                               const std::string& who);

}  // namespace asf::studies
