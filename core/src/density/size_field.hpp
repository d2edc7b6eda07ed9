#pragma once
// rho over a domain, as every stage queries it: the request's density (expressions per
// curve, tag and inside; clamps) completed by the pipeline with the sources of eq. 6.1 and
// the gradation envelope.

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "density/expression.hpp"
#include "density/gradation.hpp"
#include "density/inverse_distance.hpp"
#include "meshd/core/density.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

/// Sizes at points, from which a cap of rho grows (SizeField::set_curve_cap).
struct SizeCaps {
    std::vector<Vec2> points;
    std::vector<double> sizes;
    bool empty() const { return points.empty(); }
};

/// rho over a domain. Expressions keep no state, but the pipeline completes the field (eq. 6.1
/// sources, gradation) as it goes: one per mesh, built by generate_mesh.
class SizeField {
public:
    /// Compiles and checks the spec against the domain: every used curve must get a density,
    /// every per-curve key must name a curve or a tag. Throws GeometryError.
    SizeField(const DensitySpec& spec, const Domain& domain);

    /// rho at a point of curve c, clamped to [min, max]. Throws DensityInvalid when the raw
    /// value is not finite and positive.
    double on_curve(CurveId c, Vec2 p) const;

    /// rho inside the domain. In interpolation mode set_boundary_segments() must come first.
    double interior(Vec2 p) const;
    /// The same for a query far from the others (a probe): eq. 6.1 summed without the
    /// query cells that interior() builds for runs of nearby queries, which a scattered
    /// query would build for itself alone.
    double interior_scattered(Vec2 p) const;
    /// out[i] = interior(p[i]) for i < n, to the bit; an expression is evaluated in batches
    /// (Expression::evaluate). For the figures of a finished mesh.
    void interior(const Vec2* p, size_t n, double* out) const;

    bool interpolates() const { return interpolate_; }
    bool curve_capped() const { return curve_cap_ != nullptr; }
    /// Sources of eq. 6.1: the start A_i of each boundary segment and its length rho_i; the
    /// field's relative error bound (inverse_distance.hpp).
    void set_boundary_segments(std::vector<Vec2> starts, std::vector<double> lengths, double tolerance = 1e-3);

    /// Limits the field (on curves and inside) to the gradation envelope over these samples
    /// (gradation.hpp).
    void set_gradation_sources(std::span<const Vec2> points, std::span<const double> sizes);
    bool graded() const { return graded_ != nullptr; }

    /// Caps rho on the curves (not inside) at min_i (sizes_i + (ratio - 1) |p - points_i|)
    /// (pipeline/agreement.hpp: curves made to agree with the interior field beside them).
    void set_curve_cap(const std::vector<Vec2>& points, const std::vector<double>& sizes, double ratio);
    /// Caps rho inside (not on the curves) the same way.
    void set_interior_cap(const std::vector<Vec2>& points, const std::vector<double>& sizes, double ratio);
    /// The interior cap as it stands (null: none), to set again with restore_interior_cap
    /// when a stage that replaced it is done again (the layers grown again).
    std::shared_ptr<const GradationField> interior_cap() const { return interior_cap_; }
    void restore_interior_cap(std::shared_ptr<const GradationField> cap) { interior_cap_ = std::move(cap); }
    /// Caps rho on the curves and inside the same way (the boundary layers' fans,
    /// layers/layers.hpp), beside the two caps above.
    void set_cap(const SizeCaps& caps, double ratio);

    /// density.min (or its default): the clamp of the given sizes.
    double min_size() const { return min_; }
    /// The least size the field takes anywhere: the caps above come from the geometry (a
    /// curve shorter than density.min, the layers' fans) and go below density.min where it
    /// does; they stop at the default min (a millionth of the domain's extent).
    double least_size() const { return cap_floor_; }
    double max_size() const { return max_; }
    std::optional<double> gradation() const { return gradation_; }

private:
    struct Source {
        std::optional<double> constant;
        std::optional<Expression> expr;
        Subject subject;  // where it came from, for error messages
    };
    double eval(const Source& s, Vec2 p) const;
    // eval()'s checks of a value v at p, and its clamps.
    double checked(const Source& s, Vec2 p, double v) const {
        if (!(std::isfinite(v) && v > 0.0)) [[unlikely]]
            refuse(s, p, v);
        return std::clamp(v, min_, max_);  // v is a number here, and min_ <= max_
    }
    [[noreturn]] void refuse(const Source& s, Vec2 p, double v) const;
    // eq. 6.1's value v clamped to [min, max] (never refused: a weighted mean of the boundary's
    // segment lengths).
    double clamped(double v) const { return fmin_inline(fmax_inline(v, min_), max_); }
    double interior_from(Vec2 p, double raw) const;

    std::vector<std::optional<size_t>> curve_source_;  // per curve: index into sources_
    std::vector<Source> sources_;
    std::optional<size_t> size_source_, interior_source_;
    bool interpolate_ = false;
    std::unique_ptr<InverseDistanceField> idw_;
    std::unique_ptr<GradationField> graded_;
    std::unique_ptr<GradationField> curve_cap_;
    std::shared_ptr<const GradationField> interior_cap_;
    std::unique_ptr<GradationField> cap_;
    double min_ = 0.0, max_ = 0.0;
    double cap_floor_ = 0.0;  // least_size()
    std::optional<double> gradation_;
};

}  // namespace meshd::core
