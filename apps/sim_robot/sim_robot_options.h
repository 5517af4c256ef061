#pragma once
// asf sim-robot's command line (sim_robot.cpp).
#include <string>
#include <utility>
#include <vector>

namespace asf::simrobot {

struct Options {
  std::string config, out;
  std::vector<std::string> sets;
  int domain = 0;
  bool loopback = false;
  bool mount_on_tf = false;  // the laser's mounting on /tf with every frame, not on /tf_static
  double rate = 1.0;       // real-time factor
  double duration = 0;     // simulated seconds; 0: until stopped
  double clock_start = 1;  // ROS tools read a zero stamp as "latest": start the clock here
  double cmd_vel_timeout = 0.5;  // simulated seconds a /cmd_vel holds (robot drivers stop after)
  std::string fault;       // a bad peer on purpose (kFaults), for testing what talks to it
  std::vector<std::pair<double, std::string>> commands;  // an operator's script: (time, text)
};

/// Parses `asf sim-robot CONFIG.ini [options]` (argv[1] is "sim-robot"); throws
/// asf::ConfigError naming the argument; --help prints the usage and exits.
Options parseArgs(int argc, char** argv);

}  // namespace asf::simrobot
