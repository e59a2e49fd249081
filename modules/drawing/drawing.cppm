// rocking.drawing: where the parts of a rocking structure are, in the ground's
// frame, for animations. Pure geometry: it reads the models' data and computes
// no dynamics. SI units.
// - A single body (MODEL.md 2 and 5): the body rotates by theta about the
//   active pivot (x = sB, y = 0; theta > 0 tips it to the right, about the
//   right pivot); the elastic displacements u act along the body's own x axis
//   and are drawn multiplied by an exaggeration factor. The damper of the
//   lifted edge joins its ground anchor (the corner at rest) to the lifted
//   corner, whose distance is the chord 4B sin(|theta|/2) of MODEL.md 5.
// - A structure on rocking columns (MODEL.md 16): every column, a rectangle
//   2b wide and 2h tall, turns by theta about its bottom corner on side
//   s = sign(theta); the cap beam rests on the top corners opposite the pivots
//   and translates by rocking.columns' beam_motion without turning; the
//   structure stands on the beam, never tilts, and its u are relative to it.
// - A chain of segments (MODEL.md 15): segment j turns by theta_j, relative
//   to the face below, about that face's corner on side sign(theta_j) (its
//   absolute rotation is the sum of theta_0..theta_j); the face below is the
//   top of segment j-1 as that segment is drawn, rigid (a run reports no
//   segment's elastic displacements to observers). A tendon runs from its
//   anchor to its end on its segment.
module;
#include <rocking/eigen.hpp>
#include <array>
#include <span>
#include <utility>
#include <vector>
export module rocking.drawing;
export import rocking.geometry;
export import rocking.columns;
export import rocking.chain;

export namespace rocking {

using Point = std::pair<double, double>;  // (x, y) [m]

struct Outline {
  std::vector<Point> axis;   // node 0 (base centre) to node N
  Point left_corner, right_corner;
  Point damper_anchor, damper_end;  // equal when no edge is lifted
};

// theta is ignored in full contact.
Outline outline(const Structure& s, Phase phase, double theta, const Eigen::VectorXd& u, double exaggeration);

// A structure on rocking columns at the columns' angle theta (0: at rest).
struct ColumnsOutline {
  // Per column (in the order of Columns::axes, left to right): its corners,
  // bottom left, bottom right, top right, top left.
  std::vector<std::array<Point, 4>> columns;
  // The beam's underside, from the outer left column's top left corner to
  // the outer right column's top right corner as they are at rest, moved by
  // the beam's translation.
  Point beam_left, beam_right;
  Point beam_shift;          // (dx, dy) of beam_motion (0 at rest)
  std::vector<Point> axis;   // the beam's centre (node 0) to node N, u times the exaggeration
};
ColumnsOutline columns_outline(const Columns& c, double theta, const Eigen::VectorXd& u, double exaggeration);

// One segment of a chain drawn: its slab's ends (base_left, base_right at
// -B_j and +B_j of its joint), its top corners at the same half-width, its
// slab's centre and nodes on its centre line, and its absolute rotation.
struct SegmentOutline {
  Point base_left, base_right, top_right, top_left;
  std::vector<Point> axis;  // the slab's centre, then each node
  double angle = 0;         // theta_0 + ... + theta_j [rad]
};
struct ChainOutline {
  std::vector<SegmentOutline> segments;             // from the ground up
  std::vector<std::pair<Point, Point>> tendons;     // per tendon: from, to (ChainData::tendons' order)
};
// thetas: one per segment (missing ones are 0). A segment's top is the next
// one's base height, and the last segment's the top of its slices when its
// nodes are the middles of equal slices (a rigid block's lumped masses),
// else its last node (segment_top).
ChainOutline chain_outline(const ChainData& d, std::span<const double> thetas);
// Where a point of segment j (x from the centre line, z its height at rest,
// both in the ground's frame at rest) is drawn at those angles; j = -1: the
// ground, where it stays.
Point chain_point(const ChainData& d, std::span<const double> thetas, int segment, double x, double z);
// The height of a segment's top at rest [m].
double segment_top(const ChainData& d, int segment);

}  // namespace rocking
