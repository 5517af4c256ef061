#pragma once
/// \file occupancy_io.h
/// The occupancy grid as a ROS map_server map: an image plus a YAML file (resolution, origin,
/// thresholds, mode), what `asf run` writes (map.pgm + map.yaml, which nav2's map_server loads
/// unchanged) and what `asf plan --map`, `asf segment`, sim2d worlds and other tools read
/// back with the map's frame intact and its unknown cells unknown.
///
/// Pixel rules (ROS map_server and nav2's map_io): row 0 is the top (largest y); with
/// negate = 0 a pixel p means an occupancy probability occ = (255 - p) / 255 (negate = 1: p /
/// 255). Modes: trinary (the default): occupied when occ > occupied_thresh, free when occ <
/// free_thresh, unknown between; scale: the same ends, and between them the occupancy scaled
/// linearly from free_thresh (0 %) to occupied_thresh (100 %); raw: the pixel value itself is
/// the occupancy in percent (0..100), above 100 unknown. asf writes round(255 p(free)): free
/// 255, occupied 0, unknown 128, with free_thresh 0.35 (free is p(free) > 0.65, as asf's own
/// consumers read the grid). origin is the map-frame pose of the lower-left pixel's corner.
#include <asf/grid_map.h>
#include <asf/io/image_io.h>

#include <cstdint>
#include <string>

namespace asf::io {

enum class MapMode { Trinary, Scale, Raw };

struct OccupancyMapInfo {
  std::string image;  ///< as written in the YAML (relative to the YAML's folder)
  double resolution = 0.05;
  double origin_x = 0, origin_y = 0, origin_yaw = 0;
  bool negate = false;
  double occupied_thresh = 0.65, free_thresh = 0.196;
  MapMode mode = MapMode::Trinary;
};

/// A pixel's occupancy by map_server's rules for `info`'s mode: -1 unknown, else 0 (free) to
/// 100 (occupied) percent.
int mapServerOccupancy(const OccupancyMapInfo& info, std::uint8_t pixel);

enum class MapCell { Free, Occupied, Unknown };

/// A pixel's class: occupied above occupied_thresh, free below free_thresh, unknown between
/// (map_server's trinary classes in every mode; raw: the pixel / 100 against the thresholds,
/// above 100 unknown).
MapCell mapServerClass(const OccupancyMapInfo& info, std::uint8_t pixel);

/// Writes `<stem>.pgm` (binary PGM) and `<stem>.yaml` (stem: a path without extension): a map
/// nav2's and ROS 1's map_server load unchanged. Throws asf::Error naming the file. Nothing is
/// written for a map without a grid.
void writeOccupancyMap(const GridMap& map, const std::string& stem);

/// Reads a map_server YAML file (image, resolution, origin; negate (0/1, true/false),
/// occupied_thresh, free_thresh and mode (trinary, scale, raw) optional). Throws
/// asf::InputError naming the file and line: unknown or repeated keys, a missing
/// image/resolution/origin, non-numeric values, a non-zero origin yaw (asf's grids are
/// axis-aligned in their frame), thresholds outside [0, 1].
OccupancyMapInfo readOccupancyYaml(const std::string& path);

/// The path of the YAML's image (relative paths against the YAML's folder).
std::string occupancyImagePath(const std::string& yaml_path, const OccupancyMapInfo& info);

/// The YAML's map as a GridMap in its frame, cell value p(free) = 1 - occupancy (free 1,
/// occupied 0), unknown cells 0.5 (asf's consumers take a cell as free above 0.65, so unknown
/// is never free space). Throws InputError naming the YAML or image.
GridMap readOccupancyMap(const std::string& yaml_path);

/// Whether `path` names a map_server YAML (.yaml or .yml) rather than an image.
bool isOccupancyYaml(const std::string& path);

/// The room segmentation benchmark's free-space threshold: pixel >= 250 is free, anything
/// else occupied (the default for reading images as maps).
constexpr int kBenchmarkFreeThreshold = 250;

/// The map as a GridMap: free pixels (>= free_threshold) p(free) = 1, the rest 0; cell
/// (cx, cy) = pixel (cx, height-1-cy), origin (0, 0) unless given. version = 1, changed = the
/// whole map, rebuilt = true (a map seen for the first time).
GridMap gridFromImage(const GrayImage& image, double resolution,
                      int free_threshold = kBenchmarkFreeThreshold, double origin_x = 0,
                      double origin_y = 0);

/// The grid as an image (row 0 = top): pixel = round(255 * p(free)), so free 255, occupied 0,
/// unknown 128. Empty for a map without grid.
GrayImage imageFromGrid(const GridMap& map);

}  // namespace asf::io
