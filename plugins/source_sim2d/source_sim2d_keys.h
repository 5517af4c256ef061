#pragma once
// The sim2d source's INI keys: its ASF_PLUGIN table (source_sim2d.cpp), in a file of its own
// for length. Included once, by source_sim2d.cpp.
#include <asf/key_spec.h>

namespace {

const asf::KeySpec kKeys[] = {
    asf::keyPath("map_image", "",
                 "World image (PNG/PGM/...; dark = wall), or a ROS map_server YAML (X.yaml: its "
                 "image, resolution, origin, thresholds and mode; unknown cells as map_unknown "
                 "says). Empty: a built-in rectangular room of room_width x room_height"),
    asf::keyEnum("map_unknown", "wall", "wall|blocked|free",
                 "A map_server map's unknown cells: wall; blocked (the robot cannot enter them, "
                 "the lasers see through them); or free"),
    asf::keyDouble("resolution", "0.04", "World cell size: metres per image pixel [m]", 1e-3, 10),
    asf::keyDouble("origin_x", "0", "World x of the image's lower-left corner [m]"),
    asf::keyDouble("origin_y", "0", "World y of the image's lower-left corner [m]"),
    asf::keyDouble("occupied_threshold", "0.5",
                   "A pixel whose darkness 1 - gray/255 exceeds this is a wall", 0, 0.999),
    asf::keyDouble("wall_height", "2.0",
                   "Height of every obstacle pixel when obstacle_heights is empty, of the "
                   "pad_wall_px frame and of the built-in room's walls [m]",
                   1e-3, 1000),
    asf::keyString("obstacle_heights", "",
                   "Obstacle heights by gray level, 'GRAY:HEIGHT, ...' (e.g. '0:2.0, 100:0.25'): "
                   "an obstacle pixel is as tall as the class with the nearest gray level (a tie "
                   "goes to the darker class) [0..255:m]; empty = all wall_height"),
    asf::keyInt("pad_wall_px", "0",
                "Wall of this many pixels added around the image (for maps without an outer "
                "wall)",
                0, 1000),
    asf::keyInt("map_tiles", "1",
                "The world is map_tiles x map_tiles copies of the image, every other one "
                "mirrored so the walls meet at the seams (bigger worlds for scaling runs)",
                1, 64),
    asf::keyDouble("room_width", "8.0", "Built-in room width, when map_image is empty [m]", 0.5,
                   1000),
    asf::keyDouble("room_height", "6.0", "Built-in room height, when map_image is empty [m]", 0.5,
                   1000),
    asf::keyDouble("start_x", "1.0",
                   "True start position x, world frame [m]; a map image without start_x and "
                   "start_y starts at the free cell farthest from any wall"),
    asf::keyDouble("start_y", "1.0", "True start position y, world frame [m] (see start_x)"),
    asf::keyDouble("start_phi_deg", "0", "True start heading [deg]", -360, 360),
    asf::keyInt("laser_rays", "361", "Rays per scan", 2, 100000),
    asf::keyDouble("laser_fov_deg", "180", "Laser field of view, centred ahead [deg]", 1, 360),
    asf::keyDouble("laser_max_range", "8.0", "Maximum range; no echo beyond = invalid ray [m]", 0.1,
                   1000),
    asf::keyDouble("range_sigma", "0.01", "Std of the Gaussian range noise [m]", 0, 10),
    asf::keyDouble("laser_rate", "0",
                   "Scans per second of simulated time; 0 = one scan every step [Hz]", 0, 1e6),
    asf::keyDouble("sensor_x", "0.1", "Laser position on the robot, x (ahead) [m]", -10, 10),
    asf::keyDouble("sensor_y", "0", "Laser position on the robot, y (left) [m]", -10, 10),
    asf::keyDouble("sensor_z", "0.3",
                   "Laser height: it sees only the obstacles strictly taller than this [m]", -10,
                   10),
    asf::keyDouble("sensor_yaw_deg", "0", "Laser heading on the robot [deg]", -360, 360),
    asf::keyBool("tilted_laser", "false",
                 "A second, tilted 2D laser ray cast over the 2.5D world: a scan labelled "
                 "TILTED_LASER in each frame's observations3d whenever the horizontal laser scans"),
    asf::keyDouble("tilted_x", "0.1", "Tilted laser position on the robot, x (ahead) [m]", -10, 10),
    asf::keyDouble("tilted_y", "0", "Tilted laser position on the robot, y (left) [m]", -10, 10),
    asf::keyDouble("tilted_z", "0.5", "Tilted laser height above the floor [m]", 1e-3, 100),
    asf::keyDouble("tilted_yaw_deg", "0", "Tilted laser heading on the robot [deg]", -360, 360),
    asf::keyDouble("tilted_pitch_deg", "20",
                   "Tilted laser downward tilt (positive = looking down; MRPT pitch) [deg]", -90,
                   90),
    asf::keyInt("tilted_rays", "181", "Rays per tilted scan", 2, 100000),
    asf::keyDouble("tilted_fov_deg", "180", "Tilted laser field of view, centred ahead [deg]", 1,
                   360),
    asf::keyDouble("tilted_max_range", "4.0",
                   "Tilted laser maximum range; no echo beyond = invalid ray [m]", 0.1, 1000),
    asf::keyDouble("tilted_range_sigma", "-1",
                   "Std of the tilted laser's Gaussian range noise; negative = range_sigma [m]", -1,
                   10),
    asf::keyDouble("dt", "0.1", "Simulated time per step [s]", 1e-4, 100),
    asf::keyDouble("step_length", "0.05", "Distance driven per step [m]", 1e-3, 10),
    asf::keyDouble("turn_step_deg", "10", "Rotation in place per step [deg]", 0.01, 180),
    asf::keyDouble("heading_tolerance_deg", "10",
                   "Drive forward once the heading error to the next waypoint is below this "
                   "[deg]",
                   0.01, 90),
    asf::keyDouble("robot_radius", "0.2", "Robot radius: never closer than this to a wall [m]",
                   0.01, 100),
    asf::keyDouble("odo_a1", "0.01",
                   "Odometry model (MRPT Gaussian): xy std per metre driven [m/m]", 0, 10),
    asf::keyDouble("odo_a2", "0.001", "Odometry model: xy std per degree turned [m/deg]", 0, 10),
    asf::keyDouble("odo_a3", "1.0", "Odometry model: heading std per metre driven [deg/m]", 0,
                   1000),
    asf::keyDouble("odo_a4", "0.05", "Odometry model: heading std per degree turned [deg/deg]", 0,
                   10),
    asf::keyDouble("odo_min_std_xy", "0.001", "Odometry model: minimum xy std of a moving step [m]",
                   0, 10),
    asf::keyDouble("odo_min_std_phi_deg", "0.05",
                   "Odometry model: minimum heading std of a moving step [deg]", 0, 360),
    asf::keyDouble("recovery_backup", "0.15",
                   "After a wall stopped the robot, the next goal starts by backing up this far "
                   "[m]",
                   0, 10),
    asf::keyInt("replan_every", "20",
                "Replan the path every this many driving steps with the latest scan (0: plan "
                "once per goal)",
                0, 1000000),
    asf::keyEnum("nav_unknown", "costly", "costly|blocked",
                 "Unknown cells of the estimated map: passable at nav_unknown_cost, or blocked"),
    asf::keyDouble("nav_unknown_cost", "4.0", "Cost factor of driving through unknown space", 1,
                   1e6),
    asf::keyDouble("nav_safety_margin", "0.05",
                   "Paths keep robot_radius plus this from obstacles of the map [m]", 0.0, 1.0),
    asf::keyDouble("nav_inflation_margin", "0.4",
                   "Beyond robot_radius, paths are penalised this close to obstacles [m]", 0, 100),
    asf::keyDouble("nav_occupied_threshold", "0.65",
                   "Estimated-map cells with p(occupied) above this are obstacles", 0.5, 0.999),
    asf::keyBool("record", "true",
                 "Record the run to <output>/<record_name>.rawlog and .gt.txt (needs an output "
                 "folder)"),
    asf::keyString("record_name", "sim2d", "Base name of the recorded files"),
    asf::keyPath("resume_from", "",
                 "A run folder whose recording (<record_name>.rawlog, .gt.txt) this run continues "
                 "(asf run --resume sets it): its frames are copied to this run's recording and "
                 "the robot starts where they end. Empty: a new run"),
    asf::keyInt("max_steps", "100000", "Frames produced before the stream ends", 1, 1e12),
};

}  // namespace
