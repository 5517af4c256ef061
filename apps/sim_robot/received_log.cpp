// What asf sim-robot received, written out (received_log.h).
#include "received_log.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace asf::simrobot {

void writeReceived(const std::string& dir, const std::optional<ros2::OccupancyGrid>& map,
                   const std::vector<visualization_msgs::msg::dds_::Marker_>& markers,
                   const mrpt::poses::CPose2D& map_to_odom) {
  using nlohmann::json;
  std::filesystem::create_directories(dir);
  if (map) {
    std::ofstream pgm(dir + "/map.pgm", std::ios::binary);
    pgm << "P5\n" << map->width << " " << map->height << "\n255\n";
    for (std::int8_t v : map->data) pgm.put(static_cast<char>(v < 0 ? 255 : v));
    json h = {{"width", map->width},         {"height", map->height},
              {"resolution", map->resolution}, {"origin", {map->origin.tx, map->origin.ty}},
              {"frame_id", map->frame_id},   {"stamp", ros2::toSeconds(map->stamp)}};
    std::ofstream(dir + "/map.json") << h.dump(1) << "\n";
  }
  json ms = json::array();
  for (const auto& m : markers) {
    json pts = json::array();
    for (const auto& p : m.points()) pts.push_back({p.x(), p.y(), p.z()});
    const auto& q = m.pose().orientation();
    ms.push_back({{"ns", m.ns()},
                  {"id", m.id()},
                  {"type", m.type()},
                  {"action", m.action()},
                  {"frame_id", m.header().frame_id()},
                  {"pose", {m.pose().position().x(), m.pose().position().y(),
                            ros2::yawFromQuaternion(q.x(), q.y(), q.z(), q.w())}},
                  {"points", pts},
                  {"text", m.text()}});
  }
  std::ofstream(dir + "/markers.json") << ms.dump() << "\n";
  std::ofstream(dir + "/map_to_odom.json")
      << json{{"x", map_to_odom.x()}, {"y", map_to_odom.y()}, {"yaw", map_to_odom.phi()}}.dump() << "\n";
}

}  // namespace asf::simrobot
