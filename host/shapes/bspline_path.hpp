// A global migration path (shape-constrained flying insects paper, §6,
// "Global path planning"): a uniform cubic B-spline through its control
// points' hull, parameterised by arc length so the shape's frame moves
// along it at a given speed, and a rotation-minimising frame along it that
// the shape's frame can follow (docs/force-model.md, "Path and obstacles").
#pragma once
#include <array>
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

    using D3 = std::array<double, 3>;
    // An orthonormal frame on the curve: the unit tangent (direction of
    // travel) and a unit `up` normal to it.
    struct Frame {
        D3 point, tangent, up;
    };
    // The frame at arc length s (clamped): a rotation-minimising frame
    // (double reflection, Wang et al. 2008) started at s = 0 with `up` the
    // world +z made normal to the tangent (where the path starts vertically:
    // the image of +z under the smallest rotation taking +x to the tangent)
    // and carried along the curve, so it never flips or spins about the
    // tangent; on a path in a horizontal plane `up` stays +z.
    Frame frame_at_length(double s) const;
    // Unit tangent at curve parameter u (at the tripled end points, where the
    // first derivative vanishes, the direction the curve leaves/enters by).
    D3 tangent_at_parameter(double u) const;

private:
    D3 point(double u) const;
    double param_at_length(double s) const;
    void build_frames();

    std::vector<D3> ctrl_;                     // with the end points tripled
    std::vector<double> table_s_, table_u_;    // arc length at samples of u
    std::vector<D3> table_up_;                 // rotation-minimising up at the samples
    double length_ = 0.0;
    double scale_ = 1.0;                       // max(1, |control coordinates|): derivative "zero" threshold
};

}  // namespace swarmcl
