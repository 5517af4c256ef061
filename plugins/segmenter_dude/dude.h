#pragma once
/// \file dude.h
/// Dual-Space Decomposition (DuDe) of a polygon with holes into nearly convex pieces
/// (after Liu, Xi, Lien, "Dual-space decomposition of 2D complex shapes", CVPR 2014).
/// Pure geometry: no MRPT, no OpenCV; units are whatever the caller uses (metres here).
#include <string>
#include <utility>
#include <vector>

namespace asf::dude {

struct Vec2 {
  double x = 0, y = 0;
};

/// Closed ring, no repeated last vertex. Any orientation is accepted as input.
using Ring = std::vector<Vec2>;

/// A polygon with holes. Output pieces have `outer` counter-clockwise and holes clockwise.
struct Shape {
  Ring outer;
  std::vector<Ring> holes;
};

struct Options {
  /// tau: boundary points farther than this from the convex hull (through the hierarchy of
  /// bridges) must be resolved by a cut.
  double max_concavity = 2.5;
  /// Holes whose diameter is below this stay holes of a piece and are never cut to
  /// (< 0: max_concavity, as in the reference implementation).
  double min_hole_extent = -1;
  /// Other pocket minima closer than this to the ends of a chosen cut count as resolved in
  /// the same round (re-examined in the pieces): avoids parallel cuts a wall's width apart.
  double resolve_radius = 0.5;
  /// A cut resolves a pocket minimum when both angles it leaves there are below
  /// pi + this [rad] (tolerates noisy walls around doorways).
  double angle_tolerance = 0.3;
  /// Safety limits: a shape that reaches them is returned in its current pieces with a warning.
  int max_rounds = 200;
  int max_pieces = 20000;
};

struct Cut {
  Vec2 a, b;
};

struct Result {
  std::vector<Shape> pieces;
  std::vector<Cut> cuts;              ///< every applied cut (splits and hole bridges)
  std::vector<std::string> warnings;  ///< why a piece was returned undecomposed
};

/// Decomposes `shape` until no piece has a pocket minimum deeper than max_concavity.
/// Degenerate input (fewer than 3 distinct non-collinear vertices, zero area) gives no piece.
/// Deterministic; never throws on bad geometry (a piece that cannot be cut is kept whole and
/// a warning is added).
Result decompose(const Shape& shape, const Options& options);

/// Concavity of each vertex of a ring (counter-clockwise, cleaned): distance to the convex
/// hull through the hierarchy of bridges (pockets of pockets). Exposed for tests.
std::vector<double> concavities(const Ring& ccw_ring);

/// Largest concavity of a reflex vertex of the ring (counter-clockwise, cleaned): what
/// decides whether DuDe would cut it (> max_concavity) or keep it whole.
double maxReflexConcavity(const Ring& ccw_ring);

/// Signed area (> 0 counter-clockwise).
double signedArea(const Ring& r);

/// Removes repeated vertices, collinear vertices and zero-width spikes; returns the ring
/// counter-clockwise when ccw is true, clockwise otherwise. Empty when degenerate.
Ring cleanRing(const Ring& r, bool ccw, double eps = 1e-9);

}  // namespace asf::dude
