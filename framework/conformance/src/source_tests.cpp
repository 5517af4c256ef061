/// \file source_tests.cpp
/// Conformance tests of `source` plugins (see source.h).
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <limits>
#include <optional>

#include "kit.h"

namespace asf::conformance::detail {

using mrpt::poses::CPose2D;

namespace {

constexpr int kMaxFrames = 200;     ///< frames read by the stream tests
constexpr int kStandardFrames = 50;  ///< frames of the standard run

bool finitePose(const CPose2D& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

void record(Trace& tr, const std::string& l, const SensorFrame& f) {
  tr.num(l + ".timestamp", f.timestamp);
  tr.pose(l + ".odometry", f.odometry);
  tr.mat(l + ".odometry_cov", f.odometry_cov);
  tr.num(l + ".has_ground_truth", f.ground_truth.has_value());
  if (f.ground_truth) tr.pose(l + ".ground_truth", *f.ground_truth);
  tr.num(l + ".has_scan", f.scan != nullptr);
  if (!f.scan) return;
  const auto& s = *f.scan;
  tr.num(l + ".scan.size", static_cast<double>(s.getScanSize()));
  tr.num(l + ".scan.aperture", s.aperture);
  tr.num(l + ".scan.max_range", s.maxRange);
  tr.num(l + ".scan.right_to_left", s.rightToLeft);
  tr.num(l + ".scan.sensor_x", s.sensorPose.x());
  tr.num(l + ".scan.sensor_y", s.sensorPose.y());
  tr.num(l + ".scan.sensor_yaw", s.sensorPose.yaw());
  for (std::size_t i = 0; i < s.getScanSize(); ++i) {
    tr.num(l + ".scan.range[" + std::to_string(i) + "]", s.getScanRange(i));
    tr.num(l + ".scan.valid[" + std::to_string(i) + "]", s.getScanRangeValidity(i));
  }
}

/// Checks one frame; returns false (after reporting) when something is wrong.
bool checkFrame(int k, const SensorFrame& f, double prev_timestamp) {
  const std::string at = "frame " + std::to_string(k) + ": ";
  bool ok = true;
  const auto bad = [&]() -> testing::Message {
    ok = false;
    return testing::Message() << at;
  };
  if (!std::isfinite(f.timestamp)) ADD_FAILURE() << bad() << "timestamp is not finite";
  if (k > 0 && f.timestamp < prev_timestamp)
    ADD_FAILURE() << bad() << "timestamp " << f.timestamp << " < previous " << prev_timestamp;
  if (!finitePose(f.odometry)) ADD_FAILURE() << bad() << "odometry is not finite: " << f.odometry;
  if (auto r = isSymmetricPsd(f.odometry_cov); !r)
    ADD_FAILURE() << bad() << "odometry_cov: " << r.message();
  if (f.ground_truth && !finitePose(*f.ground_truth))
    ADD_FAILURE() << bad() << "ground_truth is not finite";
  if (f.scan) {
    const auto& s = *f.scan;
    if (s.getScanSize() == 0) ADD_FAILURE() << bad() << "scan has no rays";
    if (!(std::isfinite(s.maxRange) && s.maxRange > 0))
      ADD_FAILURE() << bad() << "scan maxRange " << s.maxRange << " is not finite and > 0";
    if (!(std::isfinite(s.aperture) && s.aperture > 0 && s.aperture <= 2 * M_PI + 1e-4))
      ADD_FAILURE() << bad() << "scan aperture " << s.aperture << " is not in (0, 2 pi]";
    const double limit = static_cast<double>(s.maxRange) * (1 + 1e-6);
    for (std::size_t i = 0; i < s.getScanSize(); ++i) {
      const float r = s.getScanRange(i);
      if (std::isnan(r)) {
        ADD_FAILURE() << bad() << "range " << i << " is NaN";
        break;
      }
      if (!s.getScanRangeValidity(i)) continue;
      if (!(std::isfinite(r) && r >= 0 && r <= limit)) {
        ADD_FAILURE() << bad() << "valid range " << i << " = " << r << " is not in [0, maxRange="
                      << s.maxRange << "]";
        break;
      }
    }
  }
  return ok;
}

}  // namespace

Trace standardRun(Source& p) {
  Trace tr;
  CPose2D estimate;  // map frame = first pose: composition of the odometry since
  for (int k = 0; k < kStandardFrames; ++k) {
    std::optional<SensorFrame> f = p.next();
    if (!f) {
      tr.text("end", "nullopt at frame " + std::to_string(k));
      break;
    }
    const std::string l = "frame[" + std::to_string(k) + "]";
    if (k > 0) estimate = estimate + f->odometry;
    record(tr, l, *f);
    if (!p.isActive()) continue;
    if (k == 0) {
      NavigationContext ctx;
      ctx.robot_estimate = estimate;
      Goal g;
      const CPose2D ahead = estimate + CPose2D(1.0, 0, 0);
      g.x = ahead.x();
      g.y = ahead.y();
      tr.num("navigate", static_cast<int>(p.navigate(g, ctx)));
    }
    tr.num(l + ".status", static_cast<int>(p.status()));
  }
  return tr;
}

void registerSourceTests(const InfoPtr& info) {
  using T = Source;

  addTest<T>(info, "frames_have_ordered_timestamps_finite_odometry_psd_covariance_valid_scans",
             Needs::Instance, [](KindTest<T>& t) {
               auto h = t.make();
               double prev = -std::numeric_limits<double>::infinity();
               int n = 0;
               for (int k = 0; k < kMaxFrames; ++k) {
                 std::optional<SensorFrame> f = h->next();
                 if (!f) break;
                 ++n;
                 if (!checkFrame(k, *f, prev)) return;  // the first bad frame is enough
                 prev = f->timestamp;
               }
               if (n == 0) GTEST_SKIP() << "the source produced no frame with its defaults";
             });

  addTest<T>(info, "stream_end_is_sticky", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    int k = 0;
    for (; k < kMaxFrames; ++k)
      if (!h->next()) break;
    if (k == kMaxFrames)
      GTEST_SKIP() << "the source did not end within " << kMaxFrames
                   << " frames (fine: not checked)";
    EXPECT_FALSE(h->next().has_value()) << "next() returned a frame after std::nullopt";
    EXPECT_FALSE(h->next().has_value()) << "next() returned a frame after std::nullopt (twice)";
  });

  addTest<T>(info, "navigate_follows_active_or_passive_contract", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               std::optional<SensorFrame> f = h->next();
               if (!f) GTEST_SKIP() << "the source produced no frame with its defaults";
               NavigationContext ctx;  // estimate at the map origin (the first pose)
               Goal g;
               g.x = 1.0;
               g.y = 0.0;
               const NavStatus s = h->navigate(g, ctx);
               if (!h->isActive()) {
                 EXPECT_EQ(s, NavStatus::Unreachable)
                     << "a passive source must answer navigate() with Unreachable, not "
                     << navStatusName(s);
                 return;
               }
               EXPECT_TRUE(s == NavStatus::Moving || s == NavStatus::Reached ||
                           s == NavStatus::Unreachable)
                   << "navigate() must return Moving, Reached or Unreachable, not "
                   << navStatusName(s);
               int frames = 0;
               for (; frames < 5; ++frames)
                 if (!h->next()) break;
               if (frames == 0) return;  // ended right away: nothing to check
               const NavStatus st = h->status();
               EXPECT_NE(st, NavStatus::Idle)
                   << "status() is Idle after " << frames << " frames with a goal";
             });

  // The run calls it once, its destructor may call it again: the second call changes nothing.
  addTest<T>(info, "end_recording_after_frames_twice_without_error", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               for (int k = 0; k < 3; ++k)
                 if (!h->next()) break;
               EXPECT_NO_THROW(h->endRecording()) << "endRecording() after frames";
               EXPECT_NO_THROW(h->endRecording()) << "endRecording() a second time";
             });
}

}  // namespace asf::conformance::detail
