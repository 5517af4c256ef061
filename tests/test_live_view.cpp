// The live view (asf run --gui): its picture (renderLiveView) on a hand-made map, and the
// window under Xvfb, where the run's last picture is found pixel for pixel in a screenshot of
// the X server's framebuffer (Xvfb -fbdir: an XWD file, read here by hand).
#include <asf/evaluation/map_views.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using Grid = mrpt::maps::COccupancyGridMap2D;
constexpr double kRes = 0.05;

/// A 4 m x 3 m room: walls on the border, free inside.
asf::GridMap room() {
  auto g = std::make_shared<Grid>(0.0f, 4.0f, 0.0f, 3.0f, static_cast<float>(kRes));
  for (unsigned y = 0; y < g->getSizeY(); ++y)
    for (unsigned x = 0; x < g->getSizeX(); ++x) {
      const bool wall = x == 0 || y == 0 || x + 1 == g->getSizeX() || y + 1 == g->getSizeY();
      g->setCell(x, y, wall ? 0.05f : 0.95f);
    }
  asf::GridMap m;
  m.grid = g;
  m.version = 1;
  return m;
}

/// Whether a pixel within `r` of map point (x, y) has colour (b, g, r) (image y down).
bool colourNear(const asf::evaluation::ViewImage& v, double x, double y, int b, int g, int r_,
                int r = 1) {
  const int cx = static_cast<int>(x / kRes), cy = v.height - 1 - static_cast<int>(y / kRes);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const int px = cx + dx, py = cy + dy;
      if (px < 0 || py < 0 || px >= v.width || py >= v.height) continue;
      const unsigned char* p = &v.bgr[(static_cast<std::size_t>(py) * v.width + px) * 3];
      if (p[0] == b && p[1] == g && p[2] == r_) return true;
    }
  return false;
}

TEST(LiveView, PictureShowsTheMapThePoseGraphTheRobotAndItsGoal) {
  const asf::GridMap map = room();
  asf::PoseGraph graph;
  for (const auto& [x, y] : {std::pair{0.5, 0.5}, {1.5, 1.0}, {0.5, 1.5}})
    graph.addNode(mrpt::poses::CPose2D(x, y, 0));
  asf::PoseEdge e;
  e.from = 0, e.to = 1;
  graph.addEdge(e);
  e.from = 1, e.to = 2;
  graph.addEdge(e);
  e.from = 2, e.to = 0, e.kind = asf::EdgeKind::LoopClosure;
  graph.addEdge(e);
  const asf::Point2 goal{1.0, 2.5};
  const asf::evaluation::ViewImage v = asf::evaluation::renderLiveView(
      map, {}, {}, graph, {}, mrpt::poses::CPose2D(3.0, 1.5, 0), &goal, 0);
  ASSERT_EQ(v.width, 80);
  ASSERT_EQ(v.height, 60);
  ASSERT_EQ(v.bgr.size(), 80u * 60u * 3u);
  EXPECT_TRUE(colourNear(v, 3.0, 1.5, 0, 0, 220)) << "the robot, red";
  EXPECT_TRUE(colourNear(v, 1.0, 2.5, 0, 140, 0)) << "the goal, a green cross";
  EXPECT_TRUE(colourNear(v, 0.5, 1.0, 200, 0, 200)) << "the loop closure 2 -> 0, magenta";
  EXPECT_FALSE(colourNear(v, 1.0, 0.75, 200, 0, 200, 0)) << "an odometry edge is not magenta";
  const auto brightness = [&](int px, int py) {
    const unsigned char* p = &v.bgr[(static_cast<std::size_t>(py) * v.width + px) * 3];
    return p[0] + p[1] + p[2];
  };
  EXPECT_LT(brightness(0, v.height - 1) + 300, brightness(60, v.height - 6))
      << "a wall cell is darker than a free one";
  // Scaled down to max_side; nothing without a grid.
  const asf::evaluation::ViewImage small =
      asf::evaluation::renderLiveView(map, {}, {}, graph, {}, {}, nullptr, 40);
  EXPECT_EQ(small.width, 40);
  EXPECT_EQ(small.height, 30);
  EXPECT_TRUE(asf::evaluation::renderLiveView({}, {}, {}, graph, {}, {}, nullptr, 40).bgr.empty());
}

TEST(LiveView, WithoutADisplayGuiIsAClearErrorAndWritesNothing) {
  const fs::path out = fs::temp_directory_path() / "asf_test_live_view_no_display";
  fs::remove_all(out);
  const asf_test::HostResult r = asf_test::runHost(
      "run " ASF_TEST_SOURCE_DIR "/configs/default.ini --set pipeline.max_steps=10 --gui --out " +
          out.string(),
      true, "env -u DISPLAY ");
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--gui: no display (DISPLAY is not set)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out)) << "nothing written";
  const asf_test::HostResult bad = asf_test::runHost(
      "run " ASF_TEST_SOURCE_DIR "/configs/default.ini --gui --gui-refresh 0 --out " +
      out.string());
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("--gui-refresh 0"), std::string::npos) << bad.out;
}

/// An XWD file (X Window Dump, as Xvfb -fbdir keeps its screen) as BGR rows, 24/32 bits per
/// pixel, either byte order. Empty when it cannot be read.
cv::Mat readXwd(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), {});
  const auto u32 = [&](std::size_t field) {
    const std::size_t o = 4 * field;
    return o + 4 > b.size() ? 0u
                            : (unsigned(b[o]) << 24 | unsigned(b[o + 1]) << 16 |
                               unsigned(b[o + 2]) << 8 | unsigned(b[o + 3]));
  };
  const unsigned header = u32(0), width = u32(4), height = u32(5), byte_order = u32(7);
  const unsigned bpp = u32(11), bpl = u32(12), red = u32(14), green = u32(15), blue = u32(16);
  const unsigned ncolors = u32(19);
  const std::size_t data = header + 12ull * ncolors;
  if (u32(1) != 7 || (bpp != 32 && bpp != 24) || data + std::size_t(bpl) * height > b.size())
    return {};
  const auto shift = [](unsigned mask) {
    int s = 0;
    while (mask && !(mask & 1)) mask >>= 1, ++s;
    return s;
  };
  cv::Mat out(static_cast<int>(height), static_cast<int>(width), CV_8UC3);
  for (unsigned y = 0; y < height; ++y)
    for (unsigned x = 0; x < width; ++x) {
      const unsigned char* p = &b[data + std::size_t(y) * bpl + x * (bpp / 8)];
      unsigned v = 0;
      for (unsigned k = 0; k < bpp / 8; ++k)
        v |= unsigned(p[k]) << (byte_order == 0 ? 8 * k : 8 * (bpp / 8 - 1 - k));
      out.at<cv::Vec3b>(y, x) = {static_cast<unsigned char>((v & blue) >> shift(blue)),
                                 static_cast<unsigned char>((v & green) >> shift(green)),
                                 static_cast<unsigned char>((v & red) >> shift(red))};
    }
  return out;
}

/// Where `needle` appears in `hay` with every pixel equal; (-1, -1) if nowhere.
cv::Point find(const cv::Mat& hay, const cv::Mat& needle) {
  for (int y = 0; y + needle.rows <= hay.rows; ++y)
    for (int x = 0; x + needle.cols <= hay.cols; ++x) {
      if (hay.at<cv::Vec3b>(y, x) != needle.at<cv::Vec3b>(0, 0)) continue;
      bool all = true;
      for (int r = 0; r < needle.rows && all; ++r)
        all = std::equal(needle.ptr<cv::Vec3b>(r), needle.ptr<cv::Vec3b>(r) + needle.cols,
                         hay.ptr<cv::Vec3b>(y + r) + x);
      if (all) return {x, y};
    }
  return {-1, -1};
}

/// The path of an executable on PATH, or "".
std::string which(const std::string& name) {
  const asf_test::HostResult r = asf_test::runCommand("command -v " + name + " 2>/dev/null");
  std::string p = r.out;
  while (!p.empty() && (p.back() == '\n' || p.back() == ' ')) p.pop_back();
  return r.code == 0 ? p : "";
}

TEST(LiveView, WindowShowsTheRunsLastPictureUnderXvfb) {
  std::string xvfb = which("Xvfb");
  if (xvfb.empty()) {  // the project's install script, as for the other test tools
    asf_test::runCommand("bash " ASF_TEST_SOURCE_DIR "/scripts/install-deps.sh xvfb 2>&1");
    xvfb = which("Xvfb");
  }
  if (xvfb.empty()) GTEST_SKIP() << "Xvfb is not installed and could not be (apt-get xvfb)";
  const fs::path dir = fs::temp_directory_path() / "asf_test_live_view";
  fs::remove_all(dir);
  fs::create_directories(dir / "fb");
  int display = 60 + static_cast<int>(getpid() % 300);
  while (fs::exists("/tmp/.X11-unix/X" + std::to_string(display))) ++display;
  const std::string d = ":" + std::to_string(display);
  const pid_t server = fork();
  if (server == 0) {
    const std::string fb = (dir / "fb").string();
    execl(xvfb.c_str(), "Xvfb", d.c_str(), "-screen", "0", "1280x1024x24", "-fbdir", fb.c_str(),
          "-nolisten", "tcp", static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(server, 0);
  const fs::path screen = dir / "fb" / "Xvfb_screen0";
  for (int i = 0; i < 100 && !fs::exists("/tmp/.X11-unix/X" + std::to_string(display)); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  setenv("DISPLAY", d.c_str(), 1);
  const fs::path out = dir / "run";
  const pid_t run = asf_test::spawnHost(
      {"run", ASF_TEST_SOURCE_DIR "/configs/default.ini", "--set", "pipeline.max_steps=400",
       "--set", "pipeline.timeline=false", "--gui", "--gui-hold", "4", "--out", out.string()},
      (dir / "run.log").string());
  unsetenv("DISPLAY");
  ASSERT_GT(run, 0);
  // live_view.png is written when the last picture has gone to the window; let it paint.
  for (int i = 0; i < 600 && !fs::exists(out / "live_view.png"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const cv::Mat shot = readXwd(screen);
  int status = 0;
  waitpid(run, &status, 0);
  kill(server, SIGTERM);
  waitpid(server, nullptr, 0);
  std::ifstream log(dir / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  ASSERT_TRUE(fs::exists(out / "live_view.png")) << text;
  ASSERT_FALSE(shot.empty()) << screen << " unreadable";
  const cv::Mat last = cv::imread((out / "live_view.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(last.empty());
  EXPECT_GT(last.cols, 100);
  const cv::Point at = find(shot, last);
  EXPECT_GE(at.x, 0) << "the run's last picture (" << last.cols << " x " << last.rows
                     << ") is not on the screen; run.log:\n"
                     << text;
  fs::remove_all(dir);
}

}  // namespace
