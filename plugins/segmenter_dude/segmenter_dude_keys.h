#pragma once
// The dude segmenter's INI keys: its ASF_PLUGIN table (segmenter_dude.cpp), in a file of its
// own for length. Included once, by segmenter_dude.cpp.
#include <asf/key_spec.h>

namespace {

const asf::KeySpec kKeys[] = {
    asf::keyEnum("variant", "rooms", "rooms|thesis",
                 "thesis: DuDe as published and as the thesis ran it (the reference's pocket "
                 "minima, Delaunay diagonals, cut sets and knapsack selection; no "
                 "post-processing); rooms: asf's heuristic cuts plus the room layer (README)"),
    asf::keyDouble("max_concavity", "2.5",
                   "DuDe's one parameter: boundary points deeper than this below the convex "
                   "hull (through the bridge hierarchy) are resolved by cuts [m]",
                   0.01, 1e6),
    asf::keyEnum("approximation", "chains", "chains|douglas_peucker",
                 "variant = thesis: how boundary chains are simplified into feature points: "
                 "the reference's default (chains grown around the farthest vertices) or its "
                 "Douglas-Peucker option"),
    asf::keyDouble("free_threshold", "0.4",
                   "A cell is free when its occupancy probability (1 - MRPT cell value) is below this",
                   0.0, 1.0),
    asf::keyDouble("occupied_threshold", "0.6",
                   "A cell is an obstacle (grown by obstacle_dilation) when its occupancy "
                   "probability is above this; cells in between are unknown, never free",
                   0.0, 1.0),
    asf::keyDouble("gap_closing", "0.1",
                   "Gaps between obstacles narrower than this (cracks in walls) are closed "
                   "before the contours are traced (closing of the obstacle mask) [m]",
                   0.0, 10.0),
    asf::keyDouble("obstacle_dilation", "0.0",
                   "Obstacles grown by this before the contours are traced [m]; the cells "
                   "given up still get the label of the nearest region",
                   0.0, 10.0),
    asf::keyDouble("simplify_tolerance", "0.1",
                   "Douglas-Peucker tolerance of the contours [m]; 0 keeps every contour vertex",
                   0.0, 10.0),
    asf::keyDouble("min_hole_extent", "-1",
                   "Holes (obstacles inside free space) narrower than this are not cut to and "
                   "stay inside one region [m]; < 0: max_concavity",
                   -1.0, 1e6),
    asf::keyDouble("resolve_radius", "0.5",
                   "Pocket minima this close to a chosen cut's ends wait for the next round "
                   "(no parallel cuts a wall's width apart) [m]",
                   0.0, 1e6),
    asf::keyDouble("min_region_area", "1.0",
                   "Pieces smaller than this join the neighbour they share most border with [m^2]",
                   0.0, 1e9),
    asf::keyDouble("min_component_area", "0.25",
                   "Free components smaller than this are left unlabelled [m^2]", 0.0, 1e9),
    asf::keyDouble("merge_concavity", "1.0",
                   "Room layer: neighbouring pieces whose union has no reflex vertex deeper "
                   "than this are merged [m]; 0: off",
                   0.0, 1e6),
    asf::keyDouble("merge_min_border", "1.2",
                   "Room layer: only pieces sharing at least this much border are merge "
                   "candidates (a doorway is narrower) [m]",
                   0.0, 1e6),
    asf::keyBool("incremental", "true",
                 "Re-decompose only the regions touching changed free space (thesis Algorithm "
                 "3)"),
    asf::keyEnum("change_rule", "asf", "asf|reference",
                 "Incremental mode: which new free space re-decomposes regions. asf: any cell "
                 "whose free state changed, in either direction, and the regions it touches; "
                 "reference: the thesis author's code (README): only free space outside the "
                 "regions, in blobs larger than a square of new_space_side touching a region"),
    asf::keyDouble("new_space_side", "0.5",
                   "change_rule = reference: blobs of new free space whose outline encloses no "
                   "more than (new_space_side / resolution, rounded down)^2 cells are dropped "
                   "(the author's safety distance) [m]",
                   0.0, 100.0),
    asf::keyDouble("rebuild_full_fraction", "0.25",
                   "After a rebuilt map (a loop closure moved keyframes) the update stays "
                   "incremental unless more than this fraction of the free cells changed "
                   "state; 0: always segment a rebuilt map in full",
                   0.0, 1.0),
    asf::keyInt("max_cells", "100000000",
                "Largest map segmented (cells; about 12 bytes each while segmenting): a larger "
                "one is an input error naming its size (1e8: 500 m x 500 m at 5 cm)",
                1, 2e9),
};

}  // namespace
