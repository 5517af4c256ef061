#pragma once
/// \file map3d.h
/// Framework service: a 3D occupancy map (an OctoMap octree) built from 3D observations at
/// the SLAM-estimated robot poses, and its projection to the 2D occupancy grid the rest of
/// the pipeline (navigation, segmenters) uses, so a robot with only a 3D sensor runs the
/// whole 2D pipeline.
///
/// Frames: the map frame is the 2D SLAM frame with z up; the robot base is at z = 0, so
/// heights in [map3d] (min_height, max_height) are metres above the floor the robot stands on.
/// A sensor's pose on the robot is the observation's sensorPose (a full 3D pose: a tilted 2D
/// laser gives 3D points).
///
/// Insertion is OctoMap's insertPointCloud (ray casting from the sensor origin, the end voxel
/// occupied, the traversed voxels free, occupied winning inside one cloud). Points farther than
/// max_range are not hits: OctoMap casts their ray as free space up to max_range only.
/// Non-finite points and points closer than min_range (or at the sensor origin, MRPT's
/// "no return" for 3D cameras) are dropped.
///
/// Loop closures: keyframes keep their points; when the back-end moves inserted keyframes,
/// the tree is rebuilt from all keyframes at their new poses into a second tree, at most
/// max_keyframes_per_update keyframes per rebuildStep(); the current tree stays in use (and
/// keeps receiving new keyframes) until the rebuild completes and replaces it. Points given
/// to insertPoints()/insertObservation() outside keyframes are not kept, so a rebuild drops
/// them.
///
/// OctoMap stays out of this header (compile time): the octree lives in the implementation.
/// Not thread-safe.
#include <asf/grid_map.h>
#include <asf/key_spec.h>
#include <asf/params.h>

#include <Eigen/Core>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::obs {
class CObservation;
class CObservation2DRangeScan;
}

namespace asf::mapping {

struct Map3dStats {
  std::size_t occupied_leaves = 0;  ///< leaves with occupancy >= 0.5 (OctoMap's threshold)
  std::size_t free_leaves = 0;
  std::size_t occupied_voxels = 0;  ///< at `resolution` (a pruned leaf counts its voxels)
  std::size_t free_voxels = 0;
  std::size_t memory_bytes = 0;     ///< OcTree::memoryUsage()
  double known_volume_m3 = 0;       ///< volume of all leaves (occupied + free)
  double resolution = 0;
  std::size_t keyframes = 0;
  std::size_t clouds_inserted = 0;  ///< into the current tree (keyframes or not)
  std::size_t points_inserted = 0;  ///< points given to OctoMap (after filtering)
  std::size_t points_dropped = 0;   ///< non-finite, at the origin, or closer than min_range
  std::size_t rebuilds = 0;         ///< completed rebuilds
  /// Every field above plus bytes_per_known_m3, as a JSON object (the "stats" of
  /// map3d.json, whoever writes it).
  std::string toJson() const;
};

/// A virtual planar laser made from 3D points (what ROS' pointcloud_to_laserscan does), so
/// a robot with only a 3D sensor feeds the 2D ICP front-end.
struct SliceOptions {
  double min_z = 0.1, max_z = 1.0;  ///< height band, metres above the robot base
  int rays = 720;                   ///< over 360 degrees
  double max_range = 30.0;          ///< farther points are left out [m]
};

/// The 2D scan of the points of `obs` (see Map3d::observationPoints) whose height in the
/// robot frame lies in [min_z, max_z]: one ray per bearing bin around the sensor's (x, y) on
/// the robot, the nearest point of the bin (horizontal distance), invalid when the bin has
/// none. The scan is planar at the band's middle height, sensorPose (x, y, z_mid, 0, 0, 0),
/// aperture 2 pi (rays - 1) / rays, rightToLeft (ray i at bearing -pi + pi/rays + i 2pi/rays),
/// label "<label>_SLICE", the observation's timestamp. Null (and `why`) for an observation
/// without 3D points.
std::shared_ptr<mrpt::obs::CObservation2DRangeScan> horizontalSlice(
    const mrpt::obs::CObservation& obs, const SliceOptions& o, std::string* why = nullptr);

class Map3d {
 public:
  using KeyframeId = std::uint64_t;

  /// INI keys of the [map3d] section.
  static const KeySpec* keys(std::size_t& n);

  Map3d();
  ~Map3d();
  Map3d(const Map3d&) = delete;
  Map3d& operator=(const Map3d&) = delete;

  /// Applies the [map3d] keys and clears the map and the keyframes. Cross-key errors
  /// (min_height >= max_height, clamping_thres_min >= clamping_thres_max) throw ConfigError
  /// naming the key. Without configure() the defaults apply.
  void configure(const Params& p);

  /// Inserts a cloud given in the sensor frame, the sensor at `sensor_pose_in_map`.
  /// Returns the number of points given to OctoMap (after filtering).
  std::size_t insertPoints(const std::vector<Eigen::Vector3f>& points_in_sensor_frame,
                           const mrpt::poses::CPose3D& sensor_pose_in_map);

  /// The 3D points of a supported observation, in its sensor frame, and the sensor's pose on
  /// the robot: CObservationPointCloud, CObservationVelodyneScan (its point_cloud, generated
  /// with MRPT's defaults when empty), CObservation3DRangeScan (points3D, or the range image
  /// unprojected), CObservation2DRangeScan (valid ranges in the scan plane; tilted by its
  /// sensorPose), CObservationRotatingScan of one ring (a planar scan). Returns false and
  /// says why for anything else; a CObservationRotatingScan of several rings is unsupported:
  /// MRPT 2.5 stores no ring elevation angles in it, so it has no 3D points.
  static bool observationPoints(const mrpt::obs::CObservation& obs,
                                std::vector<Eigen::Vector3f>& points_in_sensor_frame,
                                mrpt::poses::CPose3D& sensor_on_robot, std::string* why = nullptr);

  /// observationPoints() inserted at robot_pose (+ the sensor's pose on the robot). Returns
  /// the points inserted; throws asf::InputError for an unsupported observation class.
  std::size_t insertObservation(const mrpt::obs::CObservation& obs,
                                const mrpt::poses::CPose2D& robot_pose);

  // ------------------------------------------------------------------- keyframes

  /// Stores a keyframe (its points are kept for rebuilds) and inserts it at robot_pose.
  /// Throws asf::Error if `id` was already added.
  void addKeyframe(KeyframeId id, const mrpt::poses::CPose2D& robot_pose,
                   const mrpt::poses::CPose3D& sensor_on_robot,
                   std::vector<Eigen::Vector3f> points_in_sensor_frame);
  /// Same with the points of an observation (InputError if unsupported).
  void addKeyframe(KeyframeId id, const mrpt::poses::CPose2D& robot_pose,
                   const mrpt::obs::CObservation& obs);

  /// New poses for keyframes (ids not added are ignored). A keyframe counts as moved when its
  /// pose differs from the one it was inserted at by more than rebuild_threshold (metres, or
  /// radians x 1 m); any move starts a rebuild (or restarts one whose re-inserted keyframes
  /// moved again). Returns the number of moved keyframes.
  std::size_t updateKeyframePoses(const std::map<KeyframeId, mrpt::poses::CPose2D>& poses);

  /// Advances a pending rebuild by at most max_keyframes_per_update keyframes; when the last
  /// one is in, the rebuilt tree replaces the current one. Returns the keyframes re-inserted
  /// by this call (0 when there is no rebuild).
  std::size_t rebuildStep();
  bool rebuilding() const;
  /// Keyframes still to re-insert before the rebuild completes.
  std::size_t rebuildPending() const;
  std::size_t numKeyframes() const;

  // ------------------------------------------------------------------- outputs

  /// The 2D projection (MRPT convention: cell value = p(free)) at project_resolution. Per
  /// column (x, y), over the voxels whose centre is strictly inside (min_height, max_height)
  /// (a pruned leaf when one of its voxels is; the floor voxel [0, resolution) stays out
  /// while resolution <= 2 min_height):
  /// occupied if one has occupancy >= 0.5 + unknown_band (p(free) = 1 - the largest such
  /// occupancy), else free if one has occupancy <= 0.5 - unknown_band (p(free) = 1 - the
  /// largest such occupancy, the least sure free voxel), else unknown (0.5). The grid spans
  /// the octree's x-y bounds; an empty octree gives a GridMap without grid (version 0).
  /// version = version(); rebuilt = the tree came from a rebuild since the previous
  /// project() (or since configure()); changed = the whole grid.
  GridMap project();

  /// OctoMap binary (.bt: maximum likelihood free/occupied, what octovis shows) and full
  /// (.ot: occupancy probabilities). Written to PATH.tmp, then renamed. asf::Error on failure.
  void writeBt(const std::string& path) const;
  void writeOt(const std::string& path) const;

  Map3dStats stats() const;
  /// Incremented on every change of the current tree.
  std::uint64_t version() const;
  double resolution() const;

  /// Occupied leaves of the current tree as OctoMap keys packed into 64 bits (16 bits per
  /// axis, a pruned leaf expanded to its voxels), sorted: for comparing trees in tests.
  std::vector<std::uint64_t> occupiedVoxelKeys() const;
  /// Occupancy probability at a map point: -1 when unknown.
  double occupancyAt(double x, double y, double z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf::mapping
