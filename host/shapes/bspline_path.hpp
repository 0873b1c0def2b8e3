// A global migration path (shape-constrained flying insects paper, §6,
// "Global path planning"): a uniform cubic B-spline through its control
// points' hull, parameterised by arc length so the shape's frame moves
// along it at a given speed.
#pragma once
#include <vector>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

class BSplinePath {
public:
    // Packed xyz control points: at least 4 (a cubic segment needs 4), all
    // finite; Error(InvalidArgument) otherwise.  The curve starts near the
    // first control point and ends near the last (open uniform spline with
    // the end points tripled, so it interpolates both ends).
    explicit BSplinePath(const std::vector<float>& control_xyz);

    double length() const { return length_; }
    // The point at arc length s (clamped to [0, length()]).
    Vec3f at_length(double s) const;
    // The point at curve parameter u in [0, 1] (uniform in the knots).
    Vec3f at_parameter(double u) const;

private:
    std::vector<std::array<double, 3>> ctrl_;  // with the end points tripled
    std::vector<double> table_s_, table_u_;    // arc length at samples of u
    double length_ = 0.0;
};

}  // namespace swarmcl
