// Curve spacing made to agree with the interior field; see agreement.hpp.

#include "pipeline/agreement.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "kernel/constructions.hpp"
#include "kernel/crossings.hpp"
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

// A corner capped before and still apart is capped at least this many times lower.
constexpr double kCornerCapStep = 1.5;

// A domain point whose curves' first segments disagree: the size to cap the curves at there,
// and by how much the segments there exceed what is asked (> 1).
struct CornerCap {
    VertexId v;
    double size, excess;
};

// The domain points whose curves' first segments disagree: where the longest is more than
// kAgreementRatio times the shortest (capped at the shortest), or where two neighbouring
// segments (no other between them, the domain inside) would close a triangle of the two alone
// with an angle below kClosingAngleDeg (capped at the shorter of the two). A ratio of 1.5
// closes a right angle at 33.7 degrees but one of 105 at 28.8: a short spoke leaving a coarse
// circle. Only corners of kMinClosingDeg to kMaxClosingDeg: narrower ones close below the
// angle whatever their sides, and the interior front places a point in wider ones. `skip`:
// points left out (walls that fan or bunch there).
std::vector<CornerCap> corner_caps_for(const Discretisation& d, const std::vector<char>& skip) {
    constexpr double kDeg = std::numbers::pi / 180.0;
    struct End {
        VertexId v;
        double angle, length;
        bool arriving;  // a loop segment ending here: the domain lies clockwise of it
    };
    std::vector<End> ends;
    for (size_t i = 0; i < d.segments.size(); ++i) {
        const BoundarySegment& s = d.segments[i];
        const Vec2 a = d.point(s.a), b = d.point(s.b);
        const double l = distance(a, b);
        if (!(l > 0.0)) continue;
        if (d.curve[s.a] == kNoCurve && !skip[s.a]) ends.push_back({s.a, std::atan2(b.y - a.y, b.x - a.x), l, false});
        if (d.curve[s.b] == kNoCurve && !skip[s.b])
            ends.push_back({s.b, std::atan2(a.y - b.y, a.x - b.x), l, i < d.loop_segment_count});
    }
    std::sort(ends.begin(), ends.end(), [](const End& p, const End& q) { return p.v != q.v ? p.v < q.v : p.angle < q.angle; });
    std::vector<CornerCap> out;
    for (size_t first = 0, last; first < ends.size(); first = last) {
        double shortest = HUGE_VAL, longest = 0.0;
        for (last = first; last < ends.size() && ends[last].v == ends[first].v; ++last) {
            shortest = std::fmin(shortest, ends[last].length);
            longest = std::fmax(longest, ends[last].length);
        }
        CornerCap cap{ends[first].v, HUGE_VAL, 1.0};
        if (longest > kAgreementRatio * shortest) cap = {cap.v, shortest, longest / (kAgreementRatio * shortest)};
        const size_t k = last - first;
        for (size_t j = 0; k > 1 && j < k; ++j) {
            const End &p = ends[first + j], &q = ends[first + (j + 1) % k];
            if (p.arriving) continue;  // the wedge from p round to q lies outside the domain
            double theta = q.angle - p.angle;
            if (theta <= 0.0) theta += 2.0 * std::numbers::pi;
            if (theta < kMinClosingDeg * kDeg || theta > kMaxClosingDeg * kDeg) continue;
            const double a = std::fmin(p.length, q.length), b = std::fmax(p.length, q.length);
            // The triangle's angle at the far end of the longer side, opposite the shorter.
            const double allowed = 1.0 / shortest_side_for_angle(1.0, theta, kClosingAngleDeg * kDeg);
            if (b > allowed * a) cap = {cap.v, std::fmin(cap.size, a), std::fmax(cap.excess, b / (allowed * a))};
        }
        if (cap.size < HUGE_VAL) out.push_back(cap);
    }
    return out;
}

// Two loop segments joined along their loop by less than this many times the gap between them
// are the two sides of one sharp corner, not two boundaries facing each other.
constexpr double kWedgeDetour = 10.0;

// Loop segments facing one another across the domain closer than their length over
// kAgreementRatio (a hole almost touching the outer loop, two bodies close together): no
// triangle across such a gap has fair angles unless both sides are spaced at about its width
// (seed 2730 of the random domains: 20 degrees). Caps the curves at the gap's width at the
// nearest points of both. Not two segments their loop joins within kWedgeDetour times the gap
// (the sides of one sharp corner: its tip needs no such spacing), not segments facing across
// a hole (each must have the other on its domain side). Walls with layers too: the layers'
// outer edge repeats their spacing across the strip the cut-backs leave in the gap.
void cap_narrow_gaps(const Discretisation& d, std::vector<Vec2>& caps, std::vector<double>& sizes) {
    const size_t n = d.loop_segment_count;
    std::vector<std::uint32_t> loop_of(n);
    std::vector<double> along(n), loop_length;
    for (size_t k = 0, at = 0; k < d.loops.size(); at += d.loops[k].size(), ++k) {
        double s = 0.0;
        for (size_t i = at; i < at + d.loops[k].size() && i < n; ++i) {
            loop_of[i] = static_cast<std::uint32_t>(k);
            along[i] = s;
            s += distance(d.point(d.segments[i].a), d.point(d.segments[i].b));
        }
        loop_length.push_back(s);
    }
    detail::SegmentSoup soup;  // per segment, its box grown by its length over the ratio
    std::vector<std::uint32_t> segment_of;
    for (size_t i = 0; i < n; ++i) {
        const BoundarySegment& s = d.segments[i];
        const Vec2 a = d.point(s.a), b = d.point(s.b);
        const double r = distance(a, b) / kAgreementRatio;
        if (!(r > 0.0)) continue;
        soup.points.push_back({std::min(a.x, b.x) - r, std::min(a.y, b.y) - r});
        soup.points.push_back({std::max(a.x, b.x) + r, std::max(a.y, b.y) + r});
        soup.segments.push_back({static_cast<std::uint32_t>(soup.points.size() - 2),
                                 static_cast<std::uint32_t>(soup.points.size() - 1)});
        segment_of.push_back(static_cast<std::uint32_t>(i));
    }
    // The free ends of embedded curves (on no loop, the end of no other curve), as points,
    // each with the loop its curve leaves (-1: none). A free end as close to a loop segment
    // facing it is a gap as narrow (seed 12797 of the random domains: a spoke reaching across
    // the gap between two holes ended a third of the local size from the other hole's wall).
    // Not the segments of the loop its curve leaves: a short spoke's end lies beside its own
    // wall, whose spacing at the spoke's foot the corners' caps settle.
    std::vector<std::int32_t> loop_of_vertex(d.size(), -1);
    for (size_t k = 0; k < d.loops.size(); ++k)
        for (const VertexId v : d.loops[k]) loop_of_vertex[v] = static_cast<std::int32_t>(k);
    std::vector<std::uint32_t> ends_at(d.size(), 0);
    for (const auto& line : d.embedded)
        if (line.size() >= 2) ++ends_at[line.front()], ++ends_at[line.back()];
    // Two free ends close together (two embedded curves' ends facing each other: seed 24033 of
    // the random domains with layers, ends 0.55 of the field apart closing a triangle with an
    // interior point at 27.9 degrees) are such a gap too, where the segment at either end is
    // longer than kAgreementRatio times it. Each end's box is grown by its segment's length
    // over the ratio, as the loop segments' are: a pair of an end and a loop segment that
    // the larger box adds fails the test below anyway (the segment is then shorter than
    // kAgreementRatio times the gap).
    struct FreeEnd {
        VertexId v;
        std::int32_t leaves;  // the loop its curve leaves, -1: none
        double segment;       // the length of the curve's segment at this end
    };
    const std::uint32_t first_end = static_cast<std::uint32_t>(soup.segments.size());
    std::vector<FreeEnd> free_ends;
    for (const auto& line : d.embedded) {
        if (line.size() < 2) continue;
        for (const bool front : {true, false}) {
            const VertexId v = front ? line.front() : line.back();
            if (loop_of_vertex[v] >= 0 || ends_at[v] != 1) continue;
            const VertexId next = front ? line[1] : line[line.size() - 2];
            const double l = distance(d.point(v), d.point(next));
            free_ends.push_back({v, loop_of_vertex[front ? line.back() : line.front()], l});
            const Vec2 e = d.point(v);
            const double r = l / kAgreementRatio;
            soup.points.push_back({e.x - r, e.y - r});
            soup.points.push_back({e.x + r, e.y + r});
            soup.segments.push_back({static_cast<std::uint32_t>(soup.points.size() - 2),
                                     static_cast<std::uint32_t>(soup.points.size() - 1)});
        }
    }
    detail::for_each_box_overlap(soup, [&](std::uint32_t p, std::uint32_t q) {
        if (p >= first_end && q >= first_end) {
            const FreeEnd &f = free_ends[p - first_end], &g = free_ends[q - first_end];
            const Vec2 e = d.point(f.v), o = d.point(g.v);
            const double gap = distance(e, o);
            if (!(gap > 0.0) || !(std::fmax(f.segment, g.segment) > kAgreementRatio * gap)) return;
            caps.insert(caps.end(), {e, o});
            sizes.insert(sizes.end(), {gap, gap});
            return;
        }
        if (p >= first_end || q >= first_end) {
            const FreeEnd& end = free_ends[std::max(p, q) - first_end];
            const std::uint32_t i = segment_of[std::min(p, q)];
            const BoundarySegment& s = d.segments[i];
            if (end.leaves >= 0 && loop_of[i] == static_cast<std::uint32_t>(end.leaves)) return;
            const Vec2 a = d.point(s.a), b = d.point(s.b), e = d.point(end.v), on_s = nearest_on(a, b, e);
            const double gap = distance(e, on_s);
            if (!(gap > 0.0) || !(distance(a, b) > kAgreementRatio * gap) || !(cross(b - a, e - on_s) > 0.0)) return;
            caps.insert(caps.end(), {on_s, e});
            sizes.insert(sizes.end(), {gap, gap});
            return;
        }
        const std::uint32_t i = segment_of[p], j = segment_of[q];
        const BoundarySegment &s = d.segments[i], &t = d.segments[j];
        if (s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b) return;
        const Vec2 a = d.point(s.a), b = d.point(s.b), c = d.point(t.a), e = d.point(t.b);
        // The nearest points of two segments that do not cross: an end of one and its
        // nearest point on the other.
        Vec2 on_s = a, on_t = nearest_on(c, e, a);
        double gap = distance(on_s, on_t);
        const auto consider = [&](Vec2 x, Vec2 y) {
            if (distance(x, y) < gap) {
                gap = distance(x, y);
                on_s = x;
                on_t = y;
            }
        };
        consider(b, nearest_on(c, e, b));
        consider(nearest_on(a, b, c), c);
        consider(nearest_on(a, b, e), e);
        if (!(gap > 0.0) || !(std::max(distance(a, b), distance(c, e)) > kAgreementRatio * gap)) return;
        // Facing across the domain: each lies on the other's domain side (its left).
        if (!(cross(b - a, on_t - on_s) > 0.0) || !(cross(e - c, on_s - on_t) > 0.0)) return;
        if (loop_of[i] == loop_of[j]) {
            const double path = std::fabs(along[i] + distance(a, on_s) - along[j] - distance(c, on_t));
            if (std::fmin(path, loop_length[loop_of[i]] - path) < kWedgeDetour * gap) return;
        }
        caps.insert(caps.end(), {on_s, on_t});
        sizes.insert(sizes.end(), {gap, gap});
    });
}

// Per curve of d, whether none of the cones (points, sizes, growing by ratio per element) comes
// below the largest size the curve read where it read one: rho along it is the same once they
// join the curve cap, and so are its points.
std::vector<bool> untouched_by(const Discretisation& d, const std::vector<Vec2>& points,
                               const std::vector<double>& sizes, size_t from, double ratio) {
    std::vector<bool> keep(d.reads.size(), false);
    for (size_t c = 0; c < d.reads.size(); ++c) {
        const CurveReads& r = d.reads[c];
        if (r.box.empty()) continue;
        keep[c] = true;
        for (size_t i = from; i < points.size() && keep[c]; ++i) {
            // (A margin for the rounding of the cones' sums, as in GradationField.)
            const double lowest = sizes[i] + (ratio - 1.0) * std::sqrt(r.box.distance2(points[i]));
            keep[c] = lowest - 1e-12 * lowest >= r.largest;
        }
    }
    return keep;
}

}  // namespace

double probe_interior(const SizeField& rho, Vec2 p) {
    try {
        return rho.interior_scattered(p);
    } catch (const GeometryError&) {
        return NAN;
    }
}

AgreementStats agree_with_interior(const Domain& domain, SizeField& rho, const BoundaryOptions& options,
                                   Discretisation& d, Observer* observer, const std::vector<bool>& walls,
                                   const SizeCaps& closing) {
    AgreementStats stats;
    std::vector<Vec2> caps = closing.points, fine;
    std::vector<double> cap_sizes = closing.sizes, fine_sizes;
    std::map<std::pair<double, double>, double> corner_caps;  // a domain point's cap so far
    set_interior_cap(rho, d, fine, fine_sizes);
    for (int round = 0; round < kAgreementRounds; ++round) {
        const size_t caps_before = round == 0 ? 0 : caps.size(), fine_before = fine.size();
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
        cap_narrow_gaps(d, caps, cap_sizes);
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
            for (const CornerCap& c : corner_caps_for(d, turning_wall)) {
                const Vec2 p = d.point(c.v);
                double size = c.size;
                auto [it, fresh] = corner_caps.try_emplace({p.x, p.y}, size);
                if (!fresh && !(size < 0.9 * it->second)) {
                    // Capped before and still apart: a curve here short for its cap's cone
                    // rounded its count of segments down (an arc of 1.2 segments between a
                    // spoke's foot and the circle's start point, placed as one 1.9 times the
                    // spoke's length: 21 degrees, seed 2539 of the random domains). The cap
                    // is lowered by the ratio left over, and by a third at least: a ratio
                    // left over of 6% moved nothing, as a curve of one segment
                    // rounds up to two only under a cone well below its length (a hole's side
                    // of one segment 1.51 times the embedded line leaving its end: 29.7
                    // degrees, seed 2478).
                    size = it->second / std::fmax(c.excess, kCornerCapStep);
                }
                it->second = std::fmin(it->second, size);
                caps.push_back(p);
                cap_sizes.push_back(size);
            }
        }
        if (caps.size() == caps_before && fine.size() == fine_before) break;
        if (observer && observer->should_stop()) throw Cancelled();
        ++stats.rounds;
        stats.probes = caps.size() + fine.size();
        if (caps.size() > caps_before) {
            // Curves no new cone reaches keep their points (an airfoil beside a far field the
            // caps space again).
            const KeptCurves kept{d, untouched_by(d, caps, cap_sizes, caps_before, kAgreementCapRatio)};
            stats.curves_kept += static_cast<size_t>(std::count(kept.keep.begin(), kept.keep.end(), true));
            rho.set_curve_cap(caps, cap_sizes, kAgreementCapRatio);
            d = discretise_boundary(domain, rho, options, observer, &kept);
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
