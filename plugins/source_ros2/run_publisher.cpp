// A run on /tf, /map and the markers topic (run_publisher.h).
#include "run_publisher.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <utility>

#include "run_markers.h"

namespace asf::ros2live {

RunPublisher::RunPublisher(CycloneLink& link, LiveBag& bag, RunPublisherOptions o)
    : link_(link), bag_(bag), o_(std::move(o)) {
  map_wr_ = link_.advertiseOccupancy(o_.map_topic);
  tf_wr_ = link_.advertiseTransforms(o_.tf_topic, Qos::Reliable);
  markers_wr_ = link_.advertiseMarkers(o_.marker_topic);
}

void RunPublisher::publish(const RunView& v, const mrpt::poses::CPose2D& odom) {
  const ros2::Stamp stamp = ros2::toStamp(v.timestamp);
  const mrpt::poses::CPose2D map_to_odom = v.robot + (mrpt::poses::CPose2D() - odom);
  const std::vector<ros2::TransformStamped> tf{
      {stamp, o_.map_frame, o_.odom_frame, ros2::transformFromPose(map_to_odom)}};
  link_.publish(tf_wr_, tf);
  bag_.transforms(tf, false);
  const bool map_due = v.map && v.map->grid && v.map->version &&
                       (v.final || (v.map->version != map_version_ && v.timestamp - map_sent_ >= o_.map_period));
  if (map_due) {
    const ros2::OccupancyGrid& grid = map_converter_.convert(*v.map->grid, stamp, o_.map_frame);
    link_.publish(map_wr_, grid);
    bag_.map(grid);
    map_version_ = v.map->version;
    map_sent_ = v.timestamp;
    ++maps_sent_;
  }
  if (v.final || v.timestamp - markers_sent_ >= o_.marker_period) {
    const auto markers = runMarkers(v, stamp, o_.map_frame);
    link_.publish(markers_wr_, markers);
    bag_.markers(markers);
    markers_sent_ = v.timestamp;
  }
}

}  // namespace asf::ros2live
