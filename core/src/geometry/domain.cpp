// Building and validating the domain model (paper, section 2).
//
// Checks, in order: point coordinates; each curve's own parameters (by its factory); curve
// ends against the named points; zero length; loops (existence, reuse, closure); embedded
// curves; then, on polylines that follow every used curve within kFlattenDeviation of the
// extent: curves split where an embedded curve ends on them, crossings between and within
// curves, loop containment (one outer loop, holes inside it and apart) and embedded curves
// inside the domain.

#include "meshd/core/domain.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "geometry/curve.hpp"
#include "geometry/nesting.hpp"
#include "kernel/crossings.hpp"
#include "meshd/core/errors.hpp"
#include "kernel/predicates.hpp"
#include "kernel/tolerances.hpp"

namespace meshd::core {

Domain::Domain() = default;
Domain::Domain(Domain&&) noexcept = default;
Domain& Domain::operator=(Domain&&) noexcept = default;
Domain::~Domain() = default;

std::optional<CurveId> Domain::find_curve(const std::string& name) const {
    auto it = curve_index_.find(name);
    if (it == curve_index_.end()) return std::nullopt;
    return it->second.front();
}

const std::vector<CurveId>& Domain::curve_parts(const std::string& name) const {
    static const std::vector<CurveId> none;
    auto it = curve_index_.find(name);
    return it == curve_index_.end() ? none : it->second;
}

namespace {

// The field of the first coordinate of a curve's description beyond kMaxCoordinate (the
// exact predicates' range; also where arc lengths stop being computable), or nothing.
std::optional<std::vector<std::string>> far_coordinate(const CurveShape& shape) {
    auto far = [](double v) { return !(std::fabs(v) <= tol::kMaxCoordinate); };
    auto in_list = [&](const std::vector<Vec2>& pts, const char* field) -> std::optional<std::vector<std::string>> {
        for (size_t i = 0; i < pts.size(); ++i)
            if (far(pts[i].x) || far(pts[i].y)) return std::vector<std::string>{field, std::to_string(i)};
        return std::nullopt;
    };
    auto placed = [&](const AirfoilPlacement& p) -> std::optional<std::vector<std::string>> {
        if (far(p.leading_edge.x) || far(p.leading_edge.y)) return std::vector<std::string>{"leading_edge"};
        if (far(p.chord)) return std::vector<std::string>{"chord"};
        return std::nullopt;
    };
    return std::visit(
        [&](const auto& sh) -> std::optional<std::vector<std::string>> {
            using T = std::decay_t<decltype(sh)>;
            if constexpr (std::is_same_v<T, ArcShape>) {
                if (far(sh.center.x) || far(sh.center.y)) return std::vector<std::string>{"center"};
            } else if constexpr (std::is_same_v<T, BSplineShape>) {
                return in_list(sh.control_points, "control_points");
            } else if constexpr (std::is_same_v<T, SplineShape>) {
                return in_list(sh.through, "through");
            } else if constexpr (std::is_same_v<T, NacaSpec> || std::is_same_v<T, AirfoilSpec>) {
                return placed(sh.placement);
            }
            return std::nullopt;
        },
        shape);
}

// Points hashed by square cells of one size: every point within that distance of a place is
// in the 3 x 3 cells around it. Linear in the points for the queries of build_domain, where
// a sweep along x was quadratic when many points share an x.
class PointGrid {
public:
    PointGrid(Vec2 origin, double cell) : origin_(origin), inv_cell_(1.0 / cell) {}

    void insert(PointId id, Vec2 p) { cells_[key(index(p.x, origin_.x), index(p.y, origin_.y))].push_back(id); }

    template <class F>
    void near(Vec2 p, F&& visit) const {
        const std::int64_t x = index(p.x, origin_.x), y = index(p.y, origin_.y);
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy) {
                const auto it = cells_.find(key(x + dx, y + dy));
                if (it == cells_.end()) continue;
                for (const PointId id : it->second) visit(id);
            }
    }

private:
    std::int64_t index(double v, double o) const {
        return static_cast<std::int64_t>(std::clamp(std::floor((v - o) * inv_cell_), -0x1p61, 0x1p61));
    }
    // Distinct cells may share a key far apart (wrapped bits): that only adds candidates.
    static std::uint64_t key(std::int64_t x, std::int64_t y) {
        return (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y);
    }

    Vec2 origin_;
    double inv_cell_;
    std::unordered_map<std::uint64_t, std::vector<PointId>> cells_;
};

void name_curve(GeometryError& e, const std::string& name) {
    bool named = false;
    for (const Subject& s : e.subjects()) named |= s.kind == Subject::Kind::Curve && !s.name.empty();
    if (named) return;
    std::vector<Subject> subjects = e.subjects();
    bool done = false;
    for (Subject& s : subjects) {
        if (s.kind == Subject::Kind::Curve && s.name.empty()) {
            s.name = name;
            done = true;
        }
    }
    if (!done) subjects.insert(subjects.begin(), Subject::curve(name));
    e = GeometryError(e.kind(), std::string("curve \"") + name + "\": " + e.what(), std::move(subjects));
}

struct Flattened {
    std::vector<Vec2> points;   // polyline in the curve's direction, ends included
    std::vector<double> params;  // the curve's parameter at each point
};

// Adaptive flattening: split while the curve strays from the chord by more than `dev` at
// the quarter points (checking two points catches S-shaped pieces).
void flatten_piece(const Curve& c, double ta, double tb, Vec2 pa, Vec2 pb, double dev, int depth,
                   int min_depth, Flattened& out) {
    const double tm = 0.5 * (ta + tb);
    const Vec2 pm = c.point(tm);
    bool split = depth < min_depth;
    if (!split && depth < 24) {
        const Vec2 chord = pb - pa;
        const double len = norm(chord);
        auto off = [&](Vec2 q) {
            return len > 0.0 ? std::fabs(cross(chord, q - pa)) / len : distance(pa, q);
        };
        split = off(pm) > dev || off(c.point(0.5 * (ta + tm))) > dev || off(c.point(0.5 * (tm + tb))) > dev;
    }
    if (split) {
        flatten_piece(c, ta, tm, pa, pm, dev, depth + 1, min_depth, out);
        flatten_piece(c, tm, tb, pm, pb, dev, depth + 1, min_depth, out);
    } else {
        out.points.push_back(pb);
        out.params.push_back(tb);
    }
}

Flattened flatten(const Curve& c, Vec2 start, Vec2 end, double dev) {
    std::vector<double> cuts{c.t_begin()};
    for (double b : c.breaks()) cuts.push_back(b);
    cuts.push_back(c.t_end());
    const int min_depth = cuts.size() < 64 ? 3 : 1;
    Flattened f;
    f.points.push_back(start);
    f.params.push_back(c.t_begin());
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
        const Vec2 pa = f.points.back();
        const Vec2 pb = i + 2 == cuts.size() ? end : c.point(cuts[i + 1]);
        flatten_piece(c, cuts[i], cuts[i + 1], pa, pb, dev, 0, min_depth, f);
    }
    return f;
}

double signed_area(const std::vector<Vec2>& ring) {
    double a = 0.0;
    for (size_t i = 0, n = ring.size(); i < n; ++i) a += cross(ring[i], ring[(i + 1) % n]);
    return 0.5 * a;
}

Box box_of(const std::vector<Vec2>& pts) {
    Box b;
    for (Vec2 p : pts) b.add(p);
    return b;
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// The parameter in [ta, tb] of the point of curve c nearest q, by golden-section search (the
// distance is unimodal over a piece of the flattened polyline, which follows the curve
// closely), and that distance.
std::pair<double, double> nearest_on(const Curve& c, double ta, double tb, Vec2 q) {
    constexpr double kInvPhi = 0.6180339887498949;
    double a = ta, b = tb;
    double x1 = b - kInvPhi * (b - a), x2 = a + kInvPhi * (b - a);
    double f1 = distance(c.point(x1), q), f2 = distance(c.point(x2), q);
    for (int i = 0; i < 80 && b - a > 0.0; ++i) {
        if (f1 <= f2) {
            b = x2, x2 = x1, f2 = f1;
            x1 = b - kInvPhi * (b - a), f1 = distance(c.point(x1), q);
        } else {
            a = x1, x1 = x2, f1 = f2;
            x2 = a + kInvPhi * (b - a), f2 = distance(c.point(x2), q);
        }
    }
    double t = 0.5 * (a + b), dist = distance(c.point(t), q);
    for (double e : {ta, tb})
        if (double de = distance(c.point(e), q); de < dist) t = e, dist = de;
    return {t, dist};
}

// An embedded curve may end on another curve away from that curve's ends (a cut from a wall
// to a hole, a wake line from a point of an airfoil): that curve is split there into parts
// joined at the embedded curve's end point, so that the point is an end of every curve
// through it. The search uses the flattened curves (within `dev` of the true ones) in a
// segment grid; a touch is an end within `match` of the curve. Returns, per curve split, its
// parts in order (the first keeps the curve's id; the others are appended).
std::map<CurveId, std::vector<CurveId>> split_where_embedded_ends(std::vector<DomainCurve>& curves,
                                                                  const std::vector<DomainPoint>& points,
                                                                  const std::vector<CurveId>& embedded,
                                                                  const std::vector<Flattened>& flat, double dev,
                                                                  double match) {
    using K = GeometryErrorKind;
    if (embedded.empty()) return {};
    detail::SegmentSoup soup;
    std::vector<std::pair<CurveId, std::uint32_t>> seg_of;  // curve, index of the piece's start
    for (CurveId c = 0; c < curves.size(); ++c) {
        const auto& f = flat[c].points;
        for (size_t k = 0; k + 1 < f.size(); ++k) {
            const auto i = static_cast<std::uint32_t>(soup.points.size());
            soup.points.push_back(f[k]);
            soup.points.push_back(f[k + 1]);
            soup.segments.push_back({i, i + 1});
            seg_of.push_back({c, static_cast<std::uint32_t>(k)});
        }
    }
    const detail::SegmentGrid grid(soup, dev + match);

    struct Touch {
        double t;
        PointId point;
    };
    std::map<CurveId, std::vector<Touch>> touches;
    for (CurveId e : embedded) {
        for (PointId p : {curves[e].from, curves[e].to}) {
            if (p == curves[e].to && curves[e].from == curves[e].to) continue;
            const Vec2 q = points[p].position;
            CurveId best_curve = kNoCurve;
            double best_t = 0.0, best_dist = HUGE_VAL;
            grid.near(q, [&](std::uint32_t s) {
                const auto [c, k] = seg_of[s];
                if (c == e || curves[c].from == p || curves[c].to == p) return;
                const Vec2 a = soup.points[soup.segments[s][0]], b = soup.points[soup.segments[s][1]];
                const double r = dev + match;
                if (q.x < std::fmin(a.x, b.x) - r || q.x > std::fmax(a.x, b.x) + r || q.y < std::fmin(a.y, b.y) - r ||
                    q.y > std::fmax(a.y, b.y) + r)
                    return;
                const auto [t, dist] = nearest_on(*curves[c].geometry, flat[c].params[k], flat[c].params[k + 1], q);
                if (dist <= match && dist < best_dist) best_curve = c, best_t = t, best_dist = dist;
            });
            if (best_curve == kNoCurve) continue;
            const DomainCurve& dc = curves[best_curve];
            const Vec2 ends[2] = {points[dc.from].position, points[dc.to].position};
            for (Vec2 end : ends)
                if (distance(end, q) <= match)
                    throw GeometryError(K::CoincidentPoints,
                                        "embedded curve " + quoted(curves[e].name) + " ends at an end of curve " +
                                            quoted(dc.name) + " by another point: use one point for both",
                                        {Subject::curve(curves[e].name), Subject::curve(dc.name)});
            touches[best_curve].push_back({best_t, p});
        }
    }

    std::map<CurveId, std::vector<CurveId>> parts;
    for (auto& [c, list] : touches) {
        // Several embedded curves may end at one point of the curve.
        std::sort(list.begin(), list.end(), [](const Touch& a, const Touch& b) { return a.point < b.point; });
        list.erase(std::unique(list.begin(), list.end(), [](const Touch& a, const Touch& b) { return a.point == b.point; }),
                   list.end());
        std::sort(list.begin(), list.end(), [](const Touch& a, const Touch& b) { return a.t < b.t; });
        const std::shared_ptr<const Curve> whole = curves[c].geometry;
        const DomainCurve original{curves[c].name, curves[c].tag, whole, curves[c].from, curves[c].to, 0.0, nullptr};
        std::vector<CurveId>& ids = parts[c];
        double ta = whole->t_begin();
        PointId from = original.from;
        for (size_t i = 0; i <= list.size(); ++i) {
            const double tb = i < list.size() ? list[i].t : whole->t_end();
            const PointId to = i < list.size() ? list[i].point : original.to;
            if (!(tb > ta) || from == to)
                throw GeometryError(K::CoincidentPoints,
                                    "two embedded curves end at the same place on curve " + quoted(original.name) +
                                        " by different points: use one point for both",
                                    {Subject::curve(original.name)});
            DomainCurve part{original.name, original.tag, make_part(whole, ta, tb), from, to, 0.0, nullptr};
            part.arc_length = make_arc_length(*part.geometry);
            part.length = part.arc_length->length();
            const CurveId id = i == 0 ? c : static_cast<CurveId>(curves.size());
            if (i == 0) curves[c] = std::move(part);
            else curves.push_back(std::move(part));
            ids.push_back(id);
            ta = tb;
            from = to;
        }
    }
    return parts;
}

}  // namespace

Domain build_domain(const DomainSpec& spec, Observer* observer) {
    using K = GeometryErrorKind;
    Domain d;
    // Asked every 64 curves and between the checks whether to stop.
    size_t polls = 0;
    auto poll = [&](bool now = false) {
        if (observer && (now || (++polls & 63u) == 0) && observer->should_stop()) throw Cancelled();
    };

    // Named points.
    std::map<std::string, PointId> point_index;
    for (const auto& [name, p] : spec.points) {
        if (!is_finite(p))
            throw GeometryError(K::NonFinite, "point " + quoted(name) + " has a non-finite coordinate",
                                {Subject::point(name)});
        if (std::fabs(p.x) > tol::kMaxCoordinate || std::fabs(p.y) > tol::kMaxCoordinate)
            throw GeometryError(K::NonFinite,
                                "point " + quoted(name) + " is too far out (coordinates beyond 1e30)",
                                {Subject::point(name)});
        if (point_index.count(name)) continue;  // the first of two equal names (api refuses them)
        point_index[name] = static_cast<PointId>(d.points_.size());
        d.points_.push_back({name, p});
    }
    auto lookup = [&](const std::string& curve, const std::string& field,
                      const std::string& name) -> PointId {
        auto it = point_index.find(name);
        if (it == point_index.end())
            throw GeometryError(K::UnknownPoint,
                                "curve " + quoted(curve) + " names point " + quoted(name) +
                                    " in \"" + field + "\", which is not defined",
                                {Subject::curve(curve, {field})});
        return it->second;
    };

    // The named points by place, for curves whose ends are given by geometry alone: a cell
    // as large as the largest tolerance of a match (kPointMatch of the largest coordinate).
    double largest = 1.0;
    for (const DomainPoint& p : d.points_) largest = std::fmax(largest, std::fmax(std::fabs(p.position.x), std::fabs(p.position.y)));
    PointGrid named_grid({0.0, 0.0}, tol::kPointMatch * largest);
    for (PointId id = 0; id < d.points_.size(); ++id) named_grid.insert(id, d.points_[id].position);

    // Curves.
    std::map<std::string, TagId> tag_index;
    for (const CurveSpec& cs : spec.curves) {
        poll();
        if (d.curve_index_.count(cs.name)) continue;
        std::optional<PointId> from, to;
        if (cs.from) from = lookup(cs.name, "from", *cs.from);
        if (cs.to) to = lookup(cs.name, "to", *cs.to);
        const bool needs_ends = std::holds_alternative<LineShape>(cs.shape) ||
                                std::holds_alternative<ArcShape>(cs.shape);
        if (needs_ends && (!from || !to))
            throw GeometryError(K::BadParameter,
                                "curve " + quoted(cs.name) + " needs both \"from\" and \"to\"",
                                {Subject::curve(cs.name, {from ? "to" : "from"})});
        if (const auto field = far_coordinate(cs.shape))
            throw GeometryError(K::NonFinite,
                                "curve " + quoted(cs.name) + " has a coordinate beyond 1e30 (" + (*field)[0] + ")",
                                {Subject::curve(cs.name, *field)});
        std::unique_ptr<Curve> geom;
        try {
            std::visit(
                [&](const auto& shape) {
                    using T = std::decay_t<decltype(shape)>;
                    if constexpr (std::is_same_v<T, LineShape>) {
                        geom = make_line(d.points_[*from].position, d.points_[*to].position);
                    } else if constexpr (std::is_same_v<T, ArcShape>) {
                        geom = make_arc(d.points_[*from].position, d.points_[*to].position,
                                        shape.center, shape.direction, *from == *to);
                    } else if constexpr (std::is_same_v<T, BSplineShape>) {
                        geom = make_bspline(shape.control_points, shape.degree, shape.knots);
                    } else if constexpr (std::is_same_v<T, SplineShape>) {
                        geom = make_spline_through(shape.through);
                    } else if constexpr (std::is_same_v<T, NacaSpec>) {
                        geom = make_naca(shape);
                    } else {
                        geom = make_airfoil(shape);
                    }
                },
                cs.shape);
        } catch (GeometryError& e) {
            name_curve(e, cs.name);
            throw;
        }
        const std::string tag = cs.tag.value_or(cs.name);
        auto [tit, inserted] = tag_index.emplace(tag, static_cast<TagId>(d.tags_.size()));
        if (inserted) d.tags_.push_back(tag);
        DomainCurve dc;
        dc.name = cs.name;
        dc.tag = tit->second;
        dc.geometry = std::move(geom);
        dc.length = 0.0;
        // Unnamed ends become anonymous points.
        const Vec2 gs = dc.geometry->start(), ge = dc.geometry->end();
        const bool closed_geom = gs == ge;
        // An unnamed end that sits on a named point (to rounding) is that point.
        auto named_at = [&](Vec2 p) -> std::optional<PointId> {
            const double scale = std::fmax(1.0, std::fmax(std::fabs(p.x), std::fabs(p.y)));
            std::optional<PointId> found;
            named_grid.near(p, [&](PointId id) {
                if (distance(d.points_[id].position, p) <= tol::kPointMatch * scale && (!found || id < *found)) found = id;
            });
            return found;
        };
        if (!from) from = named_at(gs);
        if (!to) to = closed_geom ? from : named_at(ge);
        if (!from) {
            dc.from = static_cast<PointId>(d.points_.size());
            d.points_.push_back({{}, gs});
        } else {
            dc.from = *from;
        }
        if (!to) {
            if (closed_geom) {
                dc.to = dc.from;
            } else {
                dc.to = static_cast<PointId>(d.points_.size());
                d.points_.push_back({{}, ge});
            }
        } else {
            dc.to = *to;
        }
        d.curve_index_[cs.name] = {static_cast<CurveId>(d.curves_.size())};
        d.curves_.push_back(std::move(dc));
    }

    // Extent (coarse) for the tolerances, then lengths and ends.
    Box coarse;
    for (CurveId c = 0; c < d.curves_.size(); ++c) {
        poll();
        const Curve& g = *d.curves_[c].geometry;
        Box own;
        for (int k = 0; k <= 64; ++k) own.add(g.point(g.t_begin() + (g.t_end() - g.t_begin()) * k / 64.0));
        const double far = std::fmax(std::fmax(std::fabs(own.lo.x), std::fabs(own.hi.x)),
                                     std::fmax(std::fabs(own.lo.y), std::fabs(own.hi.y)));
        if (!(far <= tol::kMaxCoordinate))
            throw GeometryError(K::NonFinite,
                                "curve " + quoted(d.curves_[c].name) +
                                    " reaches non-finite or too large coordinates (beyond 1e30)",
                                {Subject::curve(d.curves_[c].name)});
        coarse.add(own);
        coarse.add(d.points_[d.curves_[c].from].position);
        coarse.add(d.points_[d.curves_[c].to].position);
    }
    const double extent = coarse.diagonal();
    if (!(extent > 0.0) || !std::isfinite(extent))
        throw GeometryError(K::ZeroLength, "the domain has no extent", {});
    if (extent < tol::kMinExtent) {
        char across[32];
        std::snprintf(across, sizeof across, "%.3g", extent);
        throw GeometryError(K::ZeroLength,
                            std::string("the domain is ") + across +
                                " across, below 1e-30: scale its coordinates (the predicates would underflow)",
                            {});
    }
    for (CurveId c = 0; c < d.curves_.size(); ++c) {
        poll();
        DomainCurve& dc = d.curves_[c];
        const Vec2 gs = dc.geometry->start(), ge = dc.geometry->end();
        const double match = tol::kPointMatch * extent;
        if (distance(gs, d.points_[dc.from].position) > match)
            throw GeometryError(K::EndsMismatch,
                                "curve " + quoted(dc.name) + " starts at (" + std::to_string(gs.x) + ", " +
                                    std::to_string(gs.y) + "), not at its \"from\" point",
                                {Subject::curve(dc.name, {"from"})});
        if (distance(ge, d.points_[dc.to].position) > match)
            throw GeometryError(K::EndsMismatch,
                                "curve " + quoted(dc.name) + " ends at (" + std::to_string(ge.x) + ", " +
                                    std::to_string(ge.y) + "), not at its \"to\" point",
                                {Subject::curve(dc.name, {"to"})});
        try {
            dc.arc_length = make_arc_length(*dc.geometry);
            dc.length = dc.arc_length->length();
        } catch (GeometryError& e) {
            name_curve(e, dc.name);
            throw;
        }
        if (!std::isfinite(dc.length))
            throw GeometryError(K::NonFinite, "curve " + quoted(dc.name) + " has a non-finite length",
                                {Subject::curve(dc.name)});
        if (dc.length <= tol::kMinCurveLength * extent)
            throw GeometryError(K::ZeroLength, "curve " + quoted(dc.name) + " has zero length",
                                {Subject::curve(dc.name)});
    }
    // Distinct named points at the same place.
    poll(true);
    {
        const double match = tol::kPointMatch * extent;
        PointGrid grid(coarse.lo, match);
        for (PointId j = 0; j < d.points_.size(); ++j) {
            const Vec2 b = d.points_[j].position;
            grid.near(b, [&](PointId i) {
                if (distance(d.points_[i].position, b) > match) return;
                const auto& na = d.points_[i];
                const auto& nb = d.points_[j];
                if (na.name.empty() || nb.name.empty()) return;  // ends of self-closed curves
                throw GeometryError(K::CoincidentPoints,
                                    "points " + quoted(na.name) + " and " + quoted(nb.name) +
                                        " coincide; use one name for both",
                                    {Subject::point(nb.name), Subject::point(na.name)});
            });
            grid.insert(j, b);
        }
    }

    // Loops and embedded curves: names, reuse, closure.
    std::vector<int> used(d.curves_.size(), 0);
    auto curve_of = [&](const std::string& name, Subject where) -> CurveId {
        auto id = d.find_curve(name);
        if (!id)
            throw GeometryError(K::UnknownCurve, "curve " + quoted(name) + " is not defined",
                                {std::move(where)});
        if (used[*id]++)
            throw GeometryError(K::CurveReused,
                                "curve " + quoted(name) + " is used more than once in loops and embedded",
                                {std::move(where), Subject::curve(name)});
        return *id;
    };
    std::vector<DomainLoop> loops;
    for (size_t li = 0; li < spec.loops.size(); ++li) {
        const auto& items = spec.loops[li];
        const int lix = static_cast<int>(li);
        if (items.empty())
            throw GeometryError(K::EmptyLoop, "loop " + std::to_string(li) + " has no curves",
                                {Subject::loop(lix)});
        DomainLoop loop{{}, lix, false, 0.0};
        for (size_t j = 0; j < items.size(); ++j)
            loop.items.push_back(
                {curve_of(items[j].curve, Subject::loop(lix, {std::to_string(j)})), items[j].reversed});
        for (size_t j = 0; j < loop.items.size(); ++j) {
            const CurveUse& a = loop.items[j];
            const CurveUse& b = loop.items[(j + 1) % loop.items.size()];
            const DomainCurve& ca = d.curves_[a.curve];
            const DomainCurve& cb = d.curves_[b.curve];
            const PointId a_end = a.reversed ? ca.from : ca.to;
            const PointId b_start = b.reversed ? cb.to : cb.from;
            if (a_end != b_start) {
                const size_t jn = (j + 1) % loop.items.size();
                const std::string msg =
                    loop.items.size() == 1
                        ? "loop " + std::to_string(li) + ": curve " + quoted(ca.name) +
                              " is not closed (it ends where it does not start)"
                        : "loop " + std::to_string(li) + " does not close: curve " + quoted(ca.name) +
                              " ends at " + (d.points_[a_end].name.empty() ? "an unnamed point" : quoted(d.points_[a_end].name)) +
                              " but the next curve " + quoted(cb.name) + " starts at " +
                              (d.points_[b_start].name.empty() ? "an unnamed point" : quoted(d.points_[b_start].name));
                throw GeometryError(K::LoopNotClosed, msg,
                                    {Subject::loop(lix, {std::to_string(jn)}), Subject::curve(ca.name),
                                     Subject::curve(cb.name)});
            }
        }
        loops.push_back(std::move(loop));
    }
    if (loops.empty()) throw GeometryError(K::NoOuterLoop, "the geometry has no loops", {});
    std::vector<int> embedded_at;  // each embedded curve's place in spec.embedded
    for (size_t ei = 0; ei < spec.embedded.size(); ++ei) {
        d.embedded_.push_back(curve_of(spec.embedded[ei], Subject::embedded(static_cast<int>(ei))));
        embedded_at.push_back(static_cast<int>(ei));
    }
    // A curve in no loop and not embedded is almost always one forgotten in a loop; it would
    // also leave an empty boundary group in the mesh files.
    for (CurveId c = 0; c < d.curves_.size(); ++c)
        if (!used[c])
            throw GeometryError(K::UnusedCurve,
                                "curve " + quoted(d.curves_[c].name) + " is in no loop and not embedded",
                                {Subject::curve(d.curves_[c].name)});

    // Flatten every curve (all are used now); end points are shared by index.
    const double dev = tol::kFlattenDeviation * extent;
    std::vector<Flattened> flat(d.curves_.size());
    auto flatten_curve = [&](CurveId c) {
        poll();
        const DomainCurve& dc = d.curves_[c];
        flat[c] = flatten(*dc.geometry, d.points_[dc.from].position, d.points_[dc.to].position, dev);
    };
    for (CurveId c = 0; c < d.curves_.size(); ++c) flatten_curve(c);

    // Embedded curves that end on a curve away from its ends: that curve is split there.
    const std::map<CurveId, std::vector<CurveId>> parts =
        split_where_embedded_ends(d.curves_, d.points_, d.embedded_, flat, dev, tol::kPointMatch * extent);
    if (!parts.empty()) {
        auto replace = [&](std::vector<CurveUse>& items) {
            std::vector<CurveUse> out;
            for (const CurveUse& u : items) {
                const auto it = parts.find(u.curve);
                if (it == parts.end()) {
                    out.push_back(u);
                } else if (u.reversed) {
                    for (auto p = it->second.rbegin(); p != it->second.rend(); ++p) out.push_back({*p, true});
                } else {
                    for (CurveId p : it->second) out.push_back({p, false});
                }
            }
            items = std::move(out);
        };
        for (DomainLoop& l : loops) replace(l.items);
        std::vector<CurveId> emb;
        std::vector<int> emb_at;
        for (size_t ei = 0; ei < d.embedded_.size(); ++ei) {
            const auto it = parts.find(d.embedded_[ei]);
            const std::vector<CurveId> one{d.embedded_[ei]};
            for (CurveId c : it == parts.end() ? one : it->second) {
                emb.push_back(c);
                emb_at.push_back(embedded_at[ei]);
            }
        }
        d.embedded_ = std::move(emb);
        embedded_at = std::move(emb_at);
        flat.resize(d.curves_.size());
        for (const auto& [whole, ids] : parts) {
            d.curve_index_[d.curves_[whole].name] = ids;
            for (CurveId c : ids) flatten_curve(c);
        }
    }

    detail::SegmentSoup soup;
    std::vector<CurveId> seg_curve;
    std::vector<std::uint32_t> soup_of_point(d.points_.size(), UINT32_MAX);
    auto soup_point = [&](PointId p) {
        if (soup_of_point[p] == UINT32_MAX) {
            soup_of_point[p] = static_cast<std::uint32_t>(soup.points.size());
            soup.points.push_back(d.points_[p].position);
        }
        return soup_of_point[p];
    };
    for (CurveId c = 0; c < d.curves_.size(); ++c) {
        const DomainCurve& dc = d.curves_[c];
        const auto& f = flat[c].points;
        std::uint32_t prev = soup_point(dc.from);
        for (size_t k = 1; k < f.size(); ++k) {
            std::uint32_t cur;
            if (k + 1 == f.size()) {
                cur = soup_point(dc.to);
            } else {
                cur = static_cast<std::uint32_t>(soup.points.size());
                soup.points.push_back(f[k]);
            }
            soup.segments.push_back({prev, cur});
            seg_curve.push_back(c);
            prev = cur;
        }
    }
    poll(true);
    if (auto hit = detail::find_crossing(soup)) {
        const CurveId a = seg_curve[hit->first], b = seg_curve[hit->second];
        const auto& sa = soup.segments[hit->first];
        const auto& sb = soup.segments[hit->second];
        // An approximate place for the message: the nearer ends of the two pieces.
        Vec2 where = soup.points[sa[0]];
        double best = HUGE_VAL;
        for (auto i : sa)
            for (auto j : sb)
                if (double dd = distance(soup.points[i], soup.points[j]); dd < best) {
                    best = dd;
                    where = 0.5 * (soup.points[i] + soup.points[j]);
                }
        const std::string at = " near (" + std::to_string(where.x) + ", " + std::to_string(where.y) + ")";
        if (a == b)
            throw GeometryError(K::SelfIntersection,
                                "curve " + quoted(d.curves_[a].name) + " crosses itself" + at,
                                {Subject::curve(d.curves_[a].name)});
        throw GeometryError(K::CurvesCross,
                            "curves " + quoted(d.curves_[a].name) + " and " + quoted(d.curves_[b].name) +
                                " cross or touch away from a shared end" + at,
                            {Subject::curve(d.curves_[a].name), Subject::curve(d.curves_[b].name)});
    }

    // Loop polygons, areas, the outer loop, holes.
    poll(true);
    std::vector<std::vector<Vec2>> rings(loops.size());
    for (size_t li = 0; li < loops.size(); ++li) {
        for (const CurveUse& u : loops[li].items) {
            const auto& f = flat[u.curve].points;
            if (u.reversed) rings[li].insert(rings[li].end(), f.rbegin(), f.rend() - 1);
            else rings[li].insert(rings[li].end(), f.begin(), f.end() - 1);
        }
        loops[li].area = signed_area(rings[li]);
    }
    size_t outer = 0;
    for (size_t li = 1; li < loops.size(); ++li)
        if (std::fabs(loops[li].area) > std::fabs(loops[outer].area)) outer = li;
    detail::LoopNesting nesting(rings, outer);
    for (size_t li = 0; li < loops.size(); ++li) {
        if (li == outer) continue;
        poll();
        if (!nesting.inside_outer(rings[li].front()))
            throw GeometryError(K::HoleOutside,
                                "loop " + std::to_string(li) + " is not inside the outer loop (loop " +
                                    std::to_string(outer) + ", the largest)",
                                {Subject::loop(static_cast<int>(li))});
    }
    // Holes apart: no hole inside another.
    for (size_t a = 0; a < loops.size(); ++a) {
        if (a == outer) continue;
        poll();
        if (const auto b = nesting.hole_holding(rings[a].front(), a))
            throw GeometryError(K::HolesOverlap,
                                "hole loop " + std::to_string(a) + " lies inside hole loop " + std::to_string(*b),
                                {Subject::loop(static_cast<int>(a)), Subject::loop(static_cast<int>(*b))});
    }
    // Embedded curves inside the domain: probe a flattened point away from the ends.
    for (size_t ei = 0; ei < d.embedded_.size(); ++ei) {
        poll();
        const auto& f = flat[d.embedded_[ei]].points;
        const Vec2 probe = f.size() > 2 ? f[f.size() / 2] : 0.5 * (f.front() + f.back());
        if (!nesting.inside_outer(probe) || nesting.hole_holding(probe, outer))
            throw GeometryError(K::EmbeddedOutside,
                                "embedded curve " + quoted(d.curves_[d.embedded_[ei]].name) +
                                    " lies outside the domain",
                                {Subject::embedded(embedded_at[ei]),
                                 Subject::curve(d.curves_[d.embedded_[ei]].name)});
    }
    // Orientation: domain on the left.
    for (size_t li = 0; li < loops.size(); ++li) {
        DomainLoop& l = loops[li];
        l.hole = li != outer;
        const bool ccw = l.area > 0.0;
        if (ccw == l.hole) {
            std::reverse(l.items.begin(), l.items.end());
            for (CurveUse& u : l.items) u.reversed = !u.reversed;
            l.area = -l.area;
            std::reverse(rings[li].begin(), rings[li].end());
        }
    }

    for (const auto& r : rings) d.box_.add(box_of(r));
    d.loops_.push_back(std::move(loops[outer]));
    d.outlines_.push_back(std::move(rings[outer]));
    for (size_t li = 0; li < loops.size(); ++li) {
        if (li == outer) continue;
        d.loops_.push_back(std::move(loops[li]));
        d.outlines_.push_back(std::move(rings[li]));
    }
    for (CurveId c : d.embedded_) d.box_.add(box_of(flat[c].points));
    return d;
}

}  // namespace meshd::core
