// The part of a curve between two of its parameters: what remains of a curve on either side
// of a point where an embedded curve ends on it (see build_domain).

#include <algorithm>

#include "geometry/curve.hpp"

namespace meshd::core {

namespace {

class CurvePart final : public Curve {
public:
    CurvePart(std::shared_ptr<const Curve> whole, double ta, double tb) : whole_(std::move(whole)), ta_(ta), tb_(tb) {}

    CurveType type() const override { return whole_->type(); }
    double t_begin() const override { return ta_; }
    double t_end() const override { return tb_; }
    Vec2 point(double t) const override { return whole_->point(t); }
    Vec2 derivative(double t) const override { return whole_->derivative(t); }
    std::vector<double> breaks() const override { return inside(whole_->breaks()); }
    std::vector<double> corners() const override { return inside(whole_->corners()); }
    double least_radius() const override { return whole_->least_radius(); }

private:
    std::vector<double> inside(std::vector<double> ts) const {
        ts.erase(std::remove_if(ts.begin(), ts.end(), [&](double t) { return !(t > ta_ && t < tb_); }), ts.end());
        return ts;
    }

    std::shared_ptr<const Curve> whole_;
    double ta_, tb_;
};

}  // namespace

std::unique_ptr<Curve> make_part(std::shared_ptr<const Curve> whole, double ta, double tb) {
    return std::make_unique<CurvePart>(std::move(whole), ta, tb);
}

}  // namespace meshd::core
