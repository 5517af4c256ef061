#pragma once
/// \file segmenter.h
/// `segmenter` plugins: occupancy grid -> regions of free space.
///
/// Contract:
/// - segment() labels free cells only; labels are aligned with the grid (same size, origin
///   and resolution); every label > 0 appears in `regions` and vice versa; region ids > 0.
/// - `previous` (may be null) is the segmentation of an earlier version of the same map; an
///   incremental segmenter keeps the ids of regions that did not change.
/// - A map without free cells yields no regions.
/// - A map larger than the segmenter can handle (a documented limit) throws asf::InputError
///   naming its size; it never crashes or exhausts memory.
#include <asf/grid_map.h>
#include <asf/plugin.h>
#include <asf/segmentation.h>

namespace asf {

class Segmenter : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Segmenter;
  PluginKind kind() const final { return kStaticKind; }
  ~Segmenter() override;

  virtual Segmentation segment(const GridMap& map, const Segmentation* previous) = 0;
};

}  // namespace asf
