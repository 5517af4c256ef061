#pragma once
/// \file goal.h
/// What a policy asks for and what navigation answers.
#include <string>

namespace asf {

struct Goal {
  double x = 0, y = 0;  ///< map frame (SLAM estimate), metres
  double tolerance = 0.3;  ///< reached when within this distance, metres
};

struct Decision {
  enum class Type { GoTo, Done } type = Type::Done;
  Goal goal;
  std::string reason;  ///< why this goal / why done: logged and recorded
  static Decision goTo(const Goal& g, std::string why) { return {Type::GoTo, g, std::move(why)}; }
  static Decision done(std::string why) { return {Type::Done, {}, std::move(why)}; }
};

enum class NavStatus {
  Idle,         ///< no goal
  Moving,       ///< on the way
  Reached,      ///< within tolerance of the goal
  Unreachable,  ///< no path to the goal
  Blocked,      ///< stopped by an obstacle or stuck
};
const char* navStatusName(NavStatus s);

}  // namespace asf
