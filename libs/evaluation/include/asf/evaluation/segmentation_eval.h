#pragma once
/// \file segmentation_eval.h
/// Room segmentation benchmark (docs: ../shared/docs/roomseg-eval.md): reading the map and
/// ground-truth images as the benchmark does, scoring a label image against the ground-truth
/// rooms (precision, recall, pooled variants, Matthews correlation), and a simulated
/// exploration that reveals a map step by step for timing incremental segmenters.
///
/// Orientation: images (GrayImage, LabelRaster, PNG files) have row 0 at the top; grids
/// (GridMap, LabelImage) have cy = 0 at the bottom (y up). Row r is cy = height - 1 - r.
#include <asf/grid_map.h>
#include <asf/io/image_io.h>
#include <asf/io/occupancy_io.h>
#include <asf/segmentation.h>
#include <asf/statistics.h>
#include <asf/topo_graph.h>
#include <asf/graph/topology_json.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace asf {
class Segmenter;
}  // namespace asf

namespace asf::evaluation {

/// Ground-truth rooms and scored segments must have more than this many pixels.
constexpr int kBenchmarkMinRegionPixels = 100;

/// Ground-truth rooms: pixels > 250, 8-connected components with more than `min_pixels`
/// pixels, numbered 1..N in row-major order of their first pixel.
io::LabelRaster groundTruthRooms(const io::GrayImage& gt,
                                 int min_pixels = kBenchmarkMinRegionPixels);

/// Grid labels (cy up) <-> image raster (row 0 top).
io::LabelRaster toRaster(const LabelImage& labels);
LabelImage fromRaster(const io::LabelRaster& raster, double resolution, double origin_x = 0,
                      double origin_y = 0);

/// Score of a segmentation against ground-truth rooms (roomseg-eval.md):
/// - only segments (labels > 0) with more than `min_pixels` pixels count;
/// - O[s][r] = pixels in segment s and room r; precision(s) = max_r O[s][r] / |s|,
///   recall(r) = max_s O[s][r] / |r|; no one-to-one assignment;
/// - precision / recall: means over segments / rooms; *_pooled: sum of best overlaps over sum
///   of sizes. Without any segment, precision = precision_pooled = 0.
/// - mcc: Matthews correlation of "same region" over unordered pixel pairs. The pixels are
///   U = those in a counted room or a counted segment; a pixel of U outside every counted
///   segment (or room) is a region of its own on that side. Pair counts: TP = pairs in the
///   same segment and the same room, FP = same segment but different rooms, FN = same room
///   but different segments, TN = the rest; mcc = (TP TN - FP FN) / sqrt((TP+FP)(TP+FN)
///   (TN+FP)(TN+FN)), and 0 when a factor is 0 (1 if FP = FN = 0 then).
struct SegmentationScore {
  double precision = 0, recall = 0;
  double precision_pooled = 0, recall_pooled = 0;
  double mcc = 0;
  int segments = 0;  ///< counted segments
  int rooms = 0;     ///< ground-truth rooms (labels > 0 of `rooms` with > min_pixels)
  std::vector<double> segment_precision;  ///< per counted segment, by increasing label
  std::vector<double> room_recall;        ///< per counted room, by increasing label
};
/// `segmentation` and `rooms` must have the same size (else Error). Rooms are labels > 0 of
/// `rooms` (groundTruthRooms' output, or any label image), filtered by `min_pixels` too.
SegmentationScore scoreSegmentation(const io::LabelRaster& segmentation,
                                    const io::LabelRaster& rooms,
                                    int min_pixels = kBenchmarkMinRegionPixels);

/// The thesis' own scoring (read from the author's evaluation code, Incremental_DuDe_ROS
/// src/evaluation.cpp), which Table 4.1 and Fig. 4.1 report; it differs from roomseg-eval.md:
/// - rooms: pixels of the ground truth > 250, eroded once (3 x 3), 8-connected components of
///   any size, the labels dilated once (3 x 3; where two rooms meet the larger label wins);
/// - only pixels that have both a room and a segment label count (unlabelled pixels are
///   ignored), and no region is filtered by size;
/// - the thesis' "precision" is, per room, the best overlap over the room's counted pixels
///   (Bormann's recall), its "recall" is, per segment, the best overlap over the segment's
///   counted pixels (Bormann's precision); both are means over the map's rooms / segments of
///   per-region values truncated to whole percent (the author's code divides integers).
/// Field names follow the thesis.
struct ThesisProtocolScore {
  double precision = 0;         ///< mean over rooms of best overlap / counted room pixels
  double recall = 0;            ///< mean over segments of best overlap / counted segment pixels
  int rooms = 0, segments = 0;  ///< with at least one counted pixel
};
/// `segmentation` (image orientation) and `gt` must have the same size (else Error).
ThesisProtocolScore scoreThesisProtocol(const io::LabelRaster& segmentation,
                                        const io::GrayImage& gt);

/// How closely a segmentation reproduces another one region by region (asf's against the
/// reference implementation's own outputs, issue 48). Regions are labels > 0 with more than
/// `min_pixels` pixels on either side; IoU(A, B) = |A and B| / |A or B| over whole regions.
/// - iou_reference: each reference region's best IoU with a segment, averaged weighted by the
///   reference region's size (a region cut in two halves, or merged with an equal neighbour,
///   counts 0.5: both over- and under-segmentation lower it);
/// - iou_segmentation: the same from the segments' side;
/// - ari: the adjusted Rand index (Hubert and Arabie 1985) of the two partitions of the pixels
///   in a counted region on both sides; 1 for the same partition, about 0 for unrelated ones.
struct SegmentationAgreement {
  double iou_reference = 0, iou_segmentation = 0, ari = 0;
  int segments = 0, reference_regions = 0;  ///< counted regions
  std::size_t pixels_compared = 0;          ///< pixels in a counted region on both sides
};
/// `segmentation` and `reference` must have the same size (else Error).
SegmentationAgreement compareSegmentations(const io::LabelRaster& segmentation,
                                           const io::LabelRaster& reference,
                                           int min_pixels = kBenchmarkMinRegionPixels);

/// Writes a PNG of the map with the regions coloured, their ids at their centroids, the
/// topological graph's edges (if `topo`) and the outlines of ground-truth rooms (if `rooms`,
/// image orientation, same size as the map).
void writeSegmentationOverlay(const std::string& path, const GridMap& map, const Segmentation& seg,
                              const TopoGraph* topo, const io::LabelRaster* rooms = nullptr);

/// A known map revealed step by step, for timing incremental segmentation
/// (evaluateIncremental). Deterministic.
class MapReveal {
 public:
  virtual ~MapReveal() = default;
  /// Publishes the next map and returns true, or returns false (map unchanged) at the end.
  /// Every published map: unknown cells 0.5, revealed ones 1 (free) / 0 (occupied), version
  /// + 1, `changed` covering every cell revealed by this step, rebuilt = false.
  virtual bool step() = 0;
  virtual const GridMap& map() const = 0;
  /// Revealed free pixels / free pixels this protocol can reveal.
  virtual double coverage() const = 0;
  /// Metres travelled (0 when the protocol has no robot).
  virtual double pathLength() const { return 0; }
};

/// Simulated exploration of a known map with perfect localization: a point robot with a
/// 360-degree range sensor goes to the nearest frontier (a revealed free cell with an unknown
/// 4-neighbour; BFS over the free cells revealed so far, 8-connected without cutting corners),
/// choosing a new one when it reached its goal or the goal stopped being a frontier, and
/// scans every `scan_spacing` of travel (counted in BFS steps of one cell) by ray casting on
/// the true map. Deterministic.
struct ExplorationOptions {
  double sensor_range = 5.0;       ///< m
  double scan_spacing = 0.5;       ///< m of travel between scans
  int rays = 720;                  ///< per scan, evenly spaced over 360 degrees
  std::size_t max_scans = 200000;  ///< safety stop
};

class ExplorationSimulator final : public MapReveal {
 public:
  /// `image` is the true map (free = pixel >= free_threshold). The start is the free pixel
  /// farthest from any obstacle (first in row-major order on ties) in the largest
  /// 4-connected free component: rays and the robot cannot pass between two obstacle pixels
  /// that touch at a corner, so free pixels linked only diagonally stay unknown. Throws Error
  /// when the map has no free pixel.
  ExplorationSimulator(const io::GrayImage& image, double resolution,
                       const ExplorationOptions& options = {},
                       int free_threshold = io::kBenchmarkFreeThreshold);
  ~ExplorationSimulator();
  ExplorationSimulator(const ExplorationSimulator&) = delete;
  ExplorationSimulator& operator=(const ExplorationSimulator&) = delete;

  /// The first call scans at the start; later calls move towards the nearest frontier and
  /// scan. Returns false (map unchanged) when no reachable frontier is left or max_scans is
  /// reached. Every scan that returns true publishes a new GridMap: unknown cells 0.5,
  /// revealed ones 1 (free) / 0 (occupied), version + 1, `changed` = box of the cells revealed
  /// by this scan, rebuilt = false.
  bool step() override;
  const GridMap& map() const override;
  Point2 robot() const;                ///< map frame, centre of the robot's cell
  double pathLength() const override;  ///< m travelled so far
  std::size_t scans() const;
  /// Revealed free pixels / free pixels of the start's 4-connected free component.
  double coverage() const override;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// The incremental protocol of the thesis' evaluation (the author's Incremental_DuDe_ROS,
/// src/evaluation.cpp, read, not copied): disks of `radius_px` pixels are revealed, whatever
/// walls lie between, at centres stepping `step_px` along rows: centre k = ((step_px * k) mod
/// width, step_px * floor(step_px * k / width)); the last centre is the first one below the
/// image. After a disk, a map is published (and segmented) once more than `min_free_px` free
/// pixels are revealed in all, also when the disk revealed nothing new. At 0.05 m per pixel
/// the defaults are a 5 m disk every 2.5 m.
struct RasterDiskOptions {
  int radius_px = 100;
  int step_px = 50;
  std::size_t min_free_px = 160;
};

class RasterDiskReveal final : public MapReveal {
 public:
  /// `image` is the true map (free = pixel >= free_threshold, as everywhere in asf's
  /// benchmark; the author's code takes > 250). Throws Error when an option is out of range
  /// (radius < 0, step < 1) or the resolution is not > 0.
  RasterDiskReveal(const io::GrayImage& image, double resolution,
                   const RasterDiskOptions& options = {},
                   int free_threshold = io::kBenchmarkFreeThreshold);
  ~RasterDiskReveal() override;
  RasterDiskReveal(const RasterDiskReveal&) = delete;
  RasterDiskReveal& operator=(const RasterDiskReveal&) = delete;

  bool step() override;  ///< `changed`: the disk's box (clipped to the map)
  const GridMap& map() const override;
  double coverage() const override;  ///< of all free pixels of the image
  std::size_t disks() const;         ///< disks revealed so far (published or not)

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Per-update timing and final score of an incremental run (evaluateIncremental).
struct IncrementalResult {
  std::vector<double> update_ms;  ///< segment() time per scan
  SegmentationScore final_score;  ///< of the last segmentation against the rooms
  Segmentation final_segmentation;
  GridMap final_map;
  double coverage = 0, path_length_m = 0;
};

/// Calls `segmenter.segment(map, previous)` after every step of `reveal` and scores the last
/// segmentation against `rooms` (its label image must have the rooms' size). `progress` (may
/// be empty) is called after every update with the number of updates and the coverage.
IncrementalResult evaluateIncremental(
    Segmenter& segmenter, MapReveal& reveal, const io::LabelRaster& rooms,
    const std::function<void(std::size_t, double)>& progress = {});

/// The same on an ExplorationSimulator of `image`: calls segment() after
/// every scan; scores the last segmentation against `rooms`. `progress` (may be empty) is
/// called after every update with the number of updates and the coverage.
IncrementalResult evaluateIncremental(
    Segmenter& segmenter, const io::GrayImage& image, const io::LabelRaster& rooms,
    double resolution, const ExplorationOptions& options = {},
    const std::function<void(std::size_t, double)>& progress = {});

}  // namespace asf::evaluation
