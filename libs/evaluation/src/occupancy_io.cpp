#include <asf/errors.h>
#include <asf/occupancy_io.h>
#include <asf/segmentation_eval.h>
#include <asf/text.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

namespace asf {

namespace {

constexpr double kMaxOrigin = 1e5;  ///< [m]: float spacing there is 8 mm

double number(const std::string& v, const std::string& where) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || trim(v.substr(used)) != "" || !std::isfinite(x))
    throw InputError(where + ": '" + v + "' is not a finite number");
  return x;
}

}  // namespace

void writeOccupancyMap(const GridMap& map, const std::string& stem) {
  if (!map.grid) return;
  const GrayImage img = imageFromGrid(map);
  writeGrayImage(stem + ".png", img);
  std::ostringstream os;
  // free_thresh 0.35: free is p(free) > 0.65, as asf's own consumers read the grid (the
  // GVG's voronoi_free_threshold); map_server's usual 0.196 would call a cell seen free once
  // unknown.
  os << std::setprecision(17) << "# map_server occupancy map written by asf: free 255, "
     << "occupied 0, unknown 128\nimage: " << std::filesystem::path(stem).filename().string()
     << ".png\nresolution: " << map.grid->getResolution() << "\norigin: [" << map.grid->getXMin()
     << ", " << map.grid->getYMin()
     << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.35\n";
  std::ofstream f(stem + ".yaml");
  f << os.str();
  if (!f) throw Error(stem + ".yaml: cannot write");
}

OccupancyMapInfo readOccupancyYaml(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open");
  OccupancyMapInfo m;
  std::set<std::string> seen;
  std::string line;
  for (int no = 1; std::getline(f, line); ++no) {
    if (line.find('\0') != std::string::npos)
      throw InputError(path + ":" + std::to_string(no) + ": NUL byte");
    const std::string t = trim(line.substr(0, line.find('#')));
    if (t.empty()) continue;
    const std::string where = path + ":" + std::to_string(no);
    const auto colon = t.find(':');
    if (colon == std::string::npos) throw InputError(where + ": expected 'key: value'");
    const std::string key = trim(t.substr(0, colon)), v = trim(t.substr(colon + 1));
    if (!seen.insert(key).second) throw InputError(where + ": '" + key + "' given twice");
    if (key == "image") {
      m.image =
          v.size() >= 2 && (v.front() == '"' || v.front() == '\'') ? v.substr(1, v.size() - 2) : v;
      if (m.image.empty()) throw InputError(where + ": empty image");
    } else if (key == "resolution") {
      m.resolution = number(v, where);
      if (!(m.resolution > 0)) throw InputError(where + ": resolution must be > 0");
    } else if (key == "origin") {
      if (v.size() < 2 || v.front() != '[' || v.back() != ']')
        throw InputError(where + ": origin must be [x, y, yaw]");
      std::istringstream is(v.substr(1, v.size() - 2));
      std::string part;
      double xyz[3];
      int k = 0;
      while (std::getline(is, part, ',')) {
        if (k == 3) throw InputError(where + ": origin must have three numbers");
        xyz[k++] = number(trim(part), where);
      }
      if (k != 3) throw InputError(where + ": origin must have three numbers");
      m.origin_x = xyz[0];
      m.origin_y = xyz[1];
      m.origin_yaw = xyz[2];
      if (!(std::abs(m.origin_x) <= kMaxOrigin && std::abs(m.origin_y) <= kMaxOrigin))
        throw InputError(where +
                         ": origin more than 100 km from 0 (MRPT's grids keep "
                         "coordinates as float: cells there would not be told apart)");
      if (m.origin_yaw != 0)
        throw InputError(where + ": a rotated map (origin yaw " + trim(part) +
                         ") is not supported");
    } else if (key == "negate") {
      if (v != "0" && v != "1") throw InputError(where + ": negate must be 0 or 1");
      m.negate = v == "1";
    } else if (key == "occupied_thresh" || key == "free_thresh") {
      const double x = number(v, where);
      if (x < 0 || x > 1) throw InputError(where + ": " + key + " must be in [0, 1]");
      (key == "free_thresh" ? m.free_thresh : m.occupied_thresh) = x;
    } else if (key == "mode") {
      if (v != "trinary") throw InputError(where + ": mode '" + v + "': only trinary is read");
    } else {
      throw InputError(where + ": unknown key '" + key +
                       "' (keys: image, resolution, origin, negate, occupied_thresh, "
                       "free_thresh, mode)");
    }
  }
  for (const char* k : {"image", "resolution", "origin"})
    if (!seen.count(k)) throw InputError(path + ": no '" + std::string(k) + "'");
  if (m.free_thresh > m.occupied_thresh)
    throw InputError(path + ": free_thresh above occupied_thresh");
  return m;
}

GridMap readOccupancyMap(const std::string& yaml_path) {
  const OccupancyMapInfo m = readOccupancyYaml(yaml_path);
  const std::filesystem::path img =
      std::filesystem::path(yaml_path).parent_path() / std::filesystem::path(m.image);
  GrayImage g = readGrayImage(img.string());
  if (m.negate)
    for (auto& p : g.pixels) p = static_cast<std::uint8_t>(255 - p);
  // Free: occupancy (255 - p) / 255 below free_thresh, i.e. p > 255 (1 - free_thresh).
  const int free_from = static_cast<int>(std::floor(255.0 * (1.0 - m.free_thresh))) + 1;
  try {
    return gridFromImage(g, m.resolution, free_from, m.origin_x, m.origin_y);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(yaml_path + ": " + e.what());
  }
}

}  // namespace asf
