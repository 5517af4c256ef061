// The fuzz targets (fuzz_targets.h). Readers that take a path get the bytes through a file in
// a private temporary folder, so the path, the extension and the reader are those a user's
// file meets.
#include "fuzz_targets.h"

#include <asf/config.h>
#include <asf/errors.h>
#include <asf/graph/multigraph.h>
#include <asf/io/occupancy_io.h>
#include <asf/pose_graph.h>
#include <asf/io/rawlog_io.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/io/carmen.h>
#include <asf/io/rawseeds.h>
#include <asf/io/rosbag2.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace asf::fuzz {

namespace {

namespace fs = std::filesystem;

// A folder of this process's own, removed at exit.
const fs::path& scratch() {
  struct Dir {
    fs::path path;
    Dir() {
      path = fs::temp_directory_path() / ("asf_fuzz_" + std::to_string(::getpid()));
      fs::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const fs::path p = scratch() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out.flush()) throw std::runtime_error("fuzz: cannot write " + p.string());
  return p.string();
}

std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `fn`; an asf::Error is a rejection (false), anything else goes on to the fuzzer.
template <class Fn>
bool accepted(Fn&& fn) {
  try {
    fn();
    return true;
  } catch (const asf::Error&) {
    return false;
  }
}

// A graph asf accepted must survive asf's own writer and reader unchanged in shape.
bool g2o(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    const PoseGraph g = parseG2o(text(data, size), "fuzz.g2o");
    const std::string out = (scratch() / "roundtrip.g2o").string();
    writeG2o(g, out);
    const PoseGraph back = readG2o(out);
    if (back.nodes.size() != g.nodes.size() || back.edges.size() != g.edges.size() ||
        back.fixed != g.fixed)
      throw std::logic_error("fuzz g2o: the graph written and read back differs in shape");
  });
}

// Every key of every section read back, and section "pipeline" validated against a key
// table with each key type.
bool ini(const std::uint8_t* data, std::size_t size) {
  static const KeySpec keys[] = {
      keyInt("seed", "1", "an int", 0, 1e9),
      keyDouble("step", "0.5", "a double", 0, 10),
      keyBool("flag", "false", "a bool"),
      keyString("name", "x", "a string"),
      keyEnum("policy", "tigre", "tigre|frontier", "a choice"),
      keyPath("map", "", "a path"),
      keyDoubleList("list", "", "a list", -1e6, 1e6),
  };
  return accepted([&] {
    const IniConfig c = IniConfig::fromText(text(data, size), "fuzz.ini");
    for (const auto& s : c.sections())
      for (const auto& k : c.keys(s)) {
        (void)c.get(s, k);
        (void)c.where(s, k);
      }
    if (c.hasSection("pipeline")) (void)c.resolve("pipeline", keys, std::size(keys));
  });
}

bool graphList(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    for (const auto& g : graph::readGraphList(writeInput("graphs.txt", data, size)))
      (void)g.graph.connected();
  });
}

bool topologyJson(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    const auto r = graph::parseTopologyJson(text(data, size), "fuzz/topology.json");
    if (!r.centroids.empty() && r.centroids.size() != static_cast<std::size_t>(r.graph.n))
      throw std::logic_error("fuzz topology.json: centroids and nodes differ in count");
    (void)r.graph.connected();
  });
}

// Both layouts (action/sensory-frame pairs, observations only) go through one reader.
bool rawlog(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    io::RawlogReader reader(writeInput("fuzz.rawlog", data, size));
    while (reader.next()) {
    }
  });
}

bool carmen(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    io::CarmenToRawlogOptions opt;
    opt.input = writeInput("fuzz.log", data, size);
    opt.output = (scratch() / "carmen.rawlog").string();
    opt.gt_output = (scratch() / "carmen.gt.txt").string();
    io::carmenToRawlog(opt);
  });
}

// The first byte chooses the stream the rest of the input becomes (laser, odometry or
// ground truth); the other two are short valid streams.
bool rawseeds(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return false;
  static const char* kStreams[] = {"SICK_FRONT", "ODOMETRY_XYT", "GROUNDTRUTH"};
  static const char* kValid[] = {"1.000000,3,0,1.5,2.0,2.5\n1.200000,3,0,1.4,2.1,2.5\n",
                                 "0.900000,1,0,0,0,0,0\n1.100000,2,0,0,0.1,0,0.01\n",
                                 "1.000000,0,0,0\n1.300000,0.1,0,0.01\n"};
  const int chosen = data[0] % 3;
  return accepted([&] {
    const fs::path dir = scratch() / "rawseeds";
    fs::create_directories(dir);
    for (int s = 0; s < 3; ++s) {
      const std::string file = "fuzz-" + std::string(kStreams[s]) + ".csv";
      std::ofstream out(dir / file, std::ios::binary | std::ios::trunc);
      if (s == chosen)
        out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
      else
        out << kValid[s];
    }
    io::RawseedsToRawlogOptions opt;
    opt.dir = dir.string();
    opt.dataset = "fuzz";
    opt.output = (scratch() / "rawseeds.rawlog").string();
    opt.gt_output = (scratch() / "rawseeds.gt.txt").string();
    io::rawseedsToRawlog(opt);
  });
}

bool mapImage(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    const io::GrayImage img = io::readGrayImage(writeInput("map.png", data, size));
    (void)img;
  });
}

// A map_server YAML and, when it parses, the map it names (a small PGM written here when
// the YAML names "map.pgm", as the seed corpus does).
bool occupancyYaml(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    const std::string yaml = writeInput("map.yaml", data, size);
    const io::OccupancyMapInfo info = io::readOccupancyYaml(yaml);
    if (info.image == "map.pgm") {
      static const char kPgm[] = "P2\n3 2\n255\n0 255 128\n255 254 0\n";
      writeInput("map.pgm", reinterpret_cast<const std::uint8_t*>(kPgm), sizeof(kPgm) - 1);
    }
    std::error_code ec;
    if (fs::is_regular_file(fs::path(yaml).parent_path() / info.image, ec))
      (void)io::readOccupancyMap(yaml);
  });
}

// One serialized ROS message: the first byte picks the type (LaserScan, Odometry, TFMessage:
// its value mod 3) and the wire (bit 2 set: ROS 1, else CDR); the rest is the message.
bool rosMessage(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    if (size == 0) return;
    const io::Wire wire = (data[0] & 4) ? io::Wire::Ros1 : io::Wire::Cdr;
    switch (data[0] % 3) {
      case 0:
        (void)io::decodeLaserScan(data + 1, size - 1, "fuzz", wire);
        break;
      case 1:
        (void)io::decodeOdometry(data + 1, size - 1, "fuzz", wire);
        break;
      default:
        (void)io::decodeTfMessage(data + 1, size - 1, "fuzz", wire);
    }
  });
}

// An MCAP file: its topics, then every message of every topic.
bool mcap(const std::uint8_t* data, std::size_t size) {
  return accepted([&] {
    const io::McapReader r({writeInput("bag.mcap", data, size)});
    std::vector<std::string> topics;
    for (const auto& t : r.topics()) topics.push_back(t.name);
    std::size_t bytes = 0;
    r.forEach(topics, [&](const std::string&, std::int64_t, const std::uint8_t*, std::size_t n) {
      bytes += n;
    });
  });
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"g2o", g2o, "parseG2o, then writeG2o/readG2o round trip"},
      {"ini", ini, "IniConfig::fromText and resolve against a key table of every type"},
      {"graph_list", graphList, "graph::readGraphList (graphs.txt)"},
      {"topology_json", topologyJson, "graph::parseTopologyJson (topology.json)"},
      {"rawlog", rawlog, "RawlogReader over every frame (both layouts)"},
      {"carmen", carmen, "io::carmenToRawlog (CARMEN .log/.clf)"},
      {"rawseeds", rawseeds, "io::rawseedsToRawlog (Rawseeds CSV streams)"},
      {"map_image", mapImage, "readGrayImage (map PNG)"},
      {"occupancy_yaml", occupancyYaml, "readOccupancyYaml + readOccupancyMap (map_server YAML)"},
      {"ros_message", rosMessage,
       "io::decodeLaserScan / decodeOdometry / decodeTfMessage (ROS bags, CDR and ROS 1)"},
      {"mcap", mcap, "io::McapReader (MCAP files: records, chunks none / lz4 / zstd)"},
  };
  return all;
}

const Target* findTarget(const std::string& name) {
  for (const auto& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace asf::fuzz
