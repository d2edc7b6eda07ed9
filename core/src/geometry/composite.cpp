#include "geometry/composite.hpp"

#include <algorithm>

namespace meshd::core::detail {

CompositeCurve::CompositeCurve(CurveType type, std::vector<std::unique_ptr<Curve>> pieces)
    : type_(type), pieces_(std::move(pieces)) {
    offsets_.push_back(0.0);
    for (const auto& p : pieces_) offsets_.push_back(offsets_.back() + (p->t_end() - p->t_begin()));
}

size_t CompositeCurve::piece_of(double t) const {
    const auto it = std::upper_bound(offsets_.begin() + 1, offsets_.end() - 1, t);
    return static_cast<size_t>(it - (offsets_.begin() + 1));
}

Vec2 CompositeCurve::point(double t) const {
    if (t >= t_end()) return pieces_.back()->end();
    const size_t i = piece_of(t);
    return pieces_[i]->point(local(i, t));
}

Vec2 CompositeCurve::derivative(double t) const {
    const size_t i = piece_of(std::min(t, t_end()));
    return pieces_[i]->derivative(local(i, std::min(t, offsets_[i + 1])));
}

std::vector<double> CompositeCurve::breaks() const {
    std::vector<double> out;
    for (size_t i = 0; i < pieces_.size(); ++i) {
        if (i > 0) out.push_back(offsets_[i]);
        for (double b : pieces_[i]->breaks()) out.push_back(offsets_[i] + (b - pieces_[i]->t_begin()));
    }
    return out;
}

std::vector<double> CompositeCurve::corners() const {
    std::vector<double> out;
    for (size_t i = 0; i < pieces_.size(); ++i) {
        if (i > 0) out.push_back(offsets_[i]);
        for (double c : pieces_[i]->corners()) out.push_back(offsets_[i] + (c - pieces_[i]->t_begin()));
    }
    return out;
}

}  // namespace meshd::core::detail
