// asf's CDR encoders (asf/ros2/cdr.h) against an independent implementation: each message is
// deserialized by Fast CDR into the types fastddsgen generated from the same IDL, and must
// come back field by field, with every byte consumed. Plus the ros2msg definitions' shape.
#include <asf/ros2/cdr.h>
#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <gtest/gtest.h>

#include <cmath>

#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "sensor_msgs.h"
#include "std_msgs.h"
#include "tf2_msgs.h"
#include "visualization_msgs.h"

using namespace asf::ros2;

namespace {

// Deserializes `bytes` (with their encapsulation header) into T; checks all were consumed.
template <class T>
T decode(std::vector<std::uint8_t> bytes) {
  eprosima::fastcdr::FastBuffer buf(reinterpret_cast<char*>(bytes.data()), bytes.size());
  eprosima::fastcdr::Cdr cdr(buf, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN, eprosima::fastcdr::Cdr::DDS_CDR);
  cdr.read_encapsulation();
  T m;
  m.deserialize(cdr);
  EXPECT_EQ(cdr.getSerializedDataLength(), bytes.size()) << "bytes left over or missing";
  return m;
}

}  // namespace

TEST(Ros2Cdr, LaserScanDecodesOnFastCdr) {
  LaserScan s;
  s.stamp = {12, 345};
  s.frame_id = "laser";  // odd length: the floats after it are aligned
  s.angle_min = -1.5f, s.angle_max = 1.5f, s.angle_increment = 0.01f;
  s.range_min = 0.1f, s.range_max = 10;
  s.ranges = {1.0f, 2.5f, INFINITY};
  s.intensities = {7, 8, 9};
  const auto m = decode<sensor_msgs::msg::dds_::LaserScan_>(cdrLaserScan(s));
  EXPECT_EQ(m.header().stamp().sec(), 12);
  EXPECT_EQ(m.header().stamp().nanosec(), 345u);
  EXPECT_EQ(m.header().frame_id(), "laser");
  EXPECT_FLOAT_EQ(m.angle_increment(), 0.01f);
  EXPECT_FLOAT_EQ(m.range_max(), 10);
  ASSERT_EQ(m.ranges().size(), 3u);
  EXPECT_FLOAT_EQ(m.ranges()[1], 2.5f);
  EXPECT_TRUE(std::isinf(m.ranges()[2]));
  EXPECT_EQ(m.intensities(), s.intensities);
}

TEST(Ros2Cdr, OdometryAndTransformsDecodeOnFastCdr) {
  Odometry o{{1, 2}, "odom", "base_link", transformFromPose(mrpt::poses::CPose2D(1, -2, 0.3))};
  const auto m = decode<nav_msgs::msg::dds_::Odometry_>(cdrOdometry(o));
  EXPECT_EQ(m.child_frame_id(), "base_link");
  EXPECT_DOUBLE_EQ(m.pose().pose().position().y(), -2);
  EXPECT_DOUBLE_EQ(m.pose().pose().orientation().z(), o.pose.qz);
  EXPECT_EQ(m.twist().covariance()[35], 0.0);
  const std::vector<TransformStamped> tf = {{{3, 0}, "map", "odom", transformFromPose(mrpt::poses::CPose2D(5, 6, 1))},
                                            {{3, 1}, "b", "c", {}}};
  const auto t = decode<tf2_msgs::msg::dds_::TFMessage_>(cdrTfMessage(tf));
  ASSERT_EQ(t.transforms().size(), 2u);
  EXPECT_EQ(t.transforms()[0].header().frame_id(), "map");
  EXPECT_EQ(t.transforms()[0].child_frame_id(), "odom");
  EXPECT_DOUBLE_EQ(t.transforms()[0].transform().translation().x(), 5);
  EXPECT_DOUBLE_EQ(t.transforms()[1].transform().rotation().w(), 1);
  const auto p = decode<geometry_msgs::msg::dds_::PoseStamped_>(cdrPoseStamped({4, 0}, "map", tf[0].transform));
  EXPECT_DOUBLE_EQ(p.pose().position().y(), 6);
  EXPECT_EQ(decode<std_msgs::msg::dds_::String_>(cdrString("{\"a\": 1}")).data(), "{\"a\": 1}");
}

TEST(Ros2Cdr, OccupancyGridAndMarkersDecodeOnFastCdr) {
  OccupancyGrid g;
  g.stamp = {9, 0};
  g.frame_id = "map";
  g.resolution = 0.05f, g.width = 3, g.height = 2;
  g.origin.tx = -1.5;
  g.data = {-1, 0, 100, 50, 7, -1};
  const auto m = decode<nav_msgs::msg::dds_::OccupancyGrid_>(cdrOccupancyGrid(g));
  EXPECT_EQ(m.info().width(), 3u);
  EXPECT_DOUBLE_EQ(m.info().origin().position().x(), -1.5);
  EXPECT_EQ(m.data(), g.data);
  Marker a;
  a.ns = "regions", a.id = 4, a.type = Marker::LineStrip, a.text = "";
  a.points = {{1, 2, 0}, {3, 4, 0.5}};
  a.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}};
  Marker b;
  b.ns = "region_labels", b.type = Marker::Text, b.text = "4";
  b.color = {0.5f, 0.5f, 0.5f, 1};
  const auto arr = decode<visualization_msgs::msg::dds_::MarkerArray_>(cdrMarkerArray({a, b}));
  ASSERT_EQ(arr.markers().size(), 2u);
  EXPECT_EQ(arr.markers()[0].ns(), "regions");
  EXPECT_EQ(arr.markers()[0].id(), 4);
  ASSERT_EQ(arr.markers()[0].points().size(), 2u);
  EXPECT_DOUBLE_EQ(arr.markers()[0].points()[1].z(), 0.5);
  EXPECT_FLOAT_EQ(arr.markers()[0].colors()[1].g(), 1);
  EXPECT_EQ(arr.markers()[1].text(), "4");
  EXPECT_FLOAT_EQ(arr.markers()[1].color().r(), 0.5f);
  EXPECT_FALSE(arr.markers()[1].mesh_use_embedded_materials());
}

TEST(Ros2Cdr, DefinitionsListEveryUsedTypeOnce) {
  const std::string d = messageDefinition("visualization_msgs/msg/MarkerArray");
  EXPECT_EQ(d.rfind("Marker[] markers\n", 0), 0u);
  for (const char* t : {"MSG: visualization_msgs/Marker\n", "MSG: std_msgs/Header\n", "MSG: builtin_interfaces/Time\n",
                        "MSG: builtin_interfaces/Duration\n", "MSG: geometry_msgs/Pose\n", "MSG: geometry_msgs/Point\n",
                        "MSG: sensor_msgs/CompressedImage\n", "MSG: visualization_msgs/MeshFile\n"}) {
    const auto at = d.find(t);
    EXPECT_NE(at, std::string::npos) << t;
    EXPECT_EQ(d.find(t, at + 1), std::string::npos) << "twice: " << t;
  }
  EXPECT_NE(messageDefinition("nav_msgs/msg/OccupancyGrid").find("MSG: nav_msgs/MapMetaData\n"), std::string::npos);
  EXPECT_THROW(messageDefinition("sensor_msgs/msg/Image"), std::invalid_argument);
}
