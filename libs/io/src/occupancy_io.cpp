#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/io/image_io.h>
#include <asf/text.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

namespace asf::io {

namespace fs = std::filesystem;
using Grid = mrpt::maps::COccupancyGridMap2D;

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

int mapServerOccupancy(const OccupancyMapInfo& info, std::uint8_t pixel) {
  if (info.mode == MapMode::Raw) return pixel <= 100 ? pixel : -1;
  const double occ = info.negate ? pixel / 255.0 : (255 - pixel) / 255.0;
  if (occ > info.occupied_thresh) return 100;
  if (occ < info.free_thresh) return 0;
  if (info.mode == MapMode::Trinary) return -1;
  // scale: between the thresholds, linear (nav2 map_io rounds the same way)
  return static_cast<int>(
      std::lround((occ - info.free_thresh) / (info.occupied_thresh - info.free_thresh) * 100.0));
}

MapCell mapServerClass(const OccupancyMapInfo& info, std::uint8_t pixel) {
  if (info.mode == MapMode::Raw && pixel > 100) return MapCell::Unknown;
  const double occ = info.mode == MapMode::Raw ? pixel / 100.0
                     : info.negate             ? pixel / 255.0
                                               : (255 - pixel) / 255.0;
  if (occ > info.occupied_thresh) return MapCell::Occupied;
  if (occ < info.free_thresh) return MapCell::Free;
  return MapCell::Unknown;
}

bool isOccupancyYaml(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

std::string occupancyImagePath(const std::string& yaml_path, const OccupancyMapInfo& info) {
  const fs::path img(info.image);
  return img.is_absolute() ? img.string() : (fs::path(yaml_path).parent_path() / img).string();
}

void writeOccupancyMap(const GridMap& map, const std::string& stem) {
  if (!map.grid) return;
  const GrayImage img = imageFromGrid(map);
  // Binary PGM: what map_saver writes and every map_server reads. Both files are written
  // atomically (a killed run leaves the old file or the new one, never half of one).
  std::ostringstream pgm;
  pgm << "P5\n# asf occupancy map: free 255, occupied 0, unknown 128\n"
      << img.width << " " << img.height << "\n255\n";
  pgm.write(reinterpret_cast<const char*>(img.pixels.data()),
            static_cast<std::streamsize>(img.pixels.size()));
  writeFileAtomically(stem + ".pgm", pgm.str(), "occupancy map image");
  std::ostringstream os;
  // free_thresh 0.35: free is p(free) > 0.65, as asf's own consumers read the grid (the
  // GVG's voronoi_free_threshold); map_server's usual 0.196 would call a cell seen free once
  // unknown.
  os << std::setprecision(17) << "# map_server occupancy map written by asf: free 255, "
     << "occupied 0, unknown 128\nimage: " << fs::path(stem).filename().string()
     << ".pgm\nmode: trinary\nresolution: " << map.grid->getResolution() << "\norigin: ["
     << map.grid->getXMin() << ", " << map.grid->getYMin()
     << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.35\n";
  writeFileAtomically(stem + ".yaml", os.str(), "occupancy map YAML");
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
      if (v != "0" && v != "1" && v != "true" && v != "false")
        throw InputError(where + ": negate must be 0 or 1 (or true / false)");
      m.negate = v == "1" || v == "true";
    } else if (key == "occupied_thresh" || key == "free_thresh") {
      const double x = number(v, where);
      if (x < 0 || x > 1) throw InputError(where + ": " + key + " must be in [0, 1]");
      (key == "free_thresh" ? m.free_thresh : m.occupied_thresh) = x;
    } else if (key == "mode") {
      if (v == "trinary")
        m.mode = MapMode::Trinary;
      else if (v == "scale")
        m.mode = MapMode::Scale;
      else if (v == "raw")
        m.mode = MapMode::Raw;
      else
        throw InputError(where + ": mode '" + v + "' (trinary, scale or raw)");
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
  const GrayImage g = readGrayImage(occupancyImagePath(yaml_path, m));
  GridMap map;
  try {  // the frame and size checked there; no cell free yet (threshold above 255)
    map = gridFromImage(g, m.resolution, 256, m.origin_x, m.origin_y);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(yaml_path + ": " + e.what());
  }
  auto grid = std::const_pointer_cast<mrpt::maps::COccupancyGridMap2D>(map.grid);
  for (int row = 0; row < g.height; ++row)
    for (int col = 0; col < g.width; ++col) {
      const int occ = mapServerOccupancy(m, g.at(col, row));
      grid->setCell(col, g.height - 1 - row, occ < 0 ? 0.5f : 1.0f - occ / 100.0f);
    }
  return map;
}

GridMap gridFromImage(const GrayImage& image, double resolution, int free_threshold,
                      double origin_x, double origin_y) {
  if (image.width <= 0 || image.height <= 0) throw Error("gridFromImage: empty image");
  if (!(resolution > 0)) throw Error("gridFromImage: resolution must be > 0");
  const int W = image.width, H = image.height;
  std::shared_ptr<Grid> g;
  try {  // MRPT asserts on extents float cannot tell apart (fuzzing: origin 5.8e15 m)
    g = std::make_shared<Grid>(
        static_cast<float>(origin_x), static_cast<float>(origin_x + W * resolution),
        static_cast<float>(origin_y), static_cast<float>(origin_y + H * resolution),
        static_cast<float>(resolution));
  } catch (const std::exception& e) {
    throw Error("gridFromImage: MRPT cannot make a " + std::to_string(W) + " x " +
                std::to_string(H) + " grid of " + std::to_string(resolution) + " m cells at (" +
                std::to_string(origin_x) + ", " + std::to_string(origin_y) + ")");
  }
  if (static_cast<int>(g->getSizeX()) != W || static_cast<int>(g->getSizeY()) != H)
    throw Error("gridFromImage: MRPT made a " + std::to_string(g->getSizeX()) + " x " +
                std::to_string(g->getSizeY()) + " grid for a " + std::to_string(W) + " x " +
                std::to_string(H) + " image");
  g->fill(0.0f);
  for (int row = 0; row < H; ++row)
    for (int col = 0; col < W; ++col)
      if (image.at(col, row) >= free_threshold) g->setCell(col, H - 1 - row, 1.0f);
  GridMap m;
  m.grid = std::move(g);
  m.version = 1;
  m.changed.extend(origin_x, origin_y);
  m.changed.extend(origin_x + W * resolution, origin_y + H * resolution);
  m.rebuilt = true;
  return m;
}

GrayImage imageFromGrid(const GridMap& map) {
  GrayImage g;
  if (!map.grid) return g;
  const Grid& grid = *map.grid;
  g.width = static_cast<int>(grid.getSizeX());
  g.height = static_cast<int>(grid.getSizeY());
  g.pixels.resize(static_cast<std::size_t>(g.width) * g.height);
  for (int cy = 0; cy < g.height; ++cy)
    for (int cx = 0; cx < g.width; ++cx)
      g.pixels[static_cast<std::size_t>(g.height - 1 - cy) * g.width + cx] =
          static_cast<std::uint8_t>(std::lround(255.0 * grid.getCell(cx, cy)));
  return g;
}

}  // namespace asf::io
