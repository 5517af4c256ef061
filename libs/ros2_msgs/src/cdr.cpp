// ROS 2 messages as CDR bytes and their ros2msg definitions (cdr.h).
#include <asf/ros2/cdr.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>

namespace asf::ros2 {

namespace {

/// CDR little endian after the 4-byte encapsulation header; alignment counts from the byte
/// after the header.
class Cdr {
 public:
  Cdr() : b_{0x00, 0x01, 0x00, 0x00} {}
  template <class T>
  void put(T v) {
    align(sizeof(T));
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);  // this machine is little endian
    b_.insert(b_.end(), p, p + sizeof(T));
  }
  void str(const std::string& s) {
    put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    b_.insert(b_.end(), s.begin(), s.end());
    b_.push_back(0);
  }
  void count(std::size_t n) { put<std::uint32_t>(static_cast<std::uint32_t>(n)); }
  /// A sequence of primitives: its length, then the elements in one copy.
  template <class T>
  void sequence(const std::vector<T>& v) {
    count(v.size());
    if (v.empty()) return;
    align(sizeof(T));
    const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
    b_.insert(b_.end(), p, p + v.size() * sizeof(T));
  }
  void time(const Stamp& s) {
    put<std::int32_t>(s.sec);
    put<std::uint32_t>(s.nanosec);
  }
  void header(const Stamp& s, const std::string& frame) {
    time(s);
    str(frame);
  }
  void pose(const Transform& t) {  // geometry_msgs/Pose: position, orientation
    for (double v : {t.tx, t.ty, t.tz, t.qx, t.qy, t.qz, t.qw}) put<double>(v);
  }
  void zeros(int n) {
    for (int i = 0; i < n; ++i) put<double>(0.0);
  }
  std::vector<std::uint8_t> done() { return std::move(b_); }

 private:
  void align(std::size_t n) {
    while ((b_.size() - 4) % n) b_.push_back(0);
  }
  std::vector<std::uint8_t> b_;
};

}  // namespace

std::vector<std::uint8_t> cdrLaserScan(const LaserScan& m) {
  Cdr c;
  c.header(m.stamp, m.frame_id);
  for (float v : {m.angle_min, m.angle_max, m.angle_increment, m.time_increment, m.scan_time,
                  m.range_min, m.range_max})
    c.put<float>(v);
  c.sequence(m.ranges);
  c.sequence(m.intensities);
  return c.done();
}

std::vector<std::uint8_t> cdrOdometry(const Odometry& m) {
  Cdr c;
  c.header(m.stamp, m.frame_id);
  c.str(m.child_frame_id);
  c.pose(m.pose);
  c.zeros(36);     // pose covariance
  c.zeros(6 + 36);  // twist and its covariance
  return c.done();
}

std::vector<std::uint8_t> cdrTfMessage(const std::vector<TransformStamped>& m) {
  Cdr c;
  c.count(m.size());
  for (const TransformStamped& t : m) {
    c.header(t.stamp, t.parent);
    c.str(t.child);
    c.pose(t.transform);  // Transform: translation (Vector3), rotation: the same 7 doubles
  }
  return c.done();
}

std::vector<std::uint8_t> cdrOccupancyGrid(const OccupancyGrid& m) {
  Cdr c;
  c.header(m.stamp, m.frame_id);
  c.time(m.stamp);  // map_load_time
  c.put<float>(m.resolution);
  c.put<std::uint32_t>(m.width);
  c.put<std::uint32_t>(m.height);
  c.pose(m.origin);
  c.sequence(m.data);
  return c.done();
}

std::vector<std::uint8_t> cdrMarkerArray(const std::vector<Marker>& markers) {
  Cdr c;
  c.count(markers.size());
  for (const Marker& m : markers) {
    c.header(m.stamp, m.frame_id);
    c.str(m.ns);
    c.put<std::int32_t>(m.id);
    c.put<std::int32_t>(m.type);
    c.put<std::int32_t>(m.action);
    c.pose(m.pose);
    for (double v : m.scale) c.put<double>(v);
    for (float v : m.color) c.put<float>(v);
    c.time({});  // lifetime 0: forever
    c.put<std::uint8_t>(0);  // frame_locked
    c.count(m.points.size());
    for (const auto& p : m.points)
      for (double v : p) c.put<double>(v);
    c.count(m.colors.size());
    for (const auto& col : m.colors)
      for (float v : col) c.put<float>(v);
    c.str("");         // texture_resource
    c.header({}, "");  // texture: header, format, data
    c.str("");
    c.count(0);
    c.count(0);  // uv_coordinates
    c.str(m.text);
    c.str("");  // mesh_resource
    c.str("");  // mesh_file: filename, data
    c.count(0);
    c.put<std::uint8_t>(0);  // mesh_use_embedded_materials
  }
  return c.done();
}

std::vector<std::uint8_t> cdrPoseStamped(const Stamp& stamp, const std::string& frame,
                                         const Transform& pose) {
  Cdr c;
  c.header(stamp, frame);
  c.pose(pose);
  return c.done();
}

std::vector<std::uint8_t> cdrString(const std::string& text) {
  Cdr c;
  c.str(text);
  return c.done();
}

namespace {

// The fields of each type (ROS 2 Humble), without comments and constants.
const std::map<std::string, std::string>& fieldsOf() {
  static const std::map<std::string, std::string> f = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"std_msgs/String", "string data\n"},
      {"std_msgs/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"},
      {"geometry_msgs/Pose", "Point position\nQuaternion orientation\n"},
      {"geometry_msgs/PoseStamped", "std_msgs/Header header\nPose pose\n"},
      {"geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/Twist", "Vector3 linear\nVector3 angular\n"},
      {"geometry_msgs/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n"},
      {"geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"nav_msgs/Odometry",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
       "geometry_msgs/TwistWithCovariance twist\n"},
      {"nav_msgs/MapMetaData",
       "builtin_interfaces/Time map_load_time\nfloat32 resolution\nuint32 width\nuint32 height\n"
       "geometry_msgs/Pose origin\n"},
      {"nav_msgs/OccupancyGrid", "std_msgs/Header header\nMapMetaData info\nint8[] data\n"},
      {"sensor_msgs/LaserScan",
       "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
       "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
       "float32[] ranges\nfloat32[] intensities\n"},
      {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"visualization_msgs/UVCoordinate", "float32 u\nfloat32 v\n"},
      {"visualization_msgs/MeshFile", "string filename\nuint8[] data\n"},
      {"visualization_msgs/Marker",
       "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n"
       "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\n"
       "builtin_interfaces/Duration lifetime\nbool frame_locked\ngeometry_msgs/Point[] points\n"
       "std_msgs/ColorRGBA[] colors\nstring texture_resource\nsensor_msgs/CompressedImage texture\n"
       "UVCoordinate[] uv_coordinates\nstring text\nstring mesh_resource\nMeshFile mesh_file\n"
       "bool mesh_use_embedded_materials\n"},
      {"visualization_msgs/MarkerArray", "Marker[] markers\n"},
  };
  return f;
}

// The types a definition uses, as "pkg/Type" (a bare type name is of the same package).
std::vector<std::string> usedTypes(const std::string& type) {
  static const std::vector<std::string> primitives = {"bool", "int8", "uint8", "int32", "uint32",
                                                      "float32", "float64", "string"};
  std::vector<std::string> out;
  const std::string pkg = type.substr(0, type.find('/'));
  const std::string& text = fieldsOf().at(type);
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t end = text.find('\n', pos);
    std::string t = text.substr(pos, text.find(' ', pos) - pos);
    pos = end + 1;
    t = t.substr(0, t.find('['));
    bool primitive = false;
    for (const auto& p : primitives) primitive |= t == p;
    if (primitive) continue;
    out.push_back(t.find('/') == std::string::npos ? pkg + "/" + t : t);
  }
  return out;
}

}  // namespace

std::string messageDefinition(const std::string& type) {
  const std::size_t m = type.find("/msg/");
  const std::string key = m == std::string::npos ? type : type.substr(0, m) + type.substr(m + 4);
  if (!fieldsOf().count(key) || key.find('/') == std::string::npos)
    throw std::invalid_argument("no ROS 2 message definition for " + type);
  std::string out = fieldsOf().at(key);
  // Every used type once, depth first in order of use, as rosbag2 lists them.
  std::vector<std::string> done = {key}, stack = usedTypes(key);
  std::reverse(stack.begin(), stack.end());
  while (!stack.empty()) {
    const std::string t = stack.back();
    stack.pop_back();
    if (std::find(done.begin(), done.end(), t) != done.end()) continue;
    done.push_back(t);
    out += std::string(80, '=') + "\nMSG: " + t + "\n" + fieldsOf().at(t);
    auto more = usedTypes(t);
    for (auto it = more.rbegin(); it != more.rend(); ++it) stack.push_back(*it);
  }
  return out;
}

}  // namespace asf::ros2
