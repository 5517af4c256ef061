#pragma once
/// \file region_labels.h
/// From a label image to regions: the common last step of raster segmenters (runtime
/// library; the Segmentation type itself is part of the plugin contract, segmentation.h).
#include <asf/segmentation.h>

#include <cstdint>

namespace asf::mapping {

/// Turns a label image with provisional labels (any values > 0, 0 = no region) into a
/// Segmentation, the common last step of raster segmenters:
/// - regions smaller than `min_area` [m^2] are dropped (their cells become 0);
/// - ids are reused from `previous` (may be null) by largest overlap, greedily, each id at
///   most once; the others get fresh ids above `*max_issued` and every id of `previous`, and
///   `*max_issued` is updated (so an id is never reissued by the same segmenter);
/// - area, centroid and boundary (outer counter-clockwise, holes clockwise, through the
///   centres of the border cells) are computed per region; regions are sorted by id.
/// `labels` must have width * height entries; cells of one provisional label need not be
/// connected (a region's outer boundary is then that of its largest piece).
/// `boxes` (may be null) receives the cell bounding box of every region.
Segmentation regionsFromLabels(LabelImage labels, const Segmentation* previous,
                               RegionId* max_issued, std::uint64_t map_version, double min_area = 0,
                               RegionBoxes* boxes = nullptr);

/// The same result as regionsFromLabels(labels, &previous, max_issued, map_version,
/// min_area, &boxes), in time proportional to `window` and the regions with cells in it
/// rather than to the image, for an update that only changed the cells inside `window`.
/// Preconditions: outside `window`, `labels` holds exactly previous.labels (a provisional
/// label there is the previous region's id; fresh labels are not ids of `previous` and lie
/// inside the window), and `boxes` holds the cell boxes of previous' regions (as filled by
/// either function); on return it holds those of the result. When the rasters differ or a
/// box is missing, it falls back to regionsFromLabels.
Segmentation regionsFromLabelsInWindow(LabelImage labels, const Segmentation& previous,
                                       RegionBoxes& boxes, CellBox window, RegionId* max_issued,
                                       std::uint64_t map_version, double min_area = 0);

}  // namespace asf::mapping
