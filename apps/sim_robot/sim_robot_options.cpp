// asf sim-robot's command line (sim_robot_options.h).
#include "sim_robot_options.h"

#include <asf/errors.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iterator>

namespace asf::simrobot {

namespace {

// The ways --fault makes the robot a bad peer.
const char* kFaults[] = {"scan_as_string", "no_tf_static", "stuck"};

const char* kUsage =
    "usage: asf sim-robot CONFIG.ini [--set section.key=value]... [--domain N] [--loopback]\n"
    "                     [--rate FACTOR] [--duration SECONDS] [--out DIR] [--fault NAME]\n"
    "                     [--cmd-vel-timeout SECONDS] [--command SECONDS:TEXT]... [--mount-on-tf]\n"
    "The [pipeline] source of CONFIG.ini (sim2d) as a ROS 2 robot on Fast DDS: publishes\n"
    "/clock /scan /odom /tf /tf_static /ground_truth /world_map, takes /goal_pose with /map and\n"
    "map -> odom, reports goals on /navigate_to_pose/_action/status; its base takes /cmd_vel\n"
    "(each held --cmd-vel-timeout simulated seconds, default 0.5). --rate: real-time factor\n"
    "(default 1); --loopback: discovery on 127.0.0.1 only; --out: the simulator's recording and\n"
    "sim_robot.json. Stops on SIGINT or SIGTERM, after --duration, or when the source ends.\n"
    "--fault makes it a bad peer, to test what talks to it: scan_as_string (/scan carries\n"
    "std_msgs/String), no_tf_static (no laser mounting), stuck (goals accepted, never driven).\n"
    "--command T:TEXT publishes TEXT (std_msgs/String) on /asf/command at simulated time T: an\n"
    "operator's script (start, pause, resume, stop, return_home). --mount-on-tf: the laser's\n"
    "mounting goes on /tf with every frame (as robot_state_publisher sends a moving joint), not\n"
    "on /tf_static.\n";

}  // namespace

Options parseArgs(int argc, char** argv) {
  Options o;
  if (const char* env = std::getenv("ROS_DOMAIN_ID"); env && *env) o.domain = std::atoi(env);
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw asf::ConfigError("asf sim-robot: " + a + " needs a value");
      return argv[++i];
    };
    auto number = [&](double lo, double hi) {
      const std::string v = value();
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end || !(d >= lo && d <= hi))
        throw asf::ConfigError("asf sim-robot: " + a + " " + v + ": not a number in [" +
                               std::to_string(lo) + ", " + std::to_string(hi) + "]");
      return d;
    };
    if (a == "--set" || a == "-s") o.sets.push_back(value());
    else if (a == "--domain") o.domain = static_cast<int>(number(0, 232));
    else if (a == "--loopback") o.loopback = true;
    else if (a == "--rate") o.rate = number(1e-3, 1e4);
    else if (a == "--duration") o.duration = number(0, 1e9);
    else if (a == "--cmd-vel-timeout") o.cmd_vel_timeout = number(0, 1e6);
    else if (a == "--command") {
      const std::string v = value();
      const std::size_t colon = v.find(':');
      char* end = nullptr;
      const double t = colon == std::string::npos ? -1 : std::strtod(v.c_str(), &end);
      if (colon == std::string::npos || end != v.c_str() + colon || !(t >= 0))
        throw asf::ConfigError("asf sim-robot: --command " + v + ": not SECONDS:TEXT");
      o.commands.emplace_back(t, v.substr(colon + 1));
    }
    else if (a == "--out") o.out = value();
    else if (a == "--mount-on-tf") o.mount_on_tf = true;
    else if (a == "--fault") {
      o.fault = value();
      if (std::find(std::begin(kFaults), std::end(kFaults), o.fault) == std::end(kFaults))
        throw asf::ConfigError("asf sim-robot: --fault " + o.fault +
                               ": not one of scan_as_string, no_tf_static, stuck");
    }
    else if (a == "-h" || a == "--help") { std::fputs(kUsage, stdout); std::exit(0); }
    else if (o.config.empty() && a[0] != '-') o.config = a;
    else throw asf::ConfigError("asf sim-robot: unknown argument '" + a + "'\n" + kUsage);
  }
  if (o.config.empty()) throw asf::ConfigError(std::string("asf sim-robot: no CONFIG.ini\n") + kUsage);
  return o;
}

}  // namespace asf::simrobot
