// asf bag2rawlog: a ROS 1 or ROS 2 bag to an MRPT rawlog (logic in
// apps/asf/convert/rosbag2.cpp and bag_to_rawlog.cpp).
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/io/rosbag2.h>
#include <tclap/CmdLine.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "commands.h"

namespace asf::app {

int cmdBag2Rawlog(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Converts a ROS 1 bag (.bag, format 2.0, chunks plain, bz2 or lz4) or a ROS 2 bag (a "
      "rosbag2 folder with metadata.yaml, sqlite3 or MCAP storage, or its .db3 / .mcap file; "
      "CDR messages) into an "
      "observation-only MRPT rawlog that `asf run` replays "
      "(configs/replay_rawlog.ini): sensor_msgs/msg/LaserScan as 2D range scans, "
      "nav_msgs/msg/Odometry as odometry, the laser's mounting from /tf_static, stamps from "
      "the messages' headers. Without --scan-topic / --odom-topic the bag's only topic of each "
      "type is taken.",
      ' ', ASF_VERSION_STRING);
  TCLAP::ValueArg<std::string> in("i", "in", "ROS 1 .bag, rosbag2 folder, .db3 or .mcap file", true,
                                  "", "BAG", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output rawlog (.gz: compressed)", false, "",
                                   "FILE.rawlog", cmd);
  TCLAP::ValueArg<std::string> scan("", "scan-topic", "LaserScan topic", false, "", "TOPIC", cmd);
  TCLAP::ValueArg<std::string> odom(
      "", "odom-topic",
      "Odometry topic (default: the only one; without one, /tf's transforms to the base frame)",
      false, "", "TOPIC", cmd);
  TCLAP::SwitchArg no_odom("", "no-odometry", "Scans only", cmd);
  TCLAP::ValueArg<std::string> base(
      "", "base-frame",
      "The robot's frame (default: the odometry's child_frame_id, else base_link)", false, "",
      "FRAME", cmd);
  TCLAP::ValueArg<std::string> laser_pose(
      "", "laser-pose", "The laser on the robot instead of /tf_static: x, y, z [m], yaw [deg]",
      false, "", "X,Y,Z,YAW_DEG", cmd);
  TCLAP::ValueArg<std::string> gt_topic(
      "", "gt-topic",
      "Ground-truth topic (nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped), to --gt", false,
      "", "TOPIC", cmd);
  TCLAP::ValueArg<std::string> gt("", "gt", "Ground-truth file to write (t x y phi lines)", false,
                                  "", "FILE", cmd);
  TCLAP::SwitchArg list("", "list", "List the bag's topics and stop", cmd);
  TCLAP::SwitchArg quiet("q", "quiet", "No progress lines", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  if (list.getValue()) {
    const auto bag = io::openBag(in.getValue());
    for (const auto& t : bag->topics())
      std::cout << std::left << std::setw(32) << t.name << std::setw(34) << t.type << std::right
                << std::setw(9) << t.messages << "  " << t.serialization_format << "\n";
    return kOk;
  }
  if (out.getValue().empty()) throw TCLAP::CmdLineParseException("required (or --list)", "--out");
  io::BagToRawlogOptions o;
  o.input = in.getValue();
  o.output = out.getValue();
  o.scan_topic = scan.getValue();
  o.odom_topic = odom.getValue();
  o.odometry = !no_odom.getValue();
  o.base_frame = base.getValue();
  if (gt_topic.isSet() != gt.isSet())
    throw TCLAP::CmdLineParseException("give both or neither", "--gt-topic/--gt");
  o.gt_topic = gt_topic.getValue();
  o.gt_output = gt.getValue();
  if (laser_pose.isSet()) try {
      o.laser_pose = io::parseLaserPose(laser_pose.getValue());
    } catch (const std::invalid_argument& e) {
      throw TCLAP::CmdLineParseException(e.what(), "--laser-pose");
    }
  o.progress = quiet.getValue() ? nullptr : &std::cerr;
  const auto r = io::bagToRawlog(o);
  const auto& p = r.laser_pose;
  std::cout << "bag2rawlog: " << r.scans << " scans from " << r.scan_topic << " (" << r.rays
            << " rays over " << r.aperture_deg << " deg, frame " << r.laser_frame << ") and "
            << r.odometry << " odometry readings"
            << (r.odom_topic.empty() ? " (no Odometry topic)" : " from " + r.odom_topic) << " -> "
            << o.output << " in " << std::setprecision(3) << r.wall_time_s << " s\n"
            << "  laser on " << r.base_frame << " (" << r.laser_pose_from << "): x " << p.x()
            << " y " << p.y() << " z " << p.z() << " yaw " << p.yaw() * 180 / M_PI << " deg\n";
  if (!o.gt_topic.empty())
    std::cout << "  " << r.gt_poses << " ground-truth poses from " << o.gt_topic << " -> "
              << o.gt_output << "\n";
  return kOk;
}

}  // namespace asf::app
