/// \file segmenter_tests.cpp
/// Conformance tests of `segmenter` plugins (see segmenter.h), on grids built in code.
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <set>

#include "kit.h"
#include "synthetic.h"

namespace asf::conformance::detail {

namespace {

/// Free cells at least this many cells (Chebyshev) away from any non-free cell must be
/// labelled; cells nearer the walls are left to the segmenter (polygonal approximations).
constexpr int kInteriorMargin = 2;

std::vector<CellClass> classes(const mrpt::maps::COccupancyGridMap2D& g) {
  const int w = static_cast<int>(g.getSizeX()), h = static_cast<int>(g.getSizeY());
  std::vector<CellClass> c(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) c[static_cast<std::size_t>(y) * w + x] = classify(g.getCell(x, y));
  return c;
}

std::set<RegionId> regionIds(const Segmentation& s) {
  std::set<RegionId> ids;
  for (const auto& r : s.regions) ids.insert(r.id);
  return ids;
}

/// Checks the alignment of the label image with the grid.
void checkAlignment(const GridMap& map, const Segmentation& s) {
  const auto& g = *map.grid;
  const LabelImage& L = s.labels;
  EXPECT_EQ(L.width, static_cast<int>(g.getSizeX())) << "label image width != grid width";
  EXPECT_EQ(L.height, static_cast<int>(g.getSizeY())) << "label image height != grid height";
  EXPECT_EQ(L.labels.size(), static_cast<std::size_t>(std::max(L.width, 0)) *
                                 static_cast<std::size_t>(std::max(L.height, 0)))
      << "labels.size() != width * height";
  EXPECT_NEAR(L.resolution, g.getResolution(), 1e-6) << "label image resolution";
  EXPECT_NEAR(L.origin_x, g.getXMin(), 1e-6) << "label image origin_x != grid x_min";
  EXPECT_NEAR(L.origin_y, g.getYMin(), 1e-6) << "label image origin_y != grid y_min";
  EXPECT_EQ(s.map_version, map.version) << "Segmentation::map_version != GridMap::version";
}

/// Every contract check of one segmentation; returns the number of labelled cells.
void checkSegmentation(const GridMap& map, const Segmentation& s) {
  checkAlignment(map, s);
  if (testing::Test::HasFatalFailure()) return;
  const auto& g = *map.grid;
  const LabelImage& L = s.labels;
  if (L.labels.size() != static_cast<std::size_t>(g.getSizeX()) * g.getSizeY()) return;

  // Regions.
  std::set<RegionId> ids;
  for (const Region& r : s.regions) {
    EXPECT_GT(r.id, 0) << "region ids must be > 0";
    EXPECT_TRUE(ids.insert(r.id).second) << "region id " << r.id << " appears twice";
    EXPECT_TRUE(std::isfinite(r.area) && r.area > 0) << "region " << r.id << " area " << r.area;
    EXPECT_TRUE(std::isfinite(r.centroid.x) && std::isfinite(r.centroid.y) &&
                r.centroid.x >= g.getXMin() && r.centroid.x <= g.getXMax() &&
                r.centroid.y >= g.getYMin() && r.centroid.y <= g.getYMax())
        << "region " << r.id << " centroid (" << r.centroid.x << ", " << r.centroid.y
        << ") outside the grid";
    bool finite = true;
    for (const auto& p : r.outer) finite = finite && std::isfinite(p.x) && std::isfinite(p.y);
    for (const auto& h : r.holes)
      for (const auto& p : h) finite = finite && std::isfinite(p.x) && std::isfinite(p.y);
    EXPECT_TRUE(finite) << "region " << r.id << " has a non-finite polygon vertex";
  }

  // Cells.
  const auto cls = classes(g);
  const int w = L.width, h = L.height;
  std::set<RegionId> in_image;
  int bad_nonfree = 0, unlabelled_interior = 0, negative = 0;
  std::string first_nonfree, first_unlabelled;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const RegionId l = L.at(x, y);
      const CellClass c = cls[static_cast<std::size_t>(y) * w + x];
      if (l < 0) ++negative;
      if (l > 0) in_image.insert(l);
      if (c != CellClass::Free && l != 0) {
        if (bad_nonfree++ == 0)
          first_nonfree = "(" + std::to_string(x) + ", " + std::to_string(y) + ") is " +
                          (c == CellClass::Occupied ? "occupied" : "unknown") +
                          " but labelled " + std::to_string(l);
      }
      if (c == CellClass::Free && l <= 0) {
        bool interior = true;
        for (int dy = -kInteriorMargin; dy <= kInteriorMargin && interior; ++dy)
          for (int dx = -kInteriorMargin; dx <= kInteriorMargin && interior; ++dx) {
            const int xx = x + dx, yy = y + dy;
            interior = xx >= 0 && yy >= 0 && xx < w && yy < h &&
                       cls[static_cast<std::size_t>(yy) * w + xx] == CellClass::Free;
          }
        if (interior && unlabelled_interior++ == 0)
          first_unlabelled = "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
      }
    }
  EXPECT_EQ(negative, 0) << "labels must be >= 0 (0 = no region)";
  EXPECT_EQ(bad_nonfree, 0) << bad_nonfree << " occupied/unknown cells carry a region label, "
                            << "e.g. cell " << first_nonfree;
  EXPECT_EQ(unlabelled_interior, 0)
      << unlabelled_interior << " free cells (at least " << kInteriorMargin
      << " cells from any non-free cell) have no region, e.g. cell " << first_unlabelled;
  for (RegionId l : in_image)
    EXPECT_EQ(ids.count(l), 1u) << "label " << l << " is in the image but not in regions";
  for (RegionId r : ids)
    EXPECT_EQ(in_image.count(r), 1u) << "region " << r << " labels no cell of the image";
}

}  // namespace

Trace standardRun(Segmenter& p) {
  Trace tr;
  const GridMap map = makeTwoRoomsMap(true);
  const Segmentation s = p.segment(map, nullptr);
  tr.num("map_version", static_cast<double>(s.map_version));
  tr.num("regions", static_cast<double>(s.regions.size()));
  for (const Region& r : s.regions) {
    const std::string l = "region[" + std::to_string(r.id) + "]";
    tr.num(l + ".id", r.id);
    tr.num(l + ".area", r.area);
    tr.num(l + ".centroid.x", r.centroid.x);
    tr.num(l + ".centroid.y", r.centroid.y);
    tr.num(l + ".outer.size", static_cast<double>(r.outer.size()));
    for (const auto& q : r.outer) {
      tr.num(l + ".outer.x", q.x);
      tr.num(l + ".outer.y", q.y);
    }
    tr.num(l + ".holes", static_cast<double>(r.holes.size()));
  }
  tr.num("labels.width", s.labels.width);
  tr.num("labels.height", s.labels.height);
  for (std::size_t i = 0; i < s.labels.labels.size(); ++i)
    tr.num("label[" + std::to_string(i) + "]", s.labels.labels[i]);
  // The incremental path with the previous result.
  const Segmentation s2 = p.segment(map, &s);
  for (const Region& r : s2.regions) tr.num("again.region.id", r.id);
  return tr;
}

void registerSegmenterTests(const InfoPtr& info) {
  using T = Segmenter;

  addTest<T>(info, "maps_without_free_cells_give_no_regions", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               {
                 SCOPED_TRACE("all-unknown map");
                 const GridMap map = makeUnknownMap();
                 const Segmentation s = h->segment(map, nullptr);
                 EXPECT_TRUE(s.regions.empty()) << s.regions.size() << " regions";
                 checkSegmentation(map, s);
               }
               {
                 SCOPED_TRACE("all-occupied map");
                 auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(0.f, 3.f, 0.f,
                                                                               2.f, 0.05f);
                 grid->fill(kOccupied);
                 const GridMap map = wrapGrid(grid, 3);
                 const Segmentation s = h->segment(map, nullptr);
                 EXPECT_TRUE(s.regions.empty()) << s.regions.size() << " regions";
                 checkSegmentation(map, s);
               }
             });

  addTest<T>(info, "walled_free_rectangle_is_labelled_and_aligned", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const GridMap map = makeRoomMap();
               const Segmentation s = h->segment(map, nullptr);
               EXPECT_GE(s.regions.size(), 1u) << "a 3.8 m x 2.8 m free room gave no region";
               checkSegmentation(map, s);
             });

  addTest<T>(info, "two_rooms_map_is_labelled_and_aligned", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               for (bool right_known : {true, false}) {
                 SCOPED_TRACE(right_known ? "both rooms mapped" : "right room unknown");
                 const GridMap map = makeTwoRoomsMap(right_known);
                 const Segmentation s = h->segment(map, nullptr);
                 EXPECT_GE(s.regions.size(), 1u);
                 checkSegmentation(map, s);
               }
             });

  addTest<T>(info, "previous_output_on_same_map_keeps_region_ids", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const GridMap map = makeTwoRoomsMap(true);
               const Segmentation s1 = h->segment(map, nullptr);
               const Segmentation s2 = h->segment(map, &s1);
               checkSegmentation(map, s2);
               const auto a = regionIds(s1), b = regionIds(s2);
               EXPECT_EQ(a, b) << "segmenting the same map again with `previous` = the last "
                                  "output changed the set of region ids";
             });
}

}  // namespace asf::conformance::detail
