// Curve spacing made to agree with the interior field; see agreement.hpp.

#include "pipeline/agreement.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "layers/layers.hpp"
#include "meshd/core/errors.hpp"
#include "pipeline/estimate.hpp"

namespace meshd::core {

namespace {

// A violating segment is probed at this many places at most (its length over the field,
// rounded up): enough for the caps' cones to cover it between probes.
constexpr double kMaxProbesPerSegment = 256.0;

// The interior cap: the fine segments found so far and, under eq. 6.1, every point of the
// boundary at the size it was placed for. eq. 6.1 averages segment lengths with weights 1/d,
// so next to any curve whose spacing grows along it (an airfoil's, tenfold from the leading
// edge to the chord's middle) it is coarser than the curve by a little or a lot; capping it at
// the curve's own sizes everywhere costs a query per evaluation of a field that is a treecode
// query already. An expression is the user's field: only its disagreements are capped.
// Its cones grow by kFrontCapRatio from the layers' outer edge and from the boundary's points
// under eq. 6.1, by kAgreementCapRatio from the fine segments of an expression's field.
void set_interior_cap(SizeField& rho, const Discretisation& d, const std::vector<Vec2>& fine,
                      const std::vector<double>& fine_sizes, bool layers_edge = false) {
    std::vector<Vec2> points = fine;
    std::vector<double> sizes = fine_sizes;
    if (rho.interpolates()) {
        for (VertexId v = 0; v < d.size(); ++v) {
            points.push_back(d.point(v));
            sizes.push_back(d.rho[v]);
        }
    }
    const double ratio = layers_edge || rho.interpolates() ? kFrontCapRatio : kAgreementCapRatio;
    rho.set_interior_cap(std::move(points), std::move(sizes), ratio);
}

// The interior field half a segment inside segment ab at `at` (on the domain's side of a loop
// segment, the smaller of both sides of an embedded one): where the first interior points
// would go, and far enough from the segment's own ends that eq. 6.1 is not just their length
// there. NaN where the field is not defined.
double field_beside(const SizeField& rho, Vec2 a, Vec2 b, bool embedded, Vec2 at) {
    const double l = distance(a, b);
    const Vec2 n = perp((b - a) / l);
    double f = probe_interior(rho, at + (0.5 * l) * n);
    if (embedded) f = std::fmin(f, probe_interior(rho, at - (0.5 * l) * n));
    return f;
}

}  // namespace

double probe_interior(const SizeField& rho, Vec2 p) {
    try {
        return rho.interior(p);
    } catch (const GeometryError&) {
        return NAN;
    }
}

AgreementStats agree_with_interior(const Domain& domain, SizeField& rho, const BoundaryOptions& options,
                                   Discretisation& d, Observer* observer, const std::vector<bool>& walls) {
    AgreementStats stats;
    std::vector<Vec2> caps, fine;
    std::vector<double> cap_sizes, fine_sizes;
    std::map<std::pair<double, double>, double> corner_caps;  // a domain point's cap so far
    set_interior_cap(rho, d, fine, fine_sizes);
    for (int round = 0; round < kAgreementRounds; ++round) {
        const size_t caps_before = caps.size(), fine_before = fine.size();
        for (size_t i = 0; i < d.segments.size(); ++i) {
            const BoundarySegment& s = d.segments[i];
            const Vec2 a = d.point(s.a), b = d.point(s.b);
            const double l = distance(a, b);
            if (!(l > 0.0)) continue;
            const bool embedded = i >= d.loop_segment_count;
            auto probe = [&](Vec2 at) { return field_beside(rho, a, b, embedded, at); };
            const double f = probe(0.5 * (a + b));
            if (f > kAgreementRatio * l) {
                if (!walls.empty() && s.curve != kNoCurve && walls[s.curve]) continue;
                // The field too coarse beside a fine segment: capped at its length there.
                fine.insert(fine.end(), {a, b});
                fine_sizes.insert(fine_sizes.end(), {l, l});
                continue;
            }
            if (!(l > kAgreementRatio * f)) continue;  // agrees (or no field there)
            // The segment too coarse for the field: the curve capped at the field there.
            const int k = static_cast<int>(std::fmin(kMaxProbesPerSegment, std::ceil(l / f)));
            for (int j = 0; j < k; ++j) {
                const Vec2 at = a + ((j + 0.5) / k) * (b - a);
                const double fj = probe(at);
                if (!(fj > 0.0)) continue;
                caps.push_back(at);
                cap_sizes.push_back(fj);
            }
            // The curves will have at least about as many points as probes: past the limit,
            // refused before the probes (and their memory) grow further.
            if (options.max_points && caps.size() > options.max_points)
                refuse_too_many(static_cast<double>(caps.size()), options.max_points);
        }
        // Where curves meet at a domain point (a corner, an embedded line leaving a curve),
        // their first segments within kAgreementRatio of each other: when no interior point
        // fits in between, the triangle closing the corner is made of the two alone, and its
        // angles follow their ratio (a spoke's short segment against a circle's long one: 15
        // degrees).
        //
        // Walls with boundary layers too: their columns stand on the wall's points, so the
        // layers' outer edge repeats the wall's spacing, and the interior is capped at that
        // edge's shortest segments after the layers grow. A short wall segment between two
        // named points (a spoke leaving a circle near the circle's own start point) beside
        // segments 6 to 70 times longer left the interior fine around it and every curve
        // nearby coarse: triangles of 7 to 18 degrees among the random domains with layers.
        // Not where a wall turns by more than kFanTurnDeg: the layers fan round a convex
        // corner (their tops spaced by the fan, layers.hpp) and bunch at a concave one, so the
        // outer edge does not repeat the wall's spacing there (a blunt trailing edge's base
        // capping the surfaces beside it left tops 0.001 apart next to the fan's 0.03).
        {
            std::vector<char> turning_wall(d.size(), 0);
            if (!walls.empty()) {
                size_t at = 0;
                for (const auto& L : d.loops) {
                    const size_t m = L.size();
                    for (size_t i = 0; i < m; ++i) {
                        const BoundarySegment &in = d.segments[at + (i + m - 1) % m], &out = d.segments[at + i];
                        const bool wall = (in.curve != kNoCurve && walls[in.curve]) || (out.curve != kNoCurve && walls[out.curve]);
                        if (!wall) continue;
                        const Vec2 t0 = d.point(in.b) - d.point(in.a), t1 = d.point(out.b) - d.point(out.a);
                        if (std::fabs(std::atan2(cross(t0, t1), dot(t0, t1))) > kFanTurnDeg * std::numbers::pi / 180.0)
                            turning_wall[L[i]] = 1;
                    }
                    at += m;
                }
            }
            std::vector<double> shortest(d.size(), HUGE_VAL), longest(d.size(), 0.0);
            for (const BoundarySegment& s : d.segments) {
                const double l = distance(d.point(s.a), d.point(s.b));
                for (const VertexId v : {s.a, s.b}) {
                    if (d.curve[v] != kNoCurve || !(l > 0.0) || turning_wall[v]) continue;
                    shortest[v] = std::fmin(shortest[v], l);
                    longest[v] = std::fmax(longest[v], l);
                }
            }
            for (VertexId v = 0; v < d.size(); ++v) {
                if (!(longest[v] > kAgreementRatio * shortest[v])) continue;
                const Vec2 p = d.point(v);
                auto [it, fresh] = corner_caps.try_emplace({p.x, p.y}, shortest[v]);
                if (!fresh && !(shortest[v] < 0.9 * it->second)) continue;
                it->second = std::fmin(it->second, shortest[v]);
                caps.push_back(p);
                cap_sizes.push_back(shortest[v]);
            }
        }
        if (caps.size() == caps_before && fine.size() == fine_before) break;
        if (observer && observer->should_stop()) throw Cancelled();
        ++stats.rounds;
        stats.probes = caps.size() + fine.size();
        if (caps.size() > caps_before) {
            rho.set_curve_cap(caps, cap_sizes, kAgreementCapRatio);
            d = discretise_boundary(domain, rho, options, observer);
            if (rho.interpolates()) set_interpolation_sources(rho, d);
        }
        set_interior_cap(rho, d, fine, fine_sizes);
    }
    return stats;
}

void agree_interior_with_front(SizeField& rho, const Discretisation& front) {
    std::vector<Vec2> fine;
    std::vector<double> fine_sizes;
    // Per front point, its longest segment: an embedded segment (a short line leaving a
    // wall, the free part above the column that slid up it) far shorter than a segment
    // beside it gets the interior fine around it, as a corner the walls' agreement would
    // have graded (seed 503 of the random domains: 1.7 against 0.9, the field beside the
    // line 1.47 times its length, 22.9 degrees without).
    std::vector<double> longest(front.size(), 0.0);
    for (const BoundarySegment& s : front.segments) {
        const double l = distance(front.point(s.a), front.point(s.b));
        longest[s.a] = std::fmax(longest[s.a], l);
        longest[s.b] = std::fmax(longest[s.b], l);
    }
    for (size_t i = 0; i < front.segments.size(); ++i) {
        const BoundarySegment& s = front.segments[i];
        const Vec2 a = front.point(s.a), b = front.point(s.b);
        const double l = distance(a, b);
        if (!(l > 0.0)) continue;
        const bool embedded = i >= front.loop_segment_count;
        const bool corner = embedded && std::fmax(longest[s.a], longest[s.b]) > kAgreementRatio * l;
        if (!corner && !(field_beside(rho, a, b, embedded, 0.5 * (a + b)) > kAgreementRatio * l)) continue;
        fine.insert(fine.end(), {a, b});
        fine_sizes.insert(fine_sizes.end(), {l, l});
    }
    set_interior_cap(rho, front, fine, fine_sizes, true);
}

}  // namespace meshd::core
