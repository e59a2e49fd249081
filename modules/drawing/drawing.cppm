// rocking.drawing: where the parts of a rocking structure are, in the ground's
// frame, for animations (MODEL.md 2 and 5). The body rotates by theta about
// the active pivot (x = sB, y = 0; theta > 0 tips it to the right, about the
// right pivot); the elastic displacements u act along the body's own x axis
// and are drawn multiplied by an exaggeration factor. The damper of the lifted
// edge joins its ground anchor (the corner at rest) to the lifted corner,
// whose distance is the chord 4B sin(|theta|/2) of MODEL.md 5. SI units.
module;
#include <rocking/eigen.hpp>
#include <utility>
#include <vector>
export module rocking.drawing;
export import rocking.geometry;

export namespace rocking {

using Point = std::pair<double, double>;  // (x, y) [m]

struct Outline {
  std::vector<Point> axis;   // node 0 (base centre) to node N
  Point left_corner, right_corner;
  Point damper_anchor, damper_end;  // equal when no edge is lifted
};

// theta is ignored in full contact.
Outline outline(const Structure& s, Phase phase, double theta, const Eigen::VectorXd& u, double exaggeration);

}  // namespace rocking
