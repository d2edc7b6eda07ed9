// Density: the per-curve table, eq. 6.1 inside, clamps (expressions: expression.cpp).

#include "density/size_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "meshd/core/errors.hpp"
#include "kernel/tolerances.hpp"

namespace meshd::core {

// ---------------------------------------------------------------------------------------
// SizeField

namespace {

std::string fmt_point(Vec2 p) {
    return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
}

}  // namespace

SizeField::SizeField(const DensitySpec& spec, const Domain& domain) {
    using K = GeometryErrorKind;
    auto make_source = [&](const ScalarSpec& s, Subject subject) {
        Source src;
        src.subject = subject;
        if (const double* v = std::get_if<double>(&s)) {
            if (!std::isfinite(*v) || *v <= 0.0)
                throw GeometryError(K::DensityInvalid, "density must be finite and positive",
                                    {std::move(subject)});
            src.constant = *v;
        } else {
            try {
                src.expr.emplace(std::get<std::string>(s));
            } catch (GeometryError& e) {
                throw GeometryError(e.kind(), e.what(), {std::move(subject)});
            }
        }
        sources_.push_back(std::move(src));
        return sources_.size() - 1;
    };
    if (spec.size) size_source_ = make_source(*spec.size, Subject::density("size"));

    // Per-curve table: names first, then tags.
    curve_source_.assign(domain.curves().size(), std::nullopt);
    std::vector<bool> by_name(domain.curves().size(), false);
    for (const auto& [key, value] : spec.curves) {
        const size_t src = make_source(value, Subject::density("curves", {key}));
        bool matched = false;
        for (CurveId c : domain.curve_parts(key)) {
            curve_source_[c] = src;
            by_name[c] = true;
            matched = true;
        }
        for (CurveId c = 0; c < domain.curves().size(); ++c) {
            if (domain.tags()[domain.curves()[c].tag] == key) {
                matched = true;
                if (!by_name[c]) curve_source_[c] = src;
            }
        }
        if (!matched)
            throw GeometryError(K::DensityMissing,
                                "density.curves names \"" + key + "\", which is neither a curve nor a tag",
                                {Subject::density("curves", {key})});
    }

    // Interior.
    InteriorMode mode = spec.interior;
    if (mode == InteriorMode::Default) mode = size_source_ ? InteriorMode::Expression : InteriorMode::Interpolate;
    if (mode == InteriorMode::Expression) {
        if (spec.interior_expression) {
            interior_source_ = make_source(*spec.interior_expression, Subject::density("interior"));
        } else if (size_source_) {
            interior_source_ = size_source_;
        } else {
            throw GeometryError(K::DensityMissing, "no density inside the domain: give size or interior",
                                {Subject::density("interior")});
        }
    }
    interpolate_ = mode == InteriorMode::Interpolate;

    // Every used curve needs a density.
    std::vector<bool> used(domain.curves().size(), false);
    for (const auto& l : domain.loops())
        for (const auto& u : l.items) used[u.curve] = true;
    for (CurveId c : domain.embedded()) used[c] = true;
    for (CurveId c = 0; c < domain.curves().size(); ++c) {
        if (!curve_source_[c]) curve_source_[c] = size_source_;
        if (used[c] && !curve_source_[c])
            throw GeometryError(K::DensityMissing,
                                "no density for curve \"" + domain.curves()[c].name +
                                    "\": give density.size or an entry in density.curves",
                                {Subject::density("curves"), Subject::curve(domain.curves()[c].name)});
    }

    const double extent = domain.extent();
    min_ = spec.min.value_or(tol::kDefaultMinSize * extent);
    max_ = spec.max.value_or(HUGE_VAL);
    if (spec.min && !(std::isfinite(*spec.min) && *spec.min > 0.0))
        throw GeometryError(K::DensityInvalid, "density.min must be finite and positive",
                            {Subject::density("min")});
    if (spec.max && !(*spec.max > 0.0) )
        throw GeometryError(K::DensityInvalid, "density.max must be positive", {Subject::density("max")});
    if (max_ < min_)
        throw GeometryError(K::DensityInvalid, "density.max is below density.min", {Subject::density("max")});
    // No edge can be longer than the domain: larger sizes only make the stages' searches
    // (which scale with the size) astronomically wide.
    max_ = std::fmin(max_, extent);
    min_ = std::fmin(min_, max_);
    cap_floor_ = std::fmin(min_, tol::kDefaultMinSize * extent);
    if (spec.gradation) {
        if (!(std::isfinite(*spec.gradation) && *spec.gradation > 1.0))
            throw GeometryError(K::DensityInvalid, "density.gradation must be a finite number above 1",
                                {Subject::density("gradation")});
        gradation_ = spec.gradation;
    }
}

double SizeField::eval(const Source& s, Vec2 p) const {
    return checked(s, p, s.constant ? *s.constant : (*s.expr)(p.x, p.y));
}

void SizeField::refuse(const Source& s, Vec2 p, double v) const {
    std::string what = std::isfinite(v) ? (v == 0.0 ? "zero" : "negative (" + std::to_string(v) + ")") : "not finite";
    throw GeometryError(GeometryErrorKind::DensityInvalid, "density is " + what + " at " + fmt_point(p), {s.subject})
        .at(p);
}

double SizeField::on_curve(CurveId c, Vec2 p) const {
    double h = eval(sources_[*curve_source_[c]], p);
    if (graded_) h = fmax_inline(graded_->capped(p, h), min_);
    if (curve_cap_) h = fmax_inline(curve_cap_->capped(p, h), cap_floor_);
    if (cap_) h = fmax_inline(cap_->capped(p, h), cap_floor_);
    return h;
}

double SizeField::interior(Vec2 p) const {
    if (!interpolate_) return interior_from(p, eval(sources_[*interior_source_], p));
    MESHD_INTERNAL_CHECK(idw_ != nullptr, "eq. 6.1 used before the boundary was set");
    return interior_from(p, clamped((*idw_)(p)));
}

void SizeField::interior(const Vec2* p, size_t n, double* out) const {
    if (interpolate_) {
        // eq. 6.1 over the whole batch, then the caps (each in the order of the points, so the
        // same values to the bit). Fig. 9's figures and target sizes at the end (eq. 6.1 at
        // 70,000 points) went from about 6.9 to 4.9 ms, and its time per triangle against the
        // NACA example's from 1.39-1.44 to 1.32-1.38 times (six alternated runs each). Why is
        // not settled: a benchmark of the same queries, warm or from emptied caches, asks
        // them at the same cost either way, and the profiles differ in what the compiler
        // inlined (docs/benchmarks.md, "eq. 6.1 at the end of a mesh").
        MESHD_INTERNAL_CHECK(idw_ != nullptr, "eq. 6.1 used before the boundary was set");
        for (size_t i = 0; i < n; ++i) out[i] = (*idw_)(p[i]);
        for (size_t i = 0; i < n; ++i) out[i] = interior_from(p[i], clamped(out[i]));
        return;
    }
    if (!sources_[*interior_source_].expr) {
        for (size_t i = 0; i < n; ++i) out[i] = interior(p[i]);
        return;
    }
    const Source& s = sources_[*interior_source_];
    const bool plain = !graded_ && !interior_cap_ && !cap_;  // interior_from() would keep every value
    constexpr size_t kChunk = 256;
    std::array<double, kChunk> x, y;
    for (size_t first = 0; first < n; first += kChunk) {
        const size_t m = std::min(kChunk, n - first);
        for (size_t i = 0; i < m; ++i) {
            x[i] = p[first + i].x;
            y[i] = p[first + i].y;
        }
        s.expr->evaluate(x.data(), y.data(), out + first, m);
        for (size_t i = first; i < first + m; ++i) {
            const double v = checked(s, p[i], out[i]);
            out[i] = plain ? v : interior_from(p[i], v);
        }
    }
}

double SizeField::interior_scattered(Vec2 p) const {
    if (!interpolate_) return interior_from(p, eval(sources_[*interior_source_], p));
    MESHD_INTERNAL_CHECK(idw_ != nullptr, "eq. 6.1 used before the boundary was set");
    return interior_from(p, clamped(idw_->summed(p)));
}

// The field inside from its raw value at p (the expression's, or eq. 6.1's): the gradation
// and the caps.
double SizeField::interior_from(Vec2 p, double h) const {
    if (graded_) h = fmax_inline(graded_->capped(p, h), min_);
    if (interior_cap_) h = fmax_inline(interior_cap_->capped(p, h), cap_floor_);
    if (cap_) h = fmax_inline(cap_->capped(p, h), cap_floor_);
    return h;
}

namespace {

// A cap of cones over the points, or none without points.
std::unique_ptr<GradationField> cap_of(const std::vector<Vec2>& points, const std::vector<double>& sizes, double ratio) {
    return points.empty() ? nullptr
                          : std::make_unique<GradationField>(points, sizes, ratio, GradationField::Spread::Curves);
}

}  // namespace

void SizeField::set_interior_cap(const std::vector<Vec2>& points, const std::vector<double>& sizes, double ratio) {
    interior_cap_ = cap_of(points, sizes, ratio);
}

void SizeField::set_cap(const SizeCaps& caps, double ratio) { cap_ = cap_of(caps.points, caps.sizes, ratio); }

void SizeField::set_gradation_sources(std::span<const Vec2> points, std::span<const double> sizes) {
    MESHD_INTERNAL_CHECK(gradation_.has_value(), "gradation sources without a gradation");
    graded_ = std::make_unique<GradationField>(points, sizes, *gradation_, GradationField::Spread::Domain);
}

void SizeField::set_curve_cap(const std::vector<Vec2>& points, const std::vector<double>& sizes, double ratio) {
    curve_cap_ = cap_of(points, sizes, ratio);
}

void SizeField::set_boundary_segments(std::vector<Vec2> starts, std::vector<double> lengths, double tolerance) {
    idw_ = std::make_unique<InverseDistanceField>(std::move(starts), std::move(lengths), tolerance);
}

}  // namespace meshd::core
