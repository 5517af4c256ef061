// End to end: a simulated run (sim2d) records a rawlog and a ground-truth file; replaying
// them through the `rawlog` source gives the pipeline the same stream, so the same
// trajectory.
#include <asf/framework/pipeline.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_replay_" + name);
  fs::remove_all(d);
  return d;
}

asf::framework::RunSummary runIni(const std::string& text, const fs::path& out) {
  asf::framework::Registry reg;
  const auto rc = asf::framework::resolveConfig(asf::IniConfig::fromText(text, "test.ini"), reg);
  asf::framework::Pipeline p(rc, out.string());
  return p.run();
}

std::vector<std::vector<double>> readCsv(const fs::path& f) {
  std::ifstream in(f);
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST(Replay, RecordedSimulationReplaysToTheSameTrajectory) {
  const fs::path sim = tempDir("sim"), replay = tempDir("replay");
  const auto s1 = runIni(R"(
[pipeline]
source = sim2d
frontend = odometry
policy = waypoints
seed = 3
[sim2d]
room_width = 8
room_height = 6
laser_rays = 181
laser_rate = 5
[waypoints]
waypoints = 5 0; 5 3; 0 3; 0 0
)",
                         sim);
  ASSERT_TRUE(s1.finished) << s1.stop_reason;
  ASSERT_TRUE(fs::exists(sim / "sim2d.rawlog"));
  const auto s2 = runIni("[pipeline]\nsource = rawlog\nfrontend = odometry\n[rawlog]\nfile = " +
                             (sim / "sim2d.rawlog").string() +
                             "\nground_truth = " + (sim / "sim2d.gt.txt").string() + "\n",
                         replay);
  EXPECT_TRUE(s2.finished) << s2.stop_reason;
  EXPECT_EQ(s2.steps, s1.steps);
  EXPECT_EQ(s2.nodes, s1.nodes);
  const auto a = readCsv(sim / "trajectory.csv"), b = readCsv(replay / "trajectory.csv");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 100u);
  // Columns: step,time_s,x,y,phi,gt_x,gt_y,gt_phi,pose_error_m,nodes,edges,distance_m.
  for (std::size_t r = 0; r < a.size(); ++r) {
    ASSERT_EQ(a[r].size(), b[r].size());
    for (std::size_t c = 0; c < 5; ++c) ASSERT_EQ(a[r][c], b[r][c]) << "row " << r << " col " << c;
    // Ground truth went through a text file with nine decimals.
    for (std::size_t c = 5; c < a[r].size(); ++c) {
      double d = a[r][c] - b[r][c];
      if (c == 7) d = std::remainder(d, 2 * M_PI);  // gt_phi: +pi and -pi are one heading
      ASSERT_NEAR(d, 0, 1e-6) << "row " << r << " col " << c;
    }
  }
}
