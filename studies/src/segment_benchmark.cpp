#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/studies/segment_benchmark.h>
#include <asf/text.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <memory>

namespace asf::studies {

namespace fs = std::filesystem;

namespace {

/// What one map's scoring shares between its variants.
struct MapContext {
  const std::string& name;
  const std::string& prefix;
  const SegmentBenchmarkOptions& o;
  const SegmenterFactory& segmenter;
  const ProgressSink& progress;
  std::string gt_file;
  io::GrayImage gt_image;
  io::LabelRaster rooms;

  std::string imagePath(const std::string& what) const {
    return (fs::path(o.images_dir) / (name + "_" + what + ".png")).string();
  }
};

/// The reference output `stem`.png (e.g. lab_a_DuDe) as regions, checked against the map's size.
io::LabelRaster referenceRegions(const MapContext& m, const std::string& stem,
                                 const io::GrayImage& image) {
  const std::string file = (fs::path(m.o.reference_dir) / (stem + ".png")).string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw InputError(file + ": no such file (--reference " + m.o.reference_dir + ")");
  io::LabelRaster r = io::readColourRegions(file);
  if (r.width != image.width || r.height != image.height)
    throw InputError(file + ": " + std::to_string(r.width) + " x " + std::to_string(r.height) +
                     " px, but the map is " + std::to_string(image.width) + " x " +
                     std::to_string(image.height));
  return r;
}

std::string referenceStem(const std::string& name, const std::string& variant, bool incremental) {
  return name + (incremental ? "_Inc" : "_DuDe") + (variant == "plain" ? "" : "_furnitures");
}

/// Reveals the map step by step, segmenting after every update (`r.inc`, `r.inc_thesis`).
void scoreIncremental(const MapContext& m, const std::string& variant, const io::GrayImage& image,
                      const std::string& file, BenchmarkMapResult& r) {
  auto inc_seg = m.segmenter();
  auto last_report = std::chrono::steady_clock::now();
  std::unique_ptr<evaluation::MapReveal> reveal;
  if (m.o.exploration == "raster_disks")
    reveal = std::make_unique<evaluation::RasterDiskReveal>(image, m.o.resolution);
  else
    reveal = std::make_unique<evaluation::ExplorationSimulator>(image, m.o.resolution, m.o.explore);
  r.inc = evaluation::evaluateIncremental(
      *inc_seg, *reveal, m.rooms, [&](std::size_t updates, double coverage) {
        if (msSince(last_report) < 5000) return;  // a line every 5 s of work
        last_report = std::chrono::steady_clock::now();
        m.progress(m.prefix + " " + variant + " incremental: " + std::to_string(updates) +
                   " updates, " + formatFixed(100 * coverage, 0) + "% explored");
      });
  r.incremental = true;
  const io::LabelRaster final_labels = segmentationRaster(r.inc.final_segmentation, image, file);
  r.inc_thesis = evaluation::scoreThesisProtocol(final_labels, m.gt_image);
  if (!m.o.reference_dir.empty()) {
    r.inc_agreement = evaluation::compareSegmentations(
        final_labels, referenceRegions(m, referenceStem(m.name, variant, true), image));
    r.has_inc_reference = true;
  }
  if (!m.o.images_dir.empty())
    evaluation::writeSegmentationOverlay(
        m.imagePath(variant == "plain" ? "incremental" : variant + "_incremental"), r.inc.final_map,
        r.inc.final_segmentation, nullptr, &m.rooms);
  m.progress(m.prefix + " " + variant + " incremental: " + std::to_string(r.inc.update_ms.size()) +
             " updates, mean " + formatFixed(meanStd(r.inc.update_ms).mean, 1) + " ms, median " +
             formatFixed(percentile(r.inc.update_ms, 50), 1) + " ms, p95 " +
             formatFixed(percentile(r.inc.update_ms, 95), 1) + " ms; final precision " +
             formatFixed(r.inc.final_score.precision, 3) + ", recall " +
             formatFixed(r.inc.final_score.recall, 3) + ", " +
             formatFixed(100 * r.inc.coverage, 1) + "% explored");
  r.inc.final_map = GridMap();  // the report needs the numbers only
  r.inc.final_segmentation = Segmentation();
}

/// `<dir>/<stem>.yaml` (a map_server map) when there is one, else `<dir>/<stem>.png`.
std::string mapFile(const std::string& dir, const std::string& stem) {
  std::error_code ec;
  for (const char* ext : {".yaml", ".yml"}) {
    const fs::path y = fs::path(dir) / (stem + ext);
    if (fs::is_regular_file(y, ec)) return y.string();
  }
  return (fs::path(dir) / (stem + ".png")).string();
}

BenchmarkMapResult scoreVariant(const MapContext& m, const std::string& variant,
                                const std::string& file) {
  // A map_server map brings its own resolution, origin and free / occupied / unknown rules.
  const bool yaml = io::isOccupancyYaml(file);
  const io::GrayImage image =
      io::readGrayImage(yaml ? io::occupancyImagePath(file, io::readOccupancyYaml(file)) : file);
  if (image.width != m.rooms.width || image.height != m.rooms.height)
    throw InputError(file + ": " + std::to_string(image.width) + " x " +
                     std::to_string(image.height) + " px, but " + m.gt_file + " is " +
                     std::to_string(m.rooms.width) + " x " + std::to_string(m.rooms.height));
  const GridMap map = yaml ? io::readOccupancyMap(file) : io::gridFromImage(image, m.o.resolution);
  auto seg = m.segmenter();
  const auto t0 = std::chrono::steady_clock::now();
  const Segmentation s = seg->segment(map, nullptr);
  BenchmarkMapResult r;
  r.time_ms = msSince(t0);
  r.name = m.name;
  r.variant = variant;
  const io::LabelRaster labels = segmentationRaster(s, image, file);
  r.score = evaluation::scoreSegmentation(labels, m.rooms);
  r.thesis = evaluation::scoreThesisProtocol(labels, m.gt_image);
  if (!m.o.reference_dir.empty()) {
    const io::LabelRaster ref = referenceRegions(m, referenceStem(m.name, variant, false), image);
    r.agreement = evaluation::compareSegmentations(labels, ref);
    r.reference_score = evaluation::scoreSegmentation(ref, m.rooms);
    r.reference_thesis = evaluation::scoreThesisProtocol(ref, m.gt_image);
    r.has_reference = true;
  }
  if (!m.o.images_dir.empty()) {
    evaluation::writeSegmentationOverlay(m.imagePath(variant), map, s, nullptr, &m.rooms);
    io::writeLabelImage(m.imagePath(variant + "_labels"), labels);
  }
  m.progress(m.prefix + " " + variant + ": " + std::to_string(r.score.segments) + " segments / " +
             std::to_string(r.score.rooms) + " rooms, precision " +
             formatFixed(r.score.precision, 3) + ", recall " + formatFixed(r.score.recall, 3) +
             ", mcc " + formatFixed(r.score.mcc, 3) + " (" + formatFixed(r.time_ms, 1) + " ms)" +
             (r.has_reference ? "; against the reference: IoU " +
                                    formatFixed(r.agreement.iou_reference, 3) + ", ARI " +
                                    formatFixed(r.agreement.ari, 3)
                              : ""));
  const std::string& on = m.o.incremental_on;
  if (m.o.incremental && (on == "both" || on == variant))
    scoreIncremental(m, variant, image, file, r);
  return r;
}

}  // namespace

std::vector<std::string> benchmarkMapNames(const SegmentBenchmarkOptions& o,
                                           const std::vector<std::string>& only) {
  std::error_code ec;
  if (!fs::is_directory(o.plain_dir, ec))
    throw InputError(o.plain_dir + ": no such folder (--plain)");
  if (!fs::is_directory(o.gt_dir, ec)) throw InputError(o.gt_dir + ": no such folder (--gt)");
  if (!o.furnished_dir.empty() && !fs::is_directory(o.furnished_dir, ec))
    throw InputError(o.furnished_dir + ": no such folder (--furnished)");
  if (!o.reference_dir.empty() && !fs::is_directory(o.reference_dir, ec))
    throw InputError(o.reference_dir + ": no such folder (--reference)");
  // A YAML's image is not a map of its own (unless a YAML of that name exists too).
  std::vector<std::string> names, yaml_stems, images;
  for (const auto& e : fs::directory_iterator(o.plain_dir)) {
    const std::string ext = lowercase(e.path().extension().string());
    if (!e.is_regular_file() || (ext != ".png" && ext != ".yaml" && ext != ".yml")) continue;
    names.push_back(e.path().stem().string());
    if (ext == ".png") continue;
    yaml_stems.push_back(names.back());
    const std::string y = e.path().string();
    images.push_back(
        fs::path(io::occupancyImagePath(y, io::readOccupancyYaml(y))).lexically_normal());
  }
  const auto contains = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  names.erase(std::remove_if(names.begin(), names.end(),
                             [&](const std::string& n) {
                               const fs::path png = fs::path(o.plain_dir) / (n + ".png");
                               return !contains(yaml_stems, n) &&
                                      contains(images, png.lexically_normal().string());
                             }),
              names.end());
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  if (!only.empty()) {
    for (const auto& m : only)
      if (std::find(names.begin(), names.end(), m) == names.end())
        throw InputError(o.plain_dir + ": no map " + m + ".png or " + m + ".yaml (--map)");
    names = only;
  }
  if (names.empty()) throw InputError(o.plain_dir + ": no .png or map_server .yaml maps");
  return names;
}

void scoreBenchmarkMap(const std::string& name, const std::string& prefix,
                       const SegmentBenchmarkOptions& o, const SegmenterFactory& segmenter,
                       const ProgressSink& progress, std::vector<BenchmarkMapResult>& results,
                       std::string& current, const std::function<void()>& scored) {
  MapContext m{name, prefix, o, segmenter, progress, {}, {}, {}};
  m.gt_file = (fs::path(o.gt_dir) / (name + "_gt_segmentation.png")).string();
  current = name + " (ground truth)";
  m.gt_image = io::readGrayImage(m.gt_file);
  m.rooms = evaluation::groundTruthRooms(m.gt_image);
  if (std::none_of(m.rooms.labels.begin(), m.rooms.labels.end(),
                   [](std::int32_t l) { return l > 0; }))
    throw InputError(m.gt_file +
                     ": no ground-truth room (no 8-connected component of pixels "
                     "> 250 with more than 100 pixels)");
  current = name + " (plain)";
  results.push_back(scoreVariant(m, "plain", mapFile(o.plain_dir, name)));
  scored();
  if (o.furnished_dir.empty()) return;
  current = name + " (furnished)";
  results.push_back(scoreVariant(m, "furnished", mapFile(o.furnished_dir, name + "_furnitures")));
  scored();
}

io::LabelRaster segmentationRaster(const Segmentation& seg, const io::GrayImage& image,
                               const std::string& who) {
  io::LabelRaster r = evaluation::toRaster(seg.labels);
  if (r.labels.empty() && seg.regions.empty()) {  // no region at all: an empty image
    r.width = image.width;
    r.height = image.height;
    r.labels.assign(static_cast<std::size_t>(image.width) * image.height, 0);
  }
  if (r.width != image.width || r.height != image.height)
    throw Error(who + ": the segmenter returned a " + std::to_string(r.width) + " x " +
                std::to_string(r.height) + " label image for a " + std::to_string(image.width) +
                " x " + std::to_string(image.height) + " map");
  return r;
}

}  // namespace asf::studies
