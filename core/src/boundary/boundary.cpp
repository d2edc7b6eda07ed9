// Graded points on the curves of a domain (paper, section 3); see boundary.hpp.

#include "boundary/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "geometry/curve.hpp"
#include "geometry/nesting.hpp"
#include "kernel/constructions.hpp"
#include "kernel/crossings.hpp"
#include "kernel/tolerances.hpp"
#include "meshd/core/errors.hpp"
#include "boundary/spacing.hpp"

namespace meshd::core {

namespace {

// The size that keeps the shape of curve g near parameter t of its smooth piece [ta, tb]:
// kMaxSegmentTurn times the radius of curvature, from the turn of the tangent over a short
// stretch inside the piece (never across its corners); never below min_size.
double shape_cap(const Curve& g, double ta, double tb, double t, double min_size) {
    const double inset = 1e-9 * (tb - ta), step = 1e-4 * (tb - ta);
    const double t0 = std::fmax(t - step, ta + inset), t1 = std::fmin(t + step, tb - inset);
    const Vec2 d0 = g.derivative(t0), d1 = g.derivative(t1);
    const double turn = angle_between(d0, d1);
    if (!(turn > 0.0)) return HUGE_VAL;  // straight here
    return std::fmax(tol::kMaxSegmentTurn * distance(g.point(t0), g.point(t1)) / turn, min_size);
}

// The angle between two directions (radians, 0 for a zero vector).
double turn_between(Vec2 a, Vec2 b) {
    const double t = angle_between(a, b);
    return std::isfinite(t) ? t : 0.0;
}

// Halves every step of `stations` (spacing coordinates from sa, on the smooth piece [ta, tb] of
// g) over which the tangent turns by more than kMaxStepTurn, until none does. shape_cap
// bounds the size where rho is sampled; a density that jumps (a size far beyond the curve next
// to a fine one) can still make the march step over a leading edge, which would leave a chord
// across the curve's shape, or a closed curve as a single point.
std::vector<double> keep_shape(const std::vector<double>& stations, const Curve& g, const CurveParametrisation& param,
                               double sa, double ta, double tb) {
    const double inset = 1e-9 * (tb - ta);
    auto tangent = [&](double s) { return g.derivative(std::clamp(param.param_at(sa + s), ta + inset, tb - inset)); };
    std::vector<double> out{stations.front()};
    struct Step {
        double s0, s1;
        Vec2 d0, d1;
        int depth;
    };
    std::vector<Step> todo;
    Vec2 d_prev = tangent(stations.front());
    for (size_t i = 0; i + 1 < stations.size(); ++i) {
        const Vec2 d_next = tangent(stations[i + 1]);
        todo.push_back({stations[i], stations[i + 1], d_prev, d_next, 0});
        while (!todo.empty()) {
            const Step st = todo.back();
            todo.pop_back();
            const double sm = 0.5 * (st.s0 + st.s1);
            const Vec2 dm = tangent(sm);
            if (st.depth < 40 && sm > st.s0 && sm < st.s1 &&
                turn_between(st.d0, dm) + turn_between(dm, st.d1) > tol::kMaxStepTurn) {
                todo.push_back({sm, st.s1, dm, st.d1, st.depth + 1});  // the later half after the earlier
                todo.push_back({st.s0, sm, st.d0, dm, st.depth + 1});
            } else {
                out.push_back(st.s1);
            }
        }
        d_prev = d_next;
    }
    return out;
}

// Under the agreement's curve cap (a lower envelope of cones about its probes), rho along a
// curve has a kink at every cone's apex and wherever two cones meet; the density profile would
// bisect each down to its interpolation tolerance, some 15 samples a cone, for a precision
// Lo's march does not need there. Its intervals stop at this fraction of the size instead.
constexpr double kCappedStationFloor = 1.0 / 32.0;

// Places the points of one curve after another, sharing the domain points at curve ends.
class CurveSampler {
public:
    CurveSampler(const Domain& domain, const SizeField& rho, const BoundaryOptions& opt)
        : domain_(domain), rho_(rho), opt_(opt), domain_vertex_(domain.points().size(), kNoVertex) {
        d_.curve_vertices.resize(domain.curves().size());
        d_.reads.resize(domain.curves().size());
        d_.end_rho.resize(domain.curves().size(), {HUGE_VAL, HUGE_VAL});
    }

    VertexId add_vertex(Vec2 p, CurveId c, double t, double size) {
        d_.x.push_back(p.x);
        d_.y.push_back(p.y);
        d_.curve.push_back(c);
        d_.param.push_back(t);
        d_.rho.push_back(size);
        if (opt_.max_points && d_.x.size() > opt_.max_points)
            throw GeometryError(GeometryErrorKind::TooManyPoints,
                                "the boundary alone needs more than " + std::to_string(opt_.max_points) +
                                    " points");
        return static_cast<VertexId>(d_.x.size() - 1);
    }

    VertexId domain_vertex(PointId p) {
        if (domain_vertex_[p] == kNoVertex)
            domain_vertex_[p] = add_vertex(domain_.points()[p].position, kNoCurve, 0.0, HUGE_VAL);
        return domain_vertex_[p];
    }

    void discretise(CurveId c) {
        const DomainCurve& dc = domain_.curves()[c];
        const Curve& g = *dc.geometry;
        // The domain's own arc length, but for the paper's control polygon of a B-spline.
        std::unique_ptr<CurveParametrisation> own;
        if ((opt_.spline_spacing == SplineSpacing::ControlPolygon && g.as_bspline()) || !dc.arc_length)
            own = make_parametrisation(g, opt_.spline_spacing);
        const CurveParametrisation* param = own ? own.get() : dc.arc_length.get();
        std::vector<VertexId>& out = d_.curve_vertices[c];
        CurveReads& reads = d_.reads[c];
        reads.floor = station_floor();
        std::vector<double> cuts{g.t_begin()};
        for (double t : g.corners()) cuts.push_back(t);
        cuts.push_back(g.t_end());
        // rho where the curve places a point at parameter t of its piece [ta, tb].
        // shape_cap is kMaxSegmentTurn times the chord over the turn of a short stretch: on a
        // circle of radius r, kMaxSegmentTurn r sin(d / 2) / (d / 2) for a turn d of at most
        // 2e-4 of the piece, within 1e-6 of kMaxSegmentTurn r. A size below 0.9 times that for
        // the curve's least radius is the smaller whatever the cap: lines and arcs skip its
        // four evaluations of the curve and its arc tangent a station.
        const double no_cap_below = 0.9 * tol::kMaxSegmentTurn * g.least_radius();
        auto size_at = [&](double ta, double tb, double t) {
            const Vec2 p = g.point(t);
            const double h = rho_.on_curve(c, p);
            reads.box.add(p);
            reads.largest = std::fmax(reads.largest, h);
            if (h < no_cap_below) return h;
            return std::fmin(h, shape_cap(g, ta, tb, t, rho_.min_size()));
        };
        auto end_vertex = [&](PointId p, double ta, double tb, double t, double& curve_end) {
            const VertexId v = domain_vertex(p);
            curve_end = size_at(ta, tb, t);
            d_.rho[v] = std::fmin(d_.rho[v], curve_end);
            return v;
        };
        out.push_back(end_vertex(dc.from, cuts[0], cuts[1], cuts[0], d_.end_rho[c][0]));

        for (size_t k = 0; k + 1 < cuts.size(); ++k) {
            const double sa = param->spacing_at(cuts[k]);
            const double sb = k + 2 == cuts.size() ? param->length() : param->spacing_at(cuts[k + 1]);
            const double len = sb - sa;
            if (len > 0.0) {
                const DensityProfile profile = sample_density(
                    len,
                    [&](double s) { return size_at(cuts[k], cuts[k + 1], param->param_at(sa + s)); },
                    rho_.least_size(), stations_left_, station_floor());
                stations_left_ -= profile.s.size();
                reads.stations += profile.s.size();
                std::vector<double> stations =
                    keep_shape(graded_stations(profile, opt_.max_points ? opt_.max_points : SIZE_MAX), g, *param, sa,
                               cuts[k], cuts[k + 1]);
                // A closed curve without corners is a loop of its own points: three at least.
                if (dc.from == dc.to && cuts.size() == 2 && stations.size() < 4) stations = {0.0, len / 3.0, 2.0 * len / 3.0, len};
                for (size_t i = 1; i + 1 < stations.size(); ++i) {
                    const double t = param->param_at(sa + stations[i]);
                    out.push_back(add_vertex(g.point(t), c, t, size_at(cuts[k], cuts[k + 1], t)));
                }
            }
            if (k + 2 < cuts.size()) {
                // A corner inside the curve: the smaller size of the pieces on either side.
                const double t = cuts[k + 1];
                out.push_back(add_vertex(g.point(t), c, t,
                                         std::fmin(size_at(cuts[k], cuts[k + 1], t), size_at(cuts[k + 1], cuts[k + 2], t))));
            }
        }
        const size_t last = cuts.size() - 1;
        out.push_back(end_vertex(dc.to, cuts[last - 1], cuts[last], cuts[last], d_.end_rho[c][1]));
    }

    // Curve c's points as `from` placed them (for the same rho along c), with its end sizes
    // and reads: what discretise(c) would make.
    void keep(CurveId c, const Discretisation& from) {
        const DomainCurve& dc = domain_.curves()[c];
        const std::vector<VertexId>& was = from.curve_vertices[c];
        std::vector<VertexId>& out = d_.curve_vertices[c];
        auto end_vertex = [&](PointId p, double size) {
            const VertexId v = domain_vertex(p);
            d_.rho[v] = std::fmin(d_.rho[v], size);
            return v;
        };
        if (from.reads[c].stations > stations_left_ || from.reads[c].floor != station_floor()) {
            discretise(c);  // refused, as placing it again would be; or placed with another floor
            return;
        }
        d_.end_rho[c] = from.end_rho[c];
        d_.reads[c] = from.reads[c];
        stations_left_ -= from.reads[c].stations;
        out.push_back(end_vertex(dc.from, from.end_rho[c][0]));
        for (size_t i = 1; i + 1 < was.size(); ++i)
            out.push_back(add_vertex(from.point(was[i]), c, from.param[was[i]], from.rho[was[i]]));
        out.push_back(end_vertex(dc.to, from.end_rho[c][1]));
    }

    double station_floor() const { return rho_.curve_capped() ? kCappedStationFloor : 0.0; }

    Discretisation finish() && { return std::move(d_); }
    Discretisation& result() { return d_; }

private:
    const Domain& domain_;
    const SizeField& rho_;
    const BoundaryOptions& opt_;
    std::vector<VertexId> domain_vertex_;
    Discretisation d_;
    // Samples of rho all curves together may still take: about four per point allowed, so
    // that a density asking for too many points costs about as much as the largest mesh.
    size_t stations_left_ = opt_.max_points ? 4 * opt_.max_points + 64 : size_t{1} << 31;
};

// The segment of loop li nearest to p (loop segments are in loop order, each loop's as many
// as its points).
size_t nearest_segment_of_loop(const Discretisation& d, size_t li, Vec2 p) {
    size_t first = 0;
    for (size_t k = 0; k < li; ++k) first += d.loops[k].size();
    size_t best = first;
    double best_d2 = HUGE_VAL;
    for (size_t i = first; i < first + d.loops[li].size(); ++i) {
        const double d2 = norm2(nearest_on(d.point(d.segments[i].a), d.point(d.segments[i].b), p) - p);
        if (d2 < best_d2) {
            best_d2 = d2;
            best = i;
        }
    }
    return best;
}

// The middle of a chord and half its length, added to caps (CoarseChords::finer).
void add_finer(const Discretisation& d, const BoundarySegment& chord, SizeCaps& caps) {
    caps.points.push_back(0.5 * (d.point(chord.a) + d.point(chord.b)));
    caps.sizes.push_back(0.5 * distance(d.point(chord.a), d.point(chord.b)));
}

// The discretised loops nest as the domain's do: every hole and embedded curve inside the
// outer loop and in no hole. Chords that cross nothing can still break that: the chords of a
// far field spaced at several times its distance from an airfoil passed on the airfoil's far
// side and left it outside the domain, whole (found by fuzz/fuzz_request, crash 83a027ff),
// and a concave curve's chords bulge past it. Each loop and embedded curve is probed at the
// middle of its first segment, which lies on no other polygon (none crosses or touches
// another: checked before). Throws CoarseChords naming the first fault, with the chord
// nearest each probe that failed.
void check_nesting(const Domain& domain, const Discretisation& d) {
    if (d.loops.size() < 2 && d.embedded.empty()) return;
    std::vector<std::vector<Vec2>> rings(d.loops.size());
    size_t outer = 0;
    for (size_t li = 0; li < d.loops.size(); ++li) {
        for (const VertexId v : d.loops[li]) rings[li].push_back(d.point(v));
        if (!domain.loops()[li].hole) outer = li;
    }
    detail::LoopNesting nesting(rings, outer);
    std::string message;
    std::vector<Subject> subjects;
    SizeCaps finer;
    auto fault = [&](size_t by_loop, Vec2 probe, const std::string& left, const char* verb, const char* where) {
        const BoundarySegment& chord = d.segments[nearest_segment_of_loop(d, by_loop, probe)];
        add_finer(d, chord, finer);
        if (!message.empty()) return;
        const std::string& by = domain.curves()[chord.curve].name;
        message = "the discretised curve \"" + by + "\" " + verb + " \"" + left + "\" " + where + " near (" +
                  std::to_string(probe.x) + ", " + std::to_string(probe.y) +
                  "): the density is too coarse for the gap between them";
        subjects = {Subject::curve(by), Subject::curve(left)};
    };
    auto check = [&](Vec2 probe, size_t own_loop, const std::string& name) {
        if (!nesting.inside_outer(probe)) fault(outer, probe, name, "leaves", "outside the domain");
        else if (const auto h = nesting.hole_holding(probe, own_loop)) fault(*h, probe, name, "takes", "into its hole");
    };
    for (size_t li = 0; li < d.loops.size(); ++li) {
        if (li == outer) continue;
        check(0.5 * (rings[li][0] + rings[li][1]), li,
              domain.curves()[domain.loops()[li].items.front().curve].name);
    }
    for (size_t e = 0; e < d.embedded.size(); ++e) {
        const std::vector<VertexId>& chain = d.embedded[e];
        if (chain.size() < 2) continue;
        check(0.5 * (d.point(chain[0]) + d.point(chain[1])), outer, domain.curves()[domain.embedded()[e]].name);
    }
    if (!message.empty()) throw CoarseChords(std::move(message), std::move(subjects), std::move(finer));
}

}  // namespace

void link_loops(const Domain& domain, Discretisation& d) {
    d.loops.clear();
    d.segments.clear();
    d.embedded.clear();
    for (const auto& l : domain.loops()) {
        std::vector<VertexId> cycle;
        for (const auto& u : l.items) {
            const auto& v = d.curve_vertices[u.curve];
            if (u.reversed) cycle.insert(cycle.end(), v.rbegin(), v.rend() - 1);
            else cycle.insert(cycle.end(), v.begin(), v.end() - 1);
            // segments follow below
        }
        d.loops.push_back(std::move(cycle));
    }
    for (size_t li = 0; li < domain.loops().size(); ++li) {
        for (const auto& u : domain.loops()[li].items) {
            const auto& v = d.curve_vertices[u.curve];
            for (size_t i = 0; i + 1 < v.size(); ++i) {
                if (u.reversed) d.segments.push_back({v[v.size() - 1 - i], v[v.size() - 2 - i], u.curve});
                else d.segments.push_back({v[i], v[i + 1], u.curve});
            }
        }
    }
    d.loop_segment_count = d.segments.size();
    for (CurveId c : domain.embedded()) {
        d.embedded.push_back(d.curve_vertices[c]);
        const auto& v = d.curve_vertices[c];
        for (size_t i = 0; i + 1 < v.size(); ++i) d.segments.push_back({v[i], v[i + 1], c});
    }
}

Discretisation discretise_boundary(const Domain& domain, const SizeField& rho,
                                   const BoundaryOptions& options, Observer* observer, const KeptCurves* kept) {
    CurveSampler b(domain, rho, options);
    std::vector<CurveId> order;
    for (const auto& l : domain.loops())
        for (const auto& u : l.items) order.push_back(u.curve);
    for (CurveId c : domain.embedded()) order.push_back(c);
    // Curves in a stable order (by id) so that vertex numbering does not depend on loops.
    std::vector<CurveId> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    double done = 0.0, total = 0.0;
    for (CurveId c : sorted) total += domain.curves()[c].length;
    for (CurveId c : sorted) {
        if (observer) {
            if (observer->should_stop()) throw Cancelled();
            observer->on_progress(Stage::Boundary, total > 0.0 ? done / total : 0.0);
        }
        if (kept && c < kept->keep.size() && kept->keep[c]) b.keep(c, kept->from);
        else b.discretise(c);
        done += domain.curves()[c].length;
    }
    Discretisation& d = b.result();
    link_loops(domain, d);

    // The chords of nearby curves can cross even when the curves do not (too coarse a
    // density across a narrow gap): the mesher needs a simple polygon, so check.
    detail::SegmentSoup soup;
    soup.points.reserve(d.size());
    for (VertexId v = 0; v < d.size(); ++v) soup.points.push_back(d.point(v));
    soup.segments.reserve(d.segments.size());
    for (const auto& s : d.segments) soup.segments.push_back({s.a, s.b});
    // Every crossing pair's chords go into the refusal's caps (each once), the first pair
    // (the smallest indices) into its message.
    std::optional<std::pair<std::uint32_t, std::uint32_t>> first;
    std::vector<char> crossed(d.segments.size(), 0);
    detail::for_each_crossing(soup, [&](std::uint32_t i, std::uint32_t j) {
        if (!first || std::pair{i, j} < *first) first = std::pair{i, j};
        crossed[i] = crossed[j] = 1;
    });
    if (first) {
        const auto& s1 = d.segments[first->first];
        const auto& s2 = d.segments[first->second];
        const std::string& n1 = domain.curves()[s1.curve].name;
        const std::string& n2 = domain.curves()[s2.curve].name;
        const Vec2 at = d.point(s1.a);
        SizeCaps finer;
        for (size_t i = 0; i < d.segments.size(); ++i)
            if (crossed[i]) add_finer(d, d.segments[i], finer);
        throw CoarseChords("the discretised curves \"" + n1 + "\" and \"" + n2 + "\" cross near (" +
                               std::to_string(at.x) + ", " + std::to_string(at.y) +
                               "): the density is too coarse for the gap between them",
                           {Subject::curve(n1), Subject::curve(n2)}, std::move(finer));
    }
    // Simple polygons now; each must still run the way its loop does (outer counter-clockwise,
    // holes clockwise), or the triangulation would take the outside for the domain.
    for (size_t li = 0; li < d.loops.size(); ++li) {
        const std::vector<VertexId>& cycle = d.loops[li];
        double twice_area = 0.0;
        for (size_t i = 0; i < cycle.size(); ++i) twice_area += cross(d.point(cycle[i]), d.point(cycle[(i + 1) % cycle.size()]));
        const bool hole = domain.loops()[li].hole;
        if (!(hole ? twice_area < 0.0 : twice_area > 0.0)) {
            const std::string& name = domain.curves()[domain.loops()[li].items.front().curve].name;
            throw GeometryError(GeometryErrorKind::DiscretisationCrosses,
                                "the discretised loop of curve \"" + name +
                                    "\" does not keep its shape: the density is too coarse for it",
                                {Subject::curve(name)});
        }
    }
    check_nesting(domain, d);
    if (observer) observer->on_progress(Stage::Boundary, 1.0);
    return std::move(b).finish();
}

BoundaryTriangulation triangulate_boundary(const Discretisation& d) {
    BoundaryTriangulation w;
    w.points = points_of(d);
    w.triangles = triangulate_delaunay(w.points, constraints_of(d)).triangles;
    return w;
}

Array<Vec2> points_of(const Discretisation& d) {
    Array<Vec2> pts;
    pts.reserve(d.size());
    for (VertexId v = 0; v < d.size(); ++v) pts.push_back(d.point(v));
    return pts;
}

std::vector<Constraint> constraints_of(const Discretisation& d) {
    std::vector<Constraint> cons;
    cons.reserve(d.segments.size());
    for (size_t i = 0; i < d.segments.size(); ++i)
        cons.push_back({d.segments[i].a, d.segments[i].b, i < d.loop_segment_count});
    return cons;
}

void set_interpolation_sources(SizeField& rho, const Discretisation& d) {
    std::vector<Vec2> starts;
    std::vector<double> lengths;
    starts.reserve(d.segments.size());
    lengths.reserve(d.segments.size());
    for (const auto& s : d.segments) {
        starts.push_back(d.point(s.a));
        lengths.push_back(distance(d.point(s.a), d.point(s.b)));
    }
    rho.set_boundary_segments(std::move(starts), std::move(lengths));
}

namespace {

void accumulate(SpacingStats& st, double ratio) {
    const double e = std::fabs(ratio - 1.0);
    if (st.segments == 0) st.min_ratio = st.max_ratio = ratio;
    ++st.segments;
    st.mean_abs_error += e;
    st.rms_error += e * e;
    st.max_abs_error = std::fmax(st.max_abs_error, e);
    st.min_ratio = std::fmin(st.min_ratio, ratio);
    st.max_ratio = std::fmax(st.max_ratio, ratio);
}

void finalise(SpacingStats& st) {
    if (st.segments == 0) return;
    st.mean_abs_error /= static_cast<double>(st.segments);
    st.rms_error = std::sqrt(st.rms_error / static_cast<double>(st.segments));
}

}  // namespace

SpacingReport spacing_report(const Domain& domain, const Discretisation& d) {
    SpacingReport r;
    r.per_curve.resize(domain.curves().size());
    // The size a point was placed for: its own (capped to keep the curve's shape, see
    // shape_cap), or at a curve end the one of the segment's curve at that end (the end next
    // to the segment's other point: both ends are one point on a closed curve).
    auto size = [&](VertexId v, VertexId other, CurveId c) {
        if (d.curve[v] == c) return d.rho[v];
        const std::vector<VertexId>& on_curve = d.curve_vertices[c];
        const bool at_start = v == on_curve.front() && other == on_curve[1];
        return d.end_rho[c][at_start ? 0 : 1];
    };
    for (const auto& s : d.segments) {
        const Vec2 a = d.point(s.a), b = d.point(s.b);
        const double target = 0.5 * (size(s.a, s.b, s.curve) + size(s.b, s.a, s.curve));
        const double ratio = distance(a, b) / target;
        accumulate(r.per_curve[s.curve], ratio);
        accumulate(r.overall, ratio);
    }
    for (auto& st : r.per_curve) finalise(st);
    finalise(r.overall);
    return r;
}

}  // namespace meshd::core
