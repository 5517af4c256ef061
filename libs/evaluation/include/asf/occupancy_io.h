#pragma once
/// \file occupancy_io.h
/// The occupancy grid as an image plus a ROS map_server YAML file (resolution, origin,
/// thresholds): what `asf run` writes (occupancy.png + occupancy.yaml) and what `asf plan
/// --map` and other tools read back with the map's frame intact.
///
/// Image convention (map_server, negate = 0): row 0 is the top (largest y); a pixel p means
/// an occupancy probability (255 - p) / 255: free below free_thresh, occupied above
/// occupied_thresh, unknown between. asf writes round(255 p(free)): free 255, occupied 0,
/// unknown 128, with free_thresh 0.35 (free is p(free) > 0.65, as asf's own consumers read
/// the grid). origin is the map-frame pose of the lower-left pixel's corner.
#include <asf/grid_map.h>

#include <string>

namespace asf {

struct OccupancyMapInfo {
  std::string image;  ///< as written in the YAML (relative to the YAML's folder)
  double resolution = 0.05;
  double origin_x = 0, origin_y = 0, origin_yaw = 0;
  bool negate = false;
  double occupied_thresh = 0.65, free_thresh = 0.196;
};

/// Writes `<stem>.png` and `<stem>.yaml` (stem: a path without extension). Throws asf::Error
/// naming the file. Nothing is written for a map without a grid.
void writeOccupancyMap(const GridMap& map, const std::string& stem);

/// Reads a map_server YAML file (image, resolution, origin; negate, occupied_thresh,
/// free_thresh optional; mode: trinary or absent). Throws asf::InputError naming the file and
/// line: unknown or repeated keys, a missing image/resolution/origin, non-numeric values, a
/// non-zero origin yaw (a rotated map is not supported), thresholds outside [0, 1].
OccupancyMapInfo readOccupancyYaml(const std::string& path);

/// The YAML's map as a GridMap in its frame: free cells (occupancy below free_thresh) p(free)
/// = 1, the rest 0 (unknown is not free space). Throws InputError naming the YAML or image.
GridMap readOccupancyMap(const std::string& yaml_path);

}  // namespace asf
