#pragma once
// A curve made of pieces joined end to end (an airfoil surface followed by the straight
// base of its blunt trailing edge). Piece i runs over [offset_i, offset_i + (t1 - t0)] of the
// composite parameter; every junction is a corner.

#include <memory>
#include <vector>

#include "geometry/curve.hpp"

namespace meshd::core::detail {

class CompositeCurve final : public Curve {
public:
    CompositeCurve(CurveType type, std::vector<std::unique_ptr<Curve>> pieces);

    CurveType type() const override { return type_; }
    double t_begin() const override { return 0.0; }
    double t_end() const override { return offsets_.back(); }
    Vec2 point(double t) const override;
    Vec2 derivative(double t) const override;
    std::vector<double> breaks() const override;
    std::vector<double> corners() const override;
    bool corner_at_ends() const override { return true; }

private:
    size_t piece_of(double t) const;
    double local(size_t i, double t) const { return pieces_[i]->t_begin() + (t - offsets_[i]); }

    CurveType type_;
    std::vector<std::unique_ptr<Curve>> pieces_;
    std::vector<double> offsets_;  // size pieces + 1
};

/// make_spline_through, reporting the given curve type.
std::unique_ptr<Curve> make_spline(std::vector<Vec2> points, bool allow_periodic, CurveType type);

}  // namespace meshd::core::detail
