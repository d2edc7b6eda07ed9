#include "layers/layers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <span>
#include <tuple>
#include <unordered_map>

#include "geometry/curve.hpp"
#include "kernel/constructions.hpp"
#include "kernel/crossings.hpp"
#include "kernel/predicates.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

using K = GeometryErrorKind;

constexpr double kDeg = std::numbers::pi / 180.0;
/// A column's lengthening at a concave corner is capped here (a corner of about 39 degrees).
constexpr double kMaxStretch = 3.0;
/// Columns keep below this share of the distance along their ray to another boundary.
constexpr double kGapShare = 0.45;
/// Between facing layers a strip at least this share of the local size stays free.
constexpr double kStripShare = 1.0;
/// After a cut-back the layers' outer edge rises from one column's top to the next by at
/// most this share of the way across (a sawtooth of full and cut columns leaves notches that
/// no isotropic triangle fills well).
constexpr double kTopSlope = 0.5;
/// Rounds of cutting tops that come too close (cut_close_tops), at most; each takes a layer.
constexpr int kCloseTopRounds = 20;
/// Tops of columns on bases this close along a chain (a concave corner's) may come close.
constexpr size_t kCloseTopBases = 2;
/// A sliding column reaches at most this share of the line it slides on.
constexpr double kSlideShare = 0.3;
/// Neighbouring tops more than this many times the field apart cap the wall below them (the
/// ratio the curves' agreement allows between a segment and the field beside it).
constexpr double kTopsRatio = 1.5;
/// A wall's end column leaning along the line it slides on stands its top 2 H sin(lean / 2)
/// from its neighbour's: past this many times the field there, columns on the end's base fill
/// the gap (split_wide_fans). Below kTopsRatio: that outer-edge segment and the line beside the
/// end's top meet at a corner of fixed points whose spacing the field sets on the line's side
/// (seed 1680 of the random domains: 1.4 times the field, 29.7 degrees).
constexpr double kLeaningTopsRatio = 1.25;
/// A wall end slides along a line that meets it at a domain angle between these (degrees).
/// From kSlideMaxDeg on, the line leaves the wall's normal by more than a fan's step, and the
/// end turns a fan round to it instead: a lone column leaning further stands its top about
/// 2 H sin(lean / 2) from its neighbour's (seed 770 of the random domains: a line at 154
/// degrees, tops 1.3 H apart, one outer-edge segment six times the interior's size beside it).
constexpr double kSlideMinDeg = 20.0, kSlideMaxDeg = 90.0 + kFanStepDeg;

Vec2 unit(Vec2 v) {
    const double n = norm(v);
    return n > 0.0 ? v / n : Vec2{0.0, 0.0};
}
Vec2 rotate(Vec2 v, double a) { return {v.x * std::cos(a) - v.y * std::sin(a), v.x * std::sin(a) + v.y * std::cos(a)}; }
// The lengthening of a column at `cosine` to a wall's normal: its layers keep their heights
// above that wall (capped at kMaxStretch).
double stretch_for(double cosine) { return cosine > 1.0 / kMaxStretch ? 1.0 / cosine : kMaxStretch; }

// The index of each point of `points` (a plan's fan corners), for lookups in log time.
std::map<std::pair<double, double>, size_t> index_of_points(const std::vector<Vec2>& points) {
    std::map<std::pair<double, double>, size_t> at;
    for (size_t i = 0; i < points.size(); ++i) at.emplace(std::pair{points[i].x, points[i].y}, i);
    return at;
}

struct Column {
    Column(VertexId b, Vec2 d, double s, int sp) : base(b), dir(d), key(d), stretch(s), spec(sp) {}
    VertexId base;
    Vec2 dir;        // unit, into the domain
    Vec2 key;        // dir as first made (a split fan column: its pivot's), for LayerColumn
    double stretch;  // >= 1
    int spec;
    int want = 0;  // layers the spec and rho ask for
    int n = 0;     // layers kept
    /// A column that slides along a curve without layers (the boundary curve a wall ends on,
    /// or an embedded curve leaving the wall): its points lie on that curve, at arc lengths
    /// measured from the base (the curve's start or end).
    CurveId slide = kNoCurve;
    bool slide_at_start = false;
    double keep_free = 0.0;  // of an embedded line it slides on (follow_embedded_lines)
    bool spoke = false;      // slides on an embedded line leaving the wall
    std::vector<std::uint32_t> ids;  // per level 0..n: the point's id in the cells
};

struct Chain {
    size_t loop;
    bool closed;
    size_t first = 0, last = 0;  // open: the wall runs from loop vertex `first` to `last` (cyclic)
    std::vector<Column> columns;
};

class Grower {
public:
    Grower(const Domain& domain, const Discretisation& d, const SizeField& rho,
           const std::vector<BoundaryLayerSpec>& specs, size_t max_points, Observer* observer,
           const LayerPlan* plan = nullptr, const std::vector<LayerColumn>* limits = nullptr)
        : domain_(domain), d_(d), rho_(rho), specs_(specs), max_points_(max_points), observer_(observer), plan_(plan),
          limits_(limits) {}

    GrownLayers run() {
        final_ = true;
        grow_columns();
        return build();
    }

    LayerPlan plan() {
        grow_columns();
        SizeCaps caps;
        std::vector<double> heights;
        for (Chain& c : chains_) {
            for (size_t k = 0; k + 1 < c.columns.size(); ++k) {
                const Column &a = c.columns[k], &b = c.columns[k + 1];
                if (a.base != b.base || a.n == 0 || b.n == 0) continue;
                const double gap = distance(level_point(a, a.n), level_point(b, b.n));
                const double tall = std::max(top(a), top(b));
                if (!caps.empty() && caps.points.back() == pt(a.base)) {
                    caps.sizes.back() = std::min(caps.sizes.back(), gap);
                    heights.back() = std::max(heights.back(), tall);
                } else {
                    caps.points.push_back(pt(a.base));
                    caps.sizes.push_back(gap);
                    heights.push_back(tall);
                }
            }
        }
        std::vector<bool> walls(spec_of_.size());
        for (size_t c = 0; c < walls.size(); ++c) walls[c] = spec_of_[c] >= 0;
        return {std::move(caps), std::move(heights), std::move(walls), coarse_tops()};
    }

private:
    // Neighbouring columns on two wall points whose tops stand more than kTopsRatio times the
    // field there apart: a cap at the wall segment's middle that would bring the tops to the
    // field. A convex wall spreads its tops by (R + H) / R (a small circle under layers twice
    // its radius thick: tops 165 apart beside interior triangles of 40), and the field may be
    // finer away from the wall than on it.
    SizeCaps coarse_tops() const {
        SizeCaps caps;
        for (const Chain& c : chains_) {
            const size_t m = c.columns.size();
            for (size_t k = 0; k + (c.closed ? 0 : 1) < m; ++k) {
                const Column &a = c.columns[k], &b = c.columns[(k + 1) % m];
                if (a.base == b.base) continue;
                const Vec2 ta = level_point(a, a.n), tb = level_point(b, b.n);
                const double gap = distance(ta, tb);
                double field = 0.0;
                try {
                    field = rho_.interior(0.5 * (ta + tb));
                } catch (const GeometryError&) {
                    continue;
                }
                if (!(gap > kTopsRatio * field)) continue;
                caps.points.push_back(0.5 * (pt(a.base) + pt(b.base)));
                caps.sizes.push_back(distance(pt(a.base), pt(b.base)) * field / gap);
            }
        }
        return caps;
    }

    void grow_columns() {
        resolve_specs();
        heights();
        find_chains();
        for (Chain& c : chains_) make_columns(c);
        double points = static_cast<double>(d_.size());
        for (Chain& c : chains_)
            for (Column& col : c.columns) {
                col.n = col.want = wanted(col);
                points += col.n;
            }
        if (plan_) hold_fans_to_plan();
        if (limits_) hold_to_limits();
        if (max_points_ && points > static_cast<double>(max_points_))
            throw GeometryError(K::TooManyPoints,
                                "the boundary layers alone would make " + std::to_string(static_cast<size_t>(points)) +
                                    " points, more than the limit of " + std::to_string(max_points_),
                                {Subject::layers(0)});
        cut_by_rays();
        for (Chain& c : chains_) spread(c);
        for (int round = 0; round < kCloseTopRounds && cut_close_tops(); ++round)
            for (Chain& c : chains_) spread(c);
        while (cut_crossings())  // each round checks for cancellation first
            for (Chain& c : chains_) spread(c);
        if (final_) {
            while (cut_short_spokes())
                for (Chain& c : chains_) spread(c);
            for (Chain& c : chains_) split_wide_fans(c);
        }
    }

    // A column that slid up an embedded line (follow_embedded_lines): its top T, the line's
    // next point P and the top N of a column beside it close a triangle of fixed points alone
    // where the corner at T lies between kMinClosingDeg and kMaxClosingDeg. Where its angle at N
    // is below kClosingAngleDeg (N's column taller than T's, so the outer edge from T to N is
    // longer than the wall segment keep_free reckoned with, or the line's free part made of
    // several segments), the column loses a layer. After the cut-backs, on the final walls
    // only, as keep_free. True when any did.
    bool cut_short_spokes() {
        if (observer_ && observer_->should_stop()) throw Cancelled();
        bool any_spoke = false;
        for (const Chain& c : chains_)
            for (const Column& col : c.columns) any_spoke = any_spoke || (col.spoke && col.n > 0);
        if (!any_spoke) return false;
        const Discretisation b = make_boundary();
        const auto angle_at = [](Vec2 corner, Vec2 p, Vec2 q) { return angle_between(p - corner, q - corner); };
        bool cut = false;
        for (Chain& c : chains_) {
            const size_t m = c.columns.size();
            for (size_t k = 0; k < m; ++k) {
                Column& col = c.columns[k];
                if (!col.spoke || col.n == 0) continue;
                const auto& line = b.curve_vertices[col.slide];
                const auto at = std::find(line.begin(), line.end(), col.ids[static_cast<size_t>(col.n)]);
                if (at == line.end()) continue;
                const Vec2 T = b.point(*at), P = b.point(col.slide_at_start ? *(at + 1) : *(at - 1));
                for (const bool before : {true, false}) {
                    if (!c.closed && (before ? k == 0 : k + 1 == m)) continue;
                    const Column& nb = c.columns[before ? (k + m - 1) % m : (k + 1) % m];
                    const Vec2 N = level_point(nb, nb.n);
                    const double corner = angle_at(T, P, N);
                    if (corner < kMinClosingDeg * kDeg || corner > kMaxClosingDeg * kDeg) continue;
                    if (angle_at(N, T, P) < kClosingAngleDeg * kDeg) {
                        --col.n;
                        cut = true;
                        break;
                    }
                }
            }
        }
        return cut;
    }

    // Neighbouring columns of a fan whose tops stand more than kTopsRatio times the field
    // between them apart get columns between them, turned by equal steps, until the tops are
    // about the field apart. A fan turns by kFanStepDeg a step, so its tops stand 0.52 H
    // apart: under layers several times the field thick, the outer edge's segment across the
    // step was three times the field beside it (seed 1234 of the random domains: 28 degrees
    // between it and the interior). Each new column reaches that segment exactly (stretched
    // up to its next level), so the outer edge keeps its line and the new cells stay where the
    // fan's were: nothing else can be there. The same between a wall's end column leaning
    // along the line it slides on and the column beside it, past kLeaningTopsRatio: the new
    // columns stand on the end's base and turn from the one towards the other (seeds 1725 and
    // 1811: tops 1.9 times the field apart, 29.8 and 29.9 degrees). After the cut-backs, on the
    // final walls only: columns this close together would hold each other to the lowest in
    // spread().
    void split_wide_fans(Chain& c) {
        std::vector<Column> out;
        out.reserve(c.columns.size());
        for (size_t k = 0; k < c.columns.size(); ++k) {
            const Column& a = c.columns[k];
            out.push_back(a);
            if (k + 1 == c.columns.size()) continue;
            const Column& b = c.columns[k + 1];
            // A fan's neighbours, or a wall's end column leaning along the line it slides on
            // and the column beside it: the new columns stand on the end's base.
            const bool leans_a = !c.closed && k == 0 && a.slide != kNoCurve && !a.spoke;
            const bool leans_b = !c.closed && k + 2 == c.columns.size() && b.slide != kNoCurve && !b.spoke;
            if (b.base != a.base && !leans_a && !leans_b) continue;
            if (a.n == 0 || b.n == 0) continue;
            const Column& pivot = b.base != a.base && leans_b ? b : a;
            const Vec2 base = pt(pivot.base), ta = level_point(a, a.n), tb = level_point(b, b.n);
            double field = 0.0;
            try {
                field = rho_.interior(0.5 * (ta + tb));
            } catch (const GeometryError&) {
                continue;
            }
            const double gap = distance(ta, tb);
            if (!(gap > (b.base != a.base ? kLeaningTopsRatio : kTopsRatio) * field)) continue;
            const Vec2 da = unit(ta - base), db = unit(tb - base);
            const double turn = std::atan2(cross(da, db), dot(da, db));
            const int steps = static_cast<int>(std::min(std::ceil(gap / field), 64.0));
            for (int j = 1; j < steps; ++j) {
                Column f(pivot.base, unit(rotate(da, turn * j / steps)), 1.0, pivot.spec);
                f.key = pivot.key;
                const double across = cross(f.dir, tb - ta);
                if (across == 0.0) continue;
                const double reach = cross(ta - base, tb - ta) / across;  // to the segment ta tb
                f.n = f.want = wanted(f);
                f.n = levels_within(f, reach);
                if (f.n == 0) continue;
                f.stretch = reach / level_[static_cast<size_t>(f.spec)][static_cast<size_t>(f.n)];
                out.push_back(f);
            }
        }
        c.columns = std::move(out);
    }

    // The height of col's top above its base, along the column.
    double top(const Column& col) const {
        return col.stretch * level_[static_cast<size_t>(col.spec)][static_cast<size_t>(col.n)];
    }

    // The columns of each fan of the plan no taller than kFanCapRatio times its tallest there
    // (the fans are found by their corner points, which the discretisations share).
    void hold_fans_to_plan() {
        const auto fan_at = index_of_points(plan_->fans.points);
        for (Chain& c : chains_)
            for (size_t k = 0; k < c.columns.size(); ++k) {
                Column& col = c.columns[k];
                const bool fan = (k > 0 && c.columns[k - 1].base == col.base) ||
                                 (k + 1 < c.columns.size() && c.columns[k + 1].base == col.base);
                if (!fan) continue;
                const Vec2 p = pt(col.base);
                const auto at = fan_at.find({p.x, p.y});
                // A fan the plan lacks had no room on the walls the plan saw (every column cut
                // back): nothing spaced the walls and the field for its tops, which would
                // stand far closer together than the wall's points beside them.
                const double planned = at == fan_at.end() ? 0.0 : plan_->fan_heights[at->second];
                col.n = levels_within(col, kFanCapRatio * planned);
            }
    }

    // The columns of limits_ no taller than its levels (found by base and first direction,
    // which a growth on the same walls makes the same).
    void hold_to_limits() {
        std::map<std::tuple<VertexId, double, double>, int> most;
        for (const LayerColumn& l : *limits_) {
            const auto [at, fresh] = most.emplace(std::tuple{l.base, l.dir.x, l.dir.y}, l.levels);
            if (!fresh) at->second = std::min(at->second, l.levels);
        }
        for (Chain& c : chains_)
            for (Column& col : c.columns) {
                const auto at = most.find({col.base, col.key.x, col.key.y});
                if (at != most.end()) col.n = std::min(col.n, std::max(at->second, 0));
            }
    }

    // Which spec each curve belongs to; refuses names that are no loop curve.
    void resolve_specs() {
        spec_of_.assign(domain_.curves().size(), -1);
        std::vector<bool> in_loop(domain_.curves().size(), false);
        for (const DomainLoop& l : domain_.loops())
            for (const CurveUse& u : l.items) in_loop[u.curve] = true;
        for (size_t s = 0; s < specs_.size(); ++s) {
            for (size_t k = 0; k < specs_[s].curves.size(); ++k) {
                const std::string& key = specs_[s].curves[k];
                bool matched = false;
                for (CurveId c : domain_.curve_parts(key)) {
                    if (!in_loop[c])
                        throw GeometryError(K::BadParameter,
                                            "boundary layers grow on loop curves; \"" + key + "\" is embedded",
                                            {Subject::layers(static_cast<int>(s), {"curves", std::to_string(k)})});
                    spec_of_[c] = static_cast<int>(s);
                    matched = true;
                }
                for (CurveId c = 0; c < domain_.curves().size(); ++c) {
                    if (domain_.tags()[domain_.curves()[c].tag] != key || !in_loop[c]) continue;
                    if (spec_of_[c] < 0) spec_of_[c] = static_cast<int>(s);
                    matched = true;
                }
                if (!matched)
                    throw GeometryError(K::UnknownCurve,
                                        "boundary_layers names \"" + key + "\", which is no loop curve and no tag",
                                        {Subject::layers(static_cast<int>(s), {"curves", std::to_string(k)})});
            }
        }
    }

    // s_k per spec: the height of level k above the wall.
    void heights() {
        level_.resize(specs_.size());
        for (size_t s = 0; s < specs_.size(); ++s) {
            const BoundaryLayerSpec& sp = specs_[s];
            auto& h = level_[s];
            h.push_back(0.0);
            double cell = sp.first_height;
            for (int k = 0; k < kMaxLayers; ++k) {
                h.push_back(h.back() + cell);
                cell *= sp.growth;
            }
        }
    }

    // The segment that starts at vertex i of loop li (loops' segments come loop by loop).
    const BoundarySegment& loop_segment(size_t li, size_t i) const { return d_.segments[loop_offsets_[li] + i]; }
    int segment_spec(size_t li, size_t i) const { return spec_of_[loop_segment(li, i).curve]; }

    void find_chains() {
        loop_offsets_.assign(d_.loops.size(), 0);
        for (size_t li = 1; li < d_.loops.size(); ++li) loop_offsets_[li] = loop_offsets_[li - 1] + d_.loops[li - 1].size();
        for (size_t li = 0; li < d_.loops.size(); ++li) {
            const size_t m = d_.loops[li].size();
            const size_t off = loop_offsets_[li];
            std::vector<int> wall(m);
            for (size_t i = 0; i < m; ++i) {
                MESHD_INTERNAL_CHECK(d_.segments[off + i].a == d_.loops[li][i], "loop and segments disagree");
                wall[i] = spec_of_[d_.segments[off + i].curve];
            }
            if (std::all_of(wall.begin(), wall.end(), [](int w) { return w >= 0; })) {
                chains_.push_back({li, true, 0, m - 1, {}});
                continue;
            }
            for (size_t i = 0; i < m; ++i) {
                if (wall[i] < 0 || wall[(i + m - 1) % m] >= 0) continue;
                size_t j = i;
                while (wall[(j + 1) % m] >= 0) j = (j + 1) % m;
                // Segments i..j are walls: vertices i..j+1.
                chains_.push_back({li, false, i, (j + 1) % m, {}});
            }
        }
    }

    Vec2 pt(VertexId v) const { return d_.point(v); }

    // The wall's turn at vertex i of loop li (radians; < 0: convex, seen from the domain).
    double turn_at(size_t li, size_t i) const {
        const auto& L = d_.loops[li];
        const size_t m = L.size();
        const Vec2 t0 = unit(pt(L[i]) - pt(L[(i + m - 1) % m])), t1 = unit(pt(L[(i + 1) % m]) - pt(L[i]));
        return std::atan2(cross(t0, t1), dot(t0, t1));
    }

    void make_columns(Chain& c) {
        const auto& L = d_.loops[c.loop];
        const size_t m = L.size();
        std::vector<size_t> at;  // loop positions of the chain's vertices
        if (c.closed) {
            for (size_t i = 0; i < m; ++i) at.push_back(i);
        } else {
            for (size_t i = c.first;; i = (i + 1) % m) {
                at.push_back(i);
                if (i == c.last) break;
            }
        }
        for (size_t q = 0; q < at.size(); ++q) {
            const size_t i = at[q];
            const VertexId v = L[i];
            const bool start = !c.closed && q == 0, end = !c.closed && q + 1 == at.size();
            const Vec2 prev = pt(L[(i + m - 1) % m]), next = pt(L[(i + 1) % m]);
            const Vec2 t0 = unit(pt(v) - prev), t1 = unit(next - pt(v));
            const Vec2 n0 = perp(t0), n1 = perp(t1);
            const int spec_in = segment_spec(c.loop, (i + m - 1) % m), spec_out = segment_spec(c.loop, i);
            if (start || end) {
                // The wall's end: along the boundary line it ends on when that meets the wall
                // at a fair angle (a symmetry line), else along the wall's normal.
                const Vec2 wall_normal = start ? n1 : n0;
                const size_t other_seg = start ? (i + m - 1) % m : i;
                const CurveId line = loop_segment(c.loop, other_seg).curve;
                // Along the curve, away from v: its tangent there (a curved boundary leaves the
                // corner along it, not along the chord to its next point).
                Vec2 along = unit((start ? prev : next) - pt(v));
                if (slidable(line)) {
                    const Curve& g = *domain_.curves()[line].geometry;
                    const bool from_start = d_.curve_vertices[line].front() == v;
                    const Vec2 tangent = unit(g.derivative(from_start ? g.t_begin() : g.t_end()));
                    if (norm(tangent) > 0.0) along = from_start ? tangent : -tangent;
                }
                const Vec2 wall_dir = start ? t1 : -t0;
                double angle = std::atan2(start ? cross(wall_dir, along) : cross(along, wall_dir), dot(wall_dir, along));
                if (angle < 0) angle += 2 * std::numbers::pi;
                Column col(v, wall_normal, 1.0, start ? spec_out : spec_in);
                const bool straight = slidable(line);
                if (straight && angle >= kSlideMaxDeg * kDeg) {
                    // The line leaves the wall at a blunt angle (a trailing edge on a symmetry
                    // line goes on straight): a fan from the wall's normal round to the line,
                    // whose last column slides on it.
                    const double turn = std::atan2(cross(wall_normal, along), dot(wall_normal, along));
                    const int sectors = std::max(1, static_cast<int>(std::ceil(std::fabs(turn) / (kFanStepDeg * kDeg))));
                    std::vector<Column> fan;
                    for (int k = 0; k <= sectors; ++k) {
                        Column f = col;
                        f.dir = unit(rotate(wall_normal, turn * k / sectors));
                        fan.push_back(f);
                    }
                    fan.back().dir = along;
                    fan.back().slide = line;
                    fan.back().slide_at_start = d_.curve_vertices[line].front() == v;
                    if (start) std::reverse(fan.begin(), fan.end());
                    c.columns.insert(c.columns.end(), fan.begin(), fan.end());
                    continue;
                }
                if (straight && angle > kSlideMinDeg * kDeg) {
                    col.dir = along;
                    col.stretch = stretch_for(dot(along, wall_normal));
                    col.slide = line;
                    col.slide_at_start = d_.curve_vertices[line].front() == v;
                }
                c.columns.push_back(col);
                continue;
            }
            const int spec = specs_[static_cast<size_t>(spec_in)].first_height <= specs_[static_cast<size_t>(spec_out)].first_height
                                 ? spec_in
                                 : spec_out;
            const double turn = turn_at(c.loop, i);  // < 0: a convex corner of the wall
            const size_t first = c.columns.size();
            if (turn < -kFanTurnDeg * kDeg) {
                // Two fans in a row (a blunt trailing edge's short base between them): each
                // stops half a step short of the shared segment's normal, so that the two
                // columns on it part like the fans' own instead of standing parallel with
                // their tops only the base's length apart. Lengthened to keep their layers'
                // heights above the base.
                const double trim = 0.5 * kFanStepDeg * kDeg;
                const bool trim_in = !(q == 1 && !c.closed) && turn_at(c.loop, (i + m - 1) % m) < -kFanTurnDeg * kDeg;
                const bool trim_out = !(q + 2 == at.size() && !c.closed) && turn_at(c.loop, (i + 1) % m) < -kFanTurnDeg * kDeg;
                const double a0 = trim_in ? -trim : 0.0, a1 = trim_out ? turn + trim : turn;
                const int sectors = static_cast<int>(std::ceil((a0 - a1) / (kFanStepDeg * kDeg)));
                for (int k = 0; k <= sectors; ++k)
                    c.columns.emplace_back(v, unit(rotate(n0, a0 + (a1 - a0) * k / sectors)), 1.0, spec);
                if (trim_in) c.columns[first].stretch = stretch_for(std::cos(trim));
                if (trim_out) c.columns.back().stretch = stretch_for(std::cos(trim));
            } else {
                Vec2 dir = unit(n0 + n1);
                if (norm(dir) == 0.0) dir = n0;
                c.columns.emplace_back(v, dir, stretch_for(dot(dir, n0)), spec);
            }
            follow_embedded_lines(c, first, n0, n1, prev, next);
        }
    }

    // An embedded straight curve that leaves the wall at v (a wake line from a trailing edge):
    // the column nearest its direction (within kFanStepDeg) turns onto it and slides on it, so
    // that the layers go on along both of its sides instead of being cut back by it.
    void follow_embedded_lines(Chain& c, size_t first, Vec2 n0, Vec2 n1, Vec2 prev, Vec2 next) {
        const VertexId v = c.columns[first].base;
        for (CurveId e : domain_.embedded()) {
            const auto& vs = d_.curve_vertices[e];
            if (!slidable(e)) continue;
            if (vs.front() != v && vs.back() != v) continue;
            const Vec2 along = unit(pt(vs.front() == v ? vs[1] : vs[vs.size() - 2]) - pt(v));
            size_t best = first;
            for (size_t k = first; k < c.columns.size(); ++k)
                if (dot(c.columns[k].dir, along) > dot(c.columns[best].dir, along)) best = k;
            Column& col = c.columns[best];
            if (dot(col.dir, along) < std::cos(kFanStepDeg * kDeg) || col.slide != kNoCurve) continue;
            col.dir = along;
            col.stretch = c.columns.size() - first > 1 ? 1.0 : stretch_for(std::min(dot(along, n0), dot(along, n1)));
            col.slide = e;
            col.slide_at_start = vs.front() == v;
            col.spoke = true;
            // The line's free part and the outer edge beside the column's top (spaced like the
            // wall, or wider on a convex one) close a triangle of fixed points alone: the
            // column leaves free as much of the line as that triangle needs for
            // kClosingAngleDeg, with the wall segment on either side at its angle to the line
            // (at 90 degrees 0.6 of the segment, at 105 0.74: a fixed share of 2/3 made 29.2
            // degrees at 100, seed 1446 of the random domains). Only when the layers are grown
            // for good: on the plan's first, coarse walls a spoke is often far shorter than
            // the segments beside it, and planning without its column changed the caps and so
            // the whole mesh (seed 123 went from 34.1 to 28.4 degrees between two other holes).
            col.keep_free = 0.0;
            for (const Vec2 side : {prev, next}) {
                const Vec2 to = side - pt(v);
                const double theta = angle_between(along, to);
                if (theta >= kMinClosingDeg * kDeg && theta <= kMaxClosingDeg * kDeg)
                    col.keep_free = std::max(col.keep_free, shortest_side_for_angle(norm(to), theta, kClosingAngleDeg * kDeg));
            }
        }
    }

    Vec2 level_point(const Column& col, int k) const {
        const double reach = col.stretch * level_[static_cast<size_t>(col.spec)][static_cast<size_t>(k)];
        if (col.slide == kNoCurve) return pt(col.base) + reach * col.dir;
        return on_line(col.slide, col.slide_at_start ? reach : domain_.curves()[col.slide].length - reach);
    }

    // Curves that columns slide on, by arc length: the parameter at arc length s from the
    // curve's start, its point, and the arc length of a parameter.
    const CurveParametrisation& arc(CurveId c) const {
        if (const auto& shared = domain_.curves()[c].arc_length) return *shared;
        auto it = arcs_.find(c);
        if (it == arcs_.end()) it = arcs_.emplace(c, make_arc_length(*domain_.curves()[c].geometry)).first;
        return *it->second;
    }
    double line_param(CurveId c, double s) const {
        const CurveParametrisation& a = arc(c);
        return a.param_at(std::clamp(s * a.length() / domain_.curves()[c].length, 0.0, a.length()));
    }
    Vec2 on_line(CurveId c, double s) const { return domain_.curves()[c].geometry->point(line_param(c, s)); }
    double along_line(CurveId c, double t) const {
        const CurveParametrisation& a = arc(c);
        return a.spacing_at(t) * domain_.curves()[c].length / a.length();
    }
    // A curve a column may slide on: open (its ends are two points), not a wall.
    bool slidable(CurveId c) const {
        const auto& vs = d_.curve_vertices[c];
        return vs.size() >= 2 && vs.front() != vs.back() && spec_of_[c] < 0;
    }

    // Layers the spec asks for at this column, stopping before a cell taller than rho.
    int wanted(const Column& col) const {
        const BoundaryLayerSpec& sp = specs_[static_cast<size_t>(col.spec)];
        const auto& h = level_[static_cast<size_t>(col.spec)];
        const int most = sp.layers > 0 ? std::min(sp.layers, kMaxLayers) : kMaxLayers;
        int n = 0;
        while (n < most) {
            if (sp.thickness > 0.0 && h[static_cast<size_t>(n) + 1] > sp.thickness * (1.0 + 1e-12)) break;
            if (col.slide != kNoCurve) {
                const double len = domain_.curves()[col.slide].length, reach = col.stretch * h[static_cast<size_t>(n) + 1];
                if (reach > kSlideShare * len || (final_ && reach > len - col.keep_free)) break;
            }
            const double cell = col.stretch * (h[static_cast<size_t>(n) + 1] - h[static_cast<size_t>(n)]);
            // rho where the column stands; a density that fails there (a column that, before
            // its cut-back, leaves the domain where the expression is not defined) stops it.
            double size = 0.0;
            try {
                size = rho_.interior(level_point(col, n));
            } catch (const GeometryError&) {
                break;
            }
            if (cell > size) break;
            ++n;
        }
        return n;
    }

    int levels_within(const Column& col, double length) const {
        const auto& h = level_[static_cast<size_t>(col.spec)];
        int n = col.n;
        while (n > 0 && col.stretch * h[static_cast<size_t>(n)] > length) --n;
        return n;
    }

    // 1. Each column's ray (twice its length and more) against the boundary and the other rays.
    void cut_by_rays() {
        detail::SegmentSoup soup;
        soup.points.assign(d_.x.size(), {});
        for (VertexId v = 0; v < d_.size(); ++v) soup.points[v] = pt(v);
        for (const BoundarySegment& s : d_.segments) soup.segments.push_back({s.a, s.b});
        // The free ends of an embedded curve (on no loop) stand for crosses of the local size,
        // so that a column passing beside one also leaves room for isotropic triangles there
        // (a crossing counts only within the local size where it is, so a coarse end's long
        // arms do not reach into a fine region). Not the end of a curve shorter than that
        // cross which leaves a loop: it lies among the loop's own columns, which stop at the
        // curve or turn onto it.
        const size_t curves_end = soup.segments.size();
        std::vector<Vec2> cross_centre;  // per cross segment
        std::vector<char> on_loop(d_.size(), 0);
        for (size_t i = 0; i < d_.loop_segment_count; ++i) on_loop[d_.segments[i].a] = on_loop[d_.segments[i].b] = 1;
        for (const CurveId e : domain_.embedded()) {
            const auto& vs = d_.curve_vertices[e];
            if (vs.size() < 2) continue;
            for (const VertexId v : {vs.front(), vs.back()}) {
                if (on_loop[v]) continue;
                const VertexId other = v == vs.front() ? vs.back() : vs.front();
                const Vec2 p = pt(v), along = unit(p - pt(v == vs.front() ? vs[1] : vs[vs.size() - 2]));
                const double r = rho_.interior(p);
                if (on_loop[other] && distance(p, pt(other)) < 2.0 * r) continue;
                for (const Vec2 arm : {along, Vec2{-along.y, along.x}}) {
                    soup.points.push_back(p - r * arm);
                    soup.points.push_back(p + r * arm);
                    soup.segments.push_back({static_cast<std::uint32_t>(soup.points.size() - 2),
                                             static_cast<std::uint32_t>(soup.points.size() - 1)});
                    cross_centre.push_back(p);
                }
            }
        }
        const size_t boundary = soup.segments.size();
        std::vector<Column*> ray_of;
        std::vector<char> in_fan;  // per ray: its column shares its base with a neighbour
        for (Chain& c : chains_) {
            const size_t m = c.columns.size();
            for (size_t k = 0; k < m; ++k) {
                Column& col = c.columns[k];
                if (col.n == 0 || col.slide != kNoCurve) continue;
                const double reach = 2.5 * top(col);
                soup.points.push_back(pt(col.base) + reach * col.dir);
                soup.segments.push_back({col.base, static_cast<std::uint32_t>(soup.points.size() - 1)});
                ray_of.push_back(&col);
                const bool before = (c.closed || k > 0) && c.columns[(k + m - 1) % m].base == col.base;
                const bool after = (c.closed || k + 1 < m) && c.columns[(k + 1) % m].base == col.base;
                in_fan.push_back(static_cast<char>(before || after));
            }
        }
        std::vector<double> cap(ray_of.size(), HUGE_VAL);
        auto along = [&](size_t r, Vec2 p) { return dot(p - pt(ray_of[r]->base), ray_of[r]->dir); };
        // Ray r meets something at x, t along it, that stands there as a boundary does: less
        // than half the gap, and room left beside it for a row of isotropic triangles.
        // (`strip`: kStripShare of rho at x.)
        auto as_boundary = [&](size_t r, double t, double strip) {
            cap[r] = std::min(cap[r], std::min(kGapShare * t, 0.5 * (t - strip)));
        };
        detail::for_each_crossing(soup, [&](std::uint32_t i, std::uint32_t j) {
            if (j < boundary) return;
            const size_t rj = j - boundary;
            const auto& sj = soup.segments[j];
            const Vec2 a = soup.points[sj[0]], b = soup.points[sj[1]];
            const auto& si = soup.segments[i];
            const Vec2 c = soup.points[si[0]], e = soup.points[si[1]];
            // Where the two lines meet (parallel overlaps: the nearer end of the other).
            const double den = cross(b - a, e - c);
            Vec2 x;
            if (den != 0.0) x = a + (cross(c - a, e - c) / den) * (b - a);
            else x = dot(c - a, b - a) < dot(e - a, b - a) ? c : e;
            if (i < boundary) {
                if (i >= curves_end && distance(x, cross_centre[i - curves_end]) > rho_.interior(x)) return;
                // Less than half the gap, and room left between the layers of both sides for
                // a row of isotropic triangles of the local size.
                as_boundary(rj, along(rj, x), kStripShare * rho_.interior(x));
            } else {
                // Two rays that cross about as far from both bases: both columns stop short
                // of the crossing. One that passes over the foot of the other column (less
                // than kGapShare of its own way from it) meets that column as a boundary,
                // and only it is cut: cutting the other to 0.9 of its few steps to the
                // crossing would flatten it (seed 2311 of the random domains: a spline's tip
                // under a fan of columns 0.9 tall, cut to 0.03 by a ray grazing the tip from
                // a column 2.8 away, left that column's outer edge sloping over one wall
                // segment to the tip beside triangles of the fan's size, at 18 degrees).
                const size_t ri = i - boundary;
                const double ti = along(ri, x), tj = along(rj, x);
                // Whether column r, whole, stays clear of x by a strip more than the other
                // column cut as by a boundary at x (its ray passes over r's foot).
                double strip = -1.0;  // rho at x is read only where a foot is passed over
                auto spared = [&](size_t r, double ta, double tb) {
                    if (!(ta < kGapShare * tb)) return false;
                    if (strip < 0.0) strip = kStripShare * rho_.interior(x);
                    return top(*ray_of[r]) + strip < (1.0 - kGapShare) * tb;
                };
                // Whether fan column r's foot, ta along its ray, is passed over by a ray that
                // leaves it room for more than those few steps (only asked after spared(r),
                // which reads `strip` when the foot is passed over).
                auto fan_room = [&](size_t r, double ta, double tb) {
                    return in_fan[r] && ta < kGapShare * tb && (1.0 - kGapShare) * tb - strip > 0.9 * ta;
                };
                if (spared(ri, ti, tj)) {
                    as_boundary(rj, tj, strip);
                } else if (spared(rj, tj, ti)) {
                    as_boundary(ri, ti, strip);
                } else if (fan_room(ri, ti, tj) || fan_room(rj, tj, ti)) {
                    // A ray over the corner of a fan whose column is too tall, whole, to stay
                    // clear of it, but with room along that ray for more than the few steps to
                    // the crossing: the passing column is still cut as by a boundary there, and
                    // the fan's column keeps what stays a strip below the room that leaves.
                    // Cutting it to those few steps flattened the fan (every column of it
                    // meets the ray there): seed 48759 of the random domains, a hole's
                    // 60-degree corner 0.08 from the ray of another hole's column 2.7 away, kept
                    // 5 of its 25 layers, and the outer edge fell from the wall's columns beside
                    // it in one segment, at 27 degrees to the interior's triangle on it. (Where
                    // the room is less, and on a wall's own columns, both are cut as below:
                    // a circle's columns beside a narrow gap, seed 2730, need that.)
                    const bool i_foot = fan_room(ri, ti, tj);
                    const size_t foot = i_foot ? ri : rj, pass = i_foot ? rj : ri;
                    const double t_pass = i_foot ? tj : ti;
                    as_boundary(pass, t_pass, strip);
                    cap[foot] = std::min(cap[foot], (1.0 - kGapShare) * t_pass - strip);
                } else {
                    cap[rj] = std::min(cap[rj], 0.9 * tj);
                    cap[ri] = std::min(cap[ri], 0.9 * ti);
                }
            }
        });
        for (size_t r = 0; r < ray_of.size(); ++r)
            if (cap[r] < HUGE_VAL) ray_of[r]->n = levels_within(*ray_of[r], std::max(cap[r], 0.0));
    }

    // 1b. Two tops closer than a strip of the local size (kStripShare of rho at each, half
    // from either side), unless they stand on one base or on bases at most kCloseTopBases apart
    // along one chain: the taller of the two loses a layer. The rays of step 1 keep a strip
    // only along each column; columns of two walls that pass beside each other at a slant
    // (two holes close together, their columns radial) left tops 0.6 rho apart, with a row
    // of triangles of layer tops alone between them (18.6 degrees). True when any was cut.
    bool cut_close_tops() {
        if (observer_ && observer_->should_stop()) throw Cancelled();
        detail::SegmentSoup soup;
        struct Top {
            Column* col;
            size_t chain, rank;
            Vec2 p;
            double r;
        };
        std::vector<Top> tops;
        std::vector<size_t> bases(chains_.size(), 0);
        for (size_t ci = 0; ci < chains_.size(); ++ci) {
            Chain& c = chains_[ci];
            size_t rank = 0;
            for (size_t k = 0; k < c.columns.size(); ++k) {
                Column& col = c.columns[k];
                if (k > 0 && col.base != c.columns[k - 1].base) ++rank;
                if (col.n == 0 || col.slide != kNoCurve) continue;
                const Vec2 p = level_point(col, col.n);
                double r = 0.0;
                try {
                    r = 0.5 * kStripShare * rho_.interior(p);
                } catch (const GeometryError&) {
                    continue;
                }
                tops.push_back({&col, ci, rank, p, r});
                soup.points.push_back(p - Vec2{r, r});
                soup.points.push_back(p + Vec2{r, r});
                soup.segments.push_back({static_cast<std::uint32_t>(soup.points.size() - 2),
                                         static_cast<std::uint32_t>(soup.points.size() - 1)});
            }
            bases[ci] = rank + 1;
        }
        std::vector<char> cut(tops.size(), 0);
        detail::for_each_box_overlap(soup, [&](std::uint32_t i, std::uint32_t j) {
            const Top &a = tops[i], &b = tops[j];
            if (a.col->base == b.col->base) return;
            if (a.chain == b.chain) {
                const size_t d = a.rank > b.rank ? a.rank - b.rank : b.rank - a.rank;
                if (d <= kCloseTopBases || (chains_[a.chain].closed && bases[a.chain] - d <= kCloseTopBases)) return;
            }
            if (!(distance(a.p, b.p) < a.r + b.r)) return;
            cut[top(*a.col) >= top(*b.col) ? i : j] = 1;
        });
        bool any = false;
        for (size_t t = 0; t < tops.size(); ++t)
            if (cut[t]) {
                --tops[t].col->n;
                any = true;
            }
        return any;
    }

    // 2. The layers' outer edge rises from one column's top to the next by at most kTopSlope
    // of the way across: fewer layers spread smoothly from a cut-back column, over a distance
    // that does not depend on how finely the wall is spaced.
    void spread(Chain& c) const {
        auto& cols = c.columns;
        const size_t n = cols.size();
        if (n < 2) return;
        const int rounds = c.closed ? 2 : 1;
        auto limit = [&](Column& to, const Column& from) {
            const double from_top = top(from);
            const double across = distance(level_point(to, std::min(to.n, from.n)), level_point(from, from.n));
            to.n = std::max(std::min(to.n, from.n), levels_within(to, from_top + kTopSlope * across));
        };
        for (int r = 0; r < rounds; ++r) {
            for (size_t i = 1; i < n + (c.closed ? 1 : 0); ++i) limit(cols[i % n], cols[i - 1]);
            for (size_t i = n - 1; i-- > 0;) limit(cols[i], cols[i + 1]);
            if (c.closed) limit(cols[n - 1], cols[0]);
        }
    }

    // The boundary as the layers leave it: each line that columns slide on holds their points
    // next to its ends (curve points, appended after the discretisation's), its own inner
    // points spread over what remains of it in proportion (no point is lost), and the loops
    // are linked again. Sets the ids of the sliding columns' points.
    Discretisation make_boundary() {
        Discretisation b = d_;
        std::map<CurveId, std::array<Column*, 2>> slides;  // line -> columns at its start, end
        for (Chain& c : chains_)
            for (Column& col : c.columns) {
                col.ids.assign(1, col.base);
                if (col.slide != kNoCurve) slides[col.slide][col.slide_at_start ? 0 : 1] = &col;
            }
        for (auto& [line, ends] : slides) {
            const double len = domain_.curves()[line].length;
            auto reach = [&](const Column* col) {
                return col ? col->stretch * level_[static_cast<size_t>(col->spec)][static_cast<size_t>(col->n)] : 0.0;
            };
            const double from = reach(ends[0]), to = reach(ends[1]);
            auto add = [&](double at) {
                const Vec2 p = on_line(line, at);
                b.x.push_back(p.x);
                b.y.push_back(p.y);
                b.curve.push_back(line);
                b.param.push_back(line_param(line, at));
                b.rho.push_back(0.0);  // set with the front's below
                return static_cast<std::uint32_t>(b.x.size() - 1);
            };
            const auto& old = d_.curve_vertices[line];
            std::vector<VertexId> chain{old.front()};
            if (Column* col = ends[0])
                for (int l = 1; l <= col->n; ++l) chain.push_back(col->ids.emplace_back(add(col->stretch * level_[static_cast<size_t>(col->spec)][static_cast<size_t>(l)])));
            for (size_t i = 1; i + 1 < old.size(); ++i) {
                const double at = from + along_line(line, d_.param[old[i]]) * (len - from - to) / len;
                const Vec2 p = on_line(line, at);
                b.x[old[i]] = p.x;
                b.y[old[i]] = p.y;
                b.param[old[i]] = line_param(line, at);
                chain.push_back(old[i]);
            }
            if (Column* col = ends[1]) {
                std::vector<VertexId> up;
                for (int l = 1; l <= col->n; ++l)
                    up.push_back(col->ids.emplace_back(add(len - col->stretch * level_[static_cast<size_t>(col->spec)][static_cast<size_t>(l)])));
                chain.insert(chain.end(), up.rbegin(), up.rend());
            }
            chain.push_back(old.back());
            b.curve_vertices[line] = std::move(chain);
        }
        link_loops(domain_, b);
        return b;
    }

    // The edges and cells of the layers as they stand. A point is (chain, column, level).
    struct LayerPoint {
        std::uint32_t chain, column;
        int level;
    };
    static int level_of(const std::vector<LayerPoint>& owner, std::uint32_t p) {
        return p < owner.size() && owner[p].chain != UINT32_MAX ? owner[p].level : 0;
    }

    // 3. One round: cells that are not strictly convex, or edges that cross, lose the layers
    // from there up. True when anything was cut.
    //
    // The cells between two neighbouring columns form a strip. Where every cell is strictly
    // convex and counter-clockwise, a strip lies on one side of each of its two columns (a
    // column is straight, and a convex cell lies on one side of the line of any of its
    // edges), so a strip crosses neither itself nor the strips beside it. Only strips whose
    // box meets the box of another strip or of a boundary segment not their own (or that hold
    // a bad cell) have their edges tested against the boundary and each other: the walls'
    // thin first layers, dozens of edges to a column's width, are then tested only where
    // something else comes near.
    bool cut_crossings() {
        if (observer_ && observer_->should_stop()) throw Cancelled();
        const Discretisation b = make_boundary();
        detail::SegmentSoup soup;
        soup.points.reserve(b.size());
        for (VertexId v = 0; v < b.size(); ++v) soup.points.push_back(b.point(v));
        std::vector<LayerPoint> owner(b.size(), LayerPoint{UINT32_MAX, 0, 0});
        for (const BoundarySegment& s : b.segments) soup.segments.push_back({s.a, s.b});
        const size_t boundary = soup.segments.size();
        for (std::uint32_t ci = 0; ci < chains_.size(); ++ci) {
            for (std::uint32_t k = 0; k < chains_[ci].columns.size(); ++k) {
                Column& col = chains_[ci].columns[k];
                for (int l = 1; l <= col.n; ++l) {
                    if (col.slide == kNoCurve) {
                        col.ids.push_back(static_cast<std::uint32_t>(soup.points.size()));
                        soup.points.push_back(level_point(col, l));
                        owner.push_back({ci, k, l});
                    } else {
                        owner[col.ids[static_cast<size_t>(l)]] = {ci, k, l};
                    }
                }
            }
        }
        // The strips, chain by chain: strip k between columns k and k + 1 (cyclic on closed
        // chains).
        std::vector<std::uint32_t> first_strip(chains_.size() + 1, 0);
        for (std::uint32_t ci = 0; ci < chains_.size(); ++ci) {
            const size_t nc = chains_[ci].columns.size();
            first_strip[ci + 1] = first_strip[ci] + static_cast<std::uint32_t>(chains_[ci].closed ? nc : (nc > 0 ? nc - 1 : 0));
        }
        const std::uint32_t strips = first_strip.back();
        auto strip_count = [&](std::uint32_t ci) { return first_strip[ci + 1] - first_strip[ci]; };
        auto chain_of = [&](std::uint32_t s) {
            return static_cast<std::uint32_t>(std::upper_bound(first_strip.begin(), first_strip.end(), s) - first_strip.begin() - 1);
        };
        auto adjacent = [&](std::uint32_t s, std::uint32_t t) {
            const std::uint32_t ci = chain_of(s);
            if (chain_of(t) != ci) return false;
            const std::uint32_t d = s > t ? s - t : t - s;
            return d <= 1 || (chains_[ci].closed && d + 1 == strip_count(ci));
        };
        // The strip of each soup segment past the boundary's (a column's side goes with the
        // strip after it, the last column of an open chain with the one before); kAny for a
        // lone column's side, which is always tested.
        constexpr std::uint32_t kAny = UINT32_MAX;
        std::vector<std::uint32_t> strip_of;
        std::vector<char> suspect(strips, 0);
        std::vector<char> bad(strips, 0);  // a cell not strictly convex and counter-clockwise
        bool cut = false;
        auto drop = [&](std::uint32_t p) {
            if (p >= owner.size() || owner[p].chain == UINT32_MAX) return;
            Column& col = chains_[owner[p].chain].columns[owner[p].column];
            if (col.n >= owner[p].level) {
                col.n = owner[p].level - 1;
                cut = true;
            }
        };
        auto edge = [&](std::uint32_t a, std::uint32_t e, std::uint32_t strip) {
            if (a == e) return;
            soup.segments.push_back({a, e});
            strip_of.push_back(strip);
        };
        auto cell = [&](const Cell& c, std::uint32_t strip) {
            const int n = c.corners;
            for (int i = 0; i < n; ++i) {
                if (orient2d(soup.points[c.v[static_cast<size_t>(i)]], soup.points[c.v[static_cast<size_t>((i + 1) % n)]],
                             soup.points[c.v[static_cast<size_t>((i + 2) % n)]]) != Orientation::Left) {
                    for (int k = 0; k < n; ++k) drop(c.v[static_cast<size_t>(k)]);  // the cell's points above the wall go
                    suspect[strip] = bad[strip] = 1;
                    return;
                }
            }
        };
        for (std::uint32_t ci = 0; ci < chains_.size(); ++ci) {
            const Chain& ch = chains_[ci];
            const std::uint32_t ns = strip_count(ci);
            for (std::uint32_t k = 0; k < ch.columns.size(); ++k) {
                const Column& col = ch.columns[k];
                if (col.slide != kNoCurve) continue;  // a sliding column's sides are the boundary's
                const std::uint32_t strip = ns == 0 ? kAny : first_strip[ci] + std::min(k, ns - 1);
                for (size_t l = 0; l + 1 < col.ids.size(); ++l) edge(col.ids[l], col.ids[l + 1], strip);
            }
            walk_cells(ch, [&](const Cell& c) {
                const std::uint32_t strip = first_strip[ci] + c.strip;
                edge(c.across[0], c.across[1], strip);
                cell(c, strip);
            });
        }
        // Each strip's box (its two columns' points) and each boundary segment, as diagonals;
        // the strips that meet another strip not beside them, or a boundary segment that is
        // not their own or their neighbours', are suspects. Where the boxes meet, a strip
        // between two straight columns (neither slides on a curve) is first looked at as the
        // hull of its columns' ends, which holds every point of its columns and so every edge
        // between them: thin strips leaning across the walls' normals have boxes far larger
        // than themselves (200 layers of growth 1 on a slanted wall made every strip a
        // suspect, and the crossing test of their edges took 75% of the mesh), and the hulls
        // of two that do not meet are apart by a margin far above the rounding of the
        // columns' points off their lines.
        detail::SegmentSoup boxes;
        std::vector<std::array<Vec2, 4>> hull(strips);
        std::vector<char> straight(strips, 0);
        double scale = 0.0;
        for (const Vec2& p : soup.points) scale = std::max({scale, std::fabs(p.x), std::fabs(p.y)});
        const double margin = 1e-9 * scale;
        for (std::uint32_t ci = 0; ci < chains_.size(); ++ci) {
            const size_t nc = chains_[ci].columns.size();
            for (std::uint32_t k = 0; k < strip_count(ci); ++k) {
                const auto next = static_cast<std::uint32_t>((k + 1) % nc);
                const std::uint32_t strip = first_strip[ci] + k;
                Box box;
                for (const std::uint32_t c : {k, next})
                    for (const std::uint32_t id : chains_[ci].columns[c].ids) box.add(soup.points[id]);
                boxes.points.push_back(box.lo);
                boxes.points.push_back(box.hi);
                boxes.segments.push_back({2 * strip, 2 * strip + 1});
                const Column& P = chains_[ci].columns[k];
                const Column& Q = chains_[ci].columns[next];
                straight[strip] = P.slide == kNoCurve && Q.slide == kNoCurve;
                hull[strip] = {soup.points[P.ids.front()], soup.points[P.ids.back()], soup.points[Q.ids.front()],
                               soup.points[Q.ids.back()]};
            }
        }
        auto apart = [&](std::uint32_t strip, std::span<const Vec2> other) {
            return straight[strip] && detail::hulls_apart(hull[strip], other, margin);
        };
        for (size_t i = 0; i < boundary; ++i) {
            boxes.segments.push_back({static_cast<std::uint32_t>(boxes.points.size()), static_cast<std::uint32_t>(boxes.points.size() + 1)});
            boxes.points.push_back(soup.points[soup.segments[i][0]]);
            boxes.points.push_back(soup.points[soup.segments[i][1]]);
        }
        // The boundary segments that are a strip's own: its wall segment, and the segments of
        // a column sliding on a curve (with the strip after it, as a column's side).
        std::unordered_map<std::uint64_t, std::uint32_t> own;
        std::unordered_map<std::uint64_t, std::uint32_t> sliding;  // a sliding column's segments: a side of that strip
        auto key = [](std::uint32_t a, std::uint32_t e) {
            return static_cast<std::uint64_t>(std::min(a, e)) << 32 | std::max(a, e);
        };
        for (std::uint32_t ci = 0; ci < chains_.size(); ++ci) {
            const Chain& ch = chains_[ci];
            const std::uint32_t ns = strip_count(ci);
            if (ns == 0) continue;
            for (std::uint32_t k = 0; k < ch.columns.size(); ++k) {
                const Column& col = ch.columns[k];
                const std::uint32_t strip = first_strip[ci] + std::min(k, ns - 1);
                if (k < ns) {
                    const VertexId next = ch.columns[(k + 1) % ch.columns.size()].base;
                    if (next != col.base) own[key(col.base, next)] = first_strip[ci] + k;
                }
                if (col.slide != kNoCurve)
                    for (size_t l = 0; l + 1 < col.ids.size(); ++l) {
                        own[key(col.ids[l], col.ids[l + 1])] = strip;
                        sliding[key(col.ids[l], col.ids[l + 1])] = strip;
                    }
            }
        }
        std::vector<std::pair<std::uint32_t, std::uint32_t>> near;  // (strip, boundary segment)
        std::vector<std::pair<std::uint32_t, std::uint32_t>> facing;  // two strips that may cross
        detail::for_each_box_overlap(boxes, [&](std::uint32_t i, std::uint32_t j) {
            if (j < strips) {  // two strips
                if (!adjacent(i, j) && !(straight[j] && apart(i, hull[j]))) {
                    suspect[i] = suspect[j] = 1;
                    facing.emplace_back(i, j);
                }
            } else if (i < strips) {  // a strip and a boundary segment
                const auto& e = soup.segments[j - strips];
                const std::array<Vec2, 2> ends{soup.points[e[0]], soup.points[e[1]]};
                const auto it = own.find(key(e[0], e[1]));
                if ((it == own.end() || !(it->second == i || adjacent(i, it->second))) && !apart(i, ends)) {
                    suspect[i] = 1;
                    near.push_back({i, j - strips});
                }
            }
        });
        // The boundary and the suspects' edges, tested for crossings. A strip whose cells are
        // all strictly convex crosses neither itself nor the strips beside it whose cells are
        // too (above), so those pairs are not looked at: the boundary, the lone columns' sides
        // and the edges of strips with a bad cell come first, tested among themselves and
        // against every other suspect's edges; then each other suspect's edges in a run of
        // their own, tested against the runs of the strips it faces. Its thin layers' rungs,
        // dozens over each of its columns' edges in a cell of the grid, are then met only by
        // what comes near from elsewhere. A sliding column's segments go with the strip after
        // it, as a straight column's edges do. (Hundreds of layers of growth 1 beside an
        // embedded line: this function 1.76 G -> 0.15 G instructions; the high-lift example's
        // 109 M -> 71 M; a slat's layers overlapping across it, 1.11 G -> 0.25 G.)
        detail::SegmentSoup tested;
        tested.points = std::move(soup.points);
        auto proven = [&](std::uint32_t strip) { return strip != kAny && suspect[strip] && !bad[strip]; };
        // The strip each segment goes with: a boundary segment with none unless it is a side
        // of a sliding column (its strip's, like a straight column's edges).
        std::vector<std::uint32_t> strip_at(soup.segments.size(), kAny);
        for (size_t i = 0; i < soup.segments.size(); ++i) {
            if (i >= boundary) {
                strip_at[i] = strip_of[i - boundary];
            } else if (const auto it = sliding.find(key(soup.segments[i][0], soup.segments[i][1])); it != sliding.end()) {
                strip_at[i] = it->second;
            }
        }
        std::vector<std::uint32_t> start(strips + 1, 0);
        for (size_t i = 0; i < soup.segments.size(); ++i) {
            const std::uint32_t strip = strip_at[i];
            if (proven(strip)) ++start[strip + 1];
            else if (i < boundary || strip == kAny || suspect[strip]) tested.segments.push_back(soup.segments[i]);
        }
        const auto others = static_cast<std::uint32_t>(tested.segments.size());
        for (std::uint32_t k = 0; k < strips; ++k) start[k + 1] += start[k];
        for (auto& x : start) x += others;
        tested.segments.resize(start.back());
        {
            std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
            for (size_t i = 0; i < soup.segments.size(); ++i)
                if (proven(strip_at[i])) tested.segments[fill[strip_at[i]]++] = soup.segments[i];
        }
        const std::function<void(std::uint32_t, std::uint32_t)> cut_both = [&](std::uint32_t i, std::uint32_t j) {
            for (std::uint32_t s : {i, j}) {
                const auto& e = tested.segments[s];
                const int la = level_of(owner, e[0]), lb = level_of(owner, e[1]);
                if (la == 0 && lb == 0) continue;  // the boundary's own
                if (la >= lb) drop(e[0]);
                if (lb >= la) drop(e[1]);
            }
        };
        detail::for_each_crossing(tested, {0, others}, cut_both);
        detail::for_each_crossing_between(tested, {others, start.back()}, {0, others}, cut_both);
        std::vector<detail::SegmentRange> runs(strips);
        for (std::uint32_t k = 0; k < strips; ++k) runs[k] = {start[k], start[k + 1]};
        detail::RunCrossings facing_runs(tested, std::move(runs));
        for (const auto& [s, t] : facing)
            if (proven(s) && proven(t)) facing_runs.between(s, t, cut_both);
        // A boundary point strictly inside a cell crosses none of its edges: an embedded
        // line that leaves a wall's corner at a shallow angle and ends within the first layer,
        // or a small hole inside a thick one. The cell's top corners go (the cell with them).
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        for (const auto& [strip, seg] : near) {
            const std::uint32_t ci = chain_of(strip);
            walk_strip(chains_[ci], strip - first_strip[ci], [&](const Cell& c) {
                for (const std::uint32_t p : soup.segments[seg]) {
                    bool inside = true;
                    for (int i = 0; i < c.corners && inside; ++i)
                        inside = orient2d(tested.points[c.v[static_cast<size_t>(i)]],
                                          tested.points[c.v[static_cast<size_t>((i + 1) % c.corners)]],
                                          tested.points[p]) == Orientation::Left;
                    if (!inside) continue;
                    int top = 0;
                    for (int i = 0; i < c.corners; ++i) top = std::max(top, level_of(owner, c.v[static_cast<size_t>(i)]));
                    for (int i = 0; i < c.corners; ++i)
                        if (level_of(owner, c.v[static_cast<size_t>(i)]) == top) drop(c.v[static_cast<size_t>(i)]);
                }
            });
        }
        return cut;
    }

    GrownLayers build() {
        GrownLayers g;
        g.boundary = make_boundary();
        Discretisation& f = g.front;
        f = g.boundary;
        f.loops.clear();
        f.segments.clear();
        auto add_front = [&](Vec2 p) {
            f.x.push_back(p.x);
            f.y.push_back(p.y);
            f.curve.push_back(kNoCurve);
            f.param.push_back(0.0);
            f.rho.push_back(0.0);  // set from the front's segments below
            return static_cast<std::uint32_t>(f.x.size() - 1);
        };
        auto add_hidden = [&](Vec2 p) {
            g.hidden.push_back(p);
            return GrownLayers::kHidden | static_cast<std::uint32_t>(g.hidden.size() - 1);
        };
        for (Chain& c : chains_) {
            const size_t nc = c.columns.size();
            for (size_t k = 0; k < nc; ++k) {
                Column& col = c.columns[k];
                if (col.slide != kNoCurve) continue;  // its points are the boundary's
                const bool side = !c.closed && (k == 0 || k + 1 == nc);
                for (int l = 1; l <= col.n; ++l) {
                    const Vec2 p = level_point(col, l);
                    col.ids.push_back(side || l == col.n ? add_front(p) : add_hidden(p));
                }
            }
        }
        g.column_of.assign(f.size(), -1);
        for (const Chain& c : chains_)
            for (const Column& col : c.columns)
                for (int l = 1; l < static_cast<int>(col.ids.size()); ++l) {
                    const std::uint32_t id = col.ids[static_cast<size_t>(l)];
                    if (id & GrownLayers::kHidden) continue;
                    g.column_of[id] = static_cast<std::int32_t>(g.columns.size());
                    g.columns.push_back({col.base, col.key, l});
                }
        // Each chain's part of the front: its columns' tops, and the whole of an end column
        // that stands free (its side borders the interior).
        std::vector<std::vector<VertexId>> fronts(chains_.size());
        for (size_t ci = 0; ci < chains_.size(); ++ci) {
            const Chain& c = chains_[ci];
            auto& out = fronts[ci];
            auto push = [&](std::uint32_t v) {
                if (out.empty() || out.back() != v) out.push_back(v);
            };
            const size_t nc = c.columns.size();
            for (size_t k = 0; k < nc; ++k) {
                const Column& col = c.columns[k];
                const bool free_side = !c.closed && col.slide == kNoCurve && (k == 0 || k + 1 == nc);
                if (free_side && k == 0) {
                    for (std::uint32_t v : col.ids) push(v);
                } else if (free_side) {
                    for (size_t l = col.ids.size(); l-- > 0;) push(col.ids[l]);
                } else {
                    push(col.ids.back());
                }
            }
            if (c.closed && out.size() > 1 && out.front() == out.back()) out.pop_back();
        }
        // The loops: each chain's stretch of its loop (from its first front point to its
        // last, which lie on the loop) replaced by its front.
        const Discretisation& b = g.boundary;
        for (size_t li = 0; li < b.loops.size(); ++li) {
            const auto& L = b.loops[li];
            const size_t m = L.size();
            std::vector<VertexId> cycle;
            std::vector<int> opens(b.size() + 1, -1);
            bool closed = false;
            for (size_t ci = 0; ci < chains_.size(); ++ci) {
                if (chains_[ci].loop != li) continue;
                if (chains_[ci].closed) {
                    cycle = fronts[ci];
                    closed = true;
                } else {
                    opens[fronts[ci].front()] = static_cast<int>(ci);
                }
            }
            if (!closed) {
                size_t start = 0;
                for (size_t i = 0; i < m; ++i)
                    for (size_t ci = 0; ci < chains_.size(); ++ci)
                        if (chains_[ci].loop == li && !chains_[ci].closed && fronts[ci].back() == L[i]) start = i;
                size_t i = start, walked = 0;
                while (walked < m) {
                    const int ci = opens[L[i]];
                    if (ci >= 0 && walked > 0) {
                        for (VertexId v : fronts[static_cast<size_t>(ci)])
                            if (cycle.empty() || cycle.back() != v) cycle.push_back(v);
                        while (L[i] != fronts[static_cast<size_t>(ci)].back() && walked < m) {
                            i = (i + 1) % m;
                            ++walked;
                        }
                        continue;
                    }
                    if (cycle.empty() || cycle.back() != L[i]) cycle.push_back(L[i]);
                    i = (i + 1) % m;
                    ++walked;
                }
                if (cycle.size() > 1 && cycle.front() == cycle.back()) cycle.pop_back();
            }
            f.loops.push_back(std::move(cycle));
        }
        // Segments: the boundary's where both ends follow each other there, else the front's.
        std::vector<std::pair<std::uint64_t, CurveId>> original;
        for (size_t i = 0; i < b.loop_segment_count; ++i)
            original.push_back({(static_cast<std::uint64_t>(b.segments[i].a) << 32) | b.segments[i].b, b.segments[i].curve});
        std::sort(original.begin(), original.end());
        for (const auto& cycle : f.loops) {
            for (size_t i = 0; i < cycle.size(); ++i) {
                const VertexId a = cycle[i], e = cycle[(i + 1) % cycle.size()];
                const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | e;
                auto it = std::lower_bound(original.begin(), original.end(), std::pair{key, CurveId{0}});
                f.segments.push_back({a, e, it != original.end() && it->first == key ? it->second : kNoCurve});
            }
        }
        f.loop_segment_count = f.segments.size();
        // Embedded lines: not their stretch inside the layers (a column slides on it there).
        std::vector<std::pair<VertexId, VertexId>> inside;
        for (const Chain& c : chains_)
            for (const Column& col : c.columns)
                if (col.slide != kNoCurve)
                    for (size_t l = 0; l + 1 < col.ids.size(); ++l)
                        inside.emplace_back(std::min(col.ids[l], col.ids[l + 1]), std::max(col.ids[l], col.ids[l + 1]));
        std::sort(inside.begin(), inside.end());
        for (size_t i = b.loop_segment_count; i < b.segments.size(); ++i)
            if (!std::binary_search(inside.begin(), inside.end(),
                                    std::pair{std::min(b.segments[i].a, b.segments[i].b), std::max(b.segments[i].a, b.segments[i].b)}))
                f.segments.push_back(b.segments[i]);
        // The new points take the mean length of their segments as their size.
        std::vector<double> len_sum(f.size(), 0.0);
        std::vector<int> len_count(f.size(), 0);
        for (size_t i = 0; i < f.loop_segment_count; ++i) {
            const double len = distance(f.point(f.segments[i].a), f.point(f.segments[i].b));
            for (VertexId v : {f.segments[i].a, f.segments[i].b}) {
                len_sum[v] += len;
                ++len_count[v];
            }
        }
        for (VertexId v = static_cast<VertexId>(d_.size()); v < f.size(); ++v)
            f.rho[v] = len_count[v] ? len_sum[v] / len_count[v] : rho_.interior(f.point(v));
        for (VertexId v = static_cast<VertexId>(d_.size()); v < g.boundary.size(); ++v) g.boundary.rho[v] = f.rho[v];

        cells(g);
        figures(g);
        split_quads(g);
        return g;
    }

    // A cell between two neighbouring columns: its corners (counter-clockwise), and its side
    // that is no column's (its top, or a step's diagonal).
    struct Cell {
        std::array<std::uint32_t, 4> v;
        int corners;
        std::array<std::uint32_t, 2> across;
        int spec;
        std::uint32_t strip;  // k: between columns k and k + 1
    };

    // The cells between each pair of neighbouring columns of a chain: quads level by level
    // (a fan's first cell a triangle: both columns start at one point), then, where one
    // column is taller, triangles from its points to the other's top (the steps).
    template <class F>
    static void walk_cells(const Chain& c, F&& visit) {
        const size_t nc = c.columns.size();
        for (size_t k = 0; k < nc; ++k) {
            if (k + 1 == nc && !c.closed) break;
            walk_strip(c, k, visit);
        }
    }

    // The cells of strip k alone (between columns k and k + 1, cyclic on a closed chain).
    template <class F>
    static void walk_strip(const Chain& c, size_t k, F&& visit) {
        const size_t nc = c.columns.size();
        const auto& P = c.columns[k].ids;
        const auto& Q = c.columns[(k + 1) % nc].ids;
        const int spec = c.columns[k].spec;
        const size_t na = P.size() - 1, nb = Q.size() - 1, common = std::min(na, nb);
        const bool fan = P[0] == Q[0];
        const auto s = static_cast<std::uint32_t>(k);
        for (size_t l = 0; l < common; ++l) {
            if (l == 0 && fan) visit(Cell{{P[0], Q[1], P[1], 0}, 3, {Q[1], P[1]}, spec, s});
            else visit(Cell{{P[l], Q[l], Q[l + 1], P[l + 1]}, 4, {Q[l + 1], P[l + 1]}, spec, s});
        }
        for (size_t l = nb; l < na; ++l)
            if (!(l == 0 && fan)) visit(Cell{{P[l], Q[nb], P[l + 1], 0}, 3, {Q[nb], P[l + 1]}, spec, s});
        for (size_t l = na; l < nb; ++l)
            if (!(l == 0 && fan)) visit(Cell{{P[na], Q[l], Q[l + 1], 0}, 3, {P[na], Q[l + 1]}, spec, s});
    }

    void cells(GrownLayers& g) {
        for (const Chain& c : chains_)
            walk_cells(c, [&](const Cell& cell) {
                if (cell.corners == 4) {
                    g.quads.push_back(cell.v);
                    quad_spec_.push_back(cell.spec);
                } else {
                    g.triangles.push_back({cell.v[0], cell.v[1], cell.v[2]});
                }
            });
    }

    // The quads of entries that asked for triangles: split along their shorter diagonal.
    void split_quads(GrownLayers& g) const {
        std::vector<std::array<std::uint32_t, 4>> kept;
        for (size_t q = 0; q < g.quads.size(); ++q) {
            const auto& Q = g.quads[q];
            if (specs_[static_cast<size_t>(quad_spec_[q])].quads) {
                kept.push_back(Q);
                continue;
            }
            if (distance(cell_point(g, Q[0]), cell_point(g, Q[2])) <= distance(cell_point(g, Q[1]), cell_point(g, Q[3]))) {
                g.triangles.push_back({Q[0], Q[1], Q[2]});
                g.triangles.push_back({Q[0], Q[2], Q[3]});
            } else {
                g.triangles.push_back({Q[0], Q[1], Q[3]});
                g.triangles.push_back({Q[1], Q[2], Q[3]});
            }
        }
        g.quads = std::move(kept);
    }

    Vec2 cell_point(const GrownLayers& g, std::uint32_t id) const {
        if (id & GrownLayers::kHidden) return g.hidden[id & ~GrownLayers::kHidden];
        return g.front.point(id);
    }

    void figures(GrownLayers& g) {
        g.figures.assign(specs_.size(), {});
        std::vector<bool> seen(specs_.size(), false);
        for (Chain& c : chains_) {
            const size_t nc = c.columns.size();
            bool in_run = false;
            size_t run_start = 0;
            auto close_run = [&](size_t end) {
                const Column& mid = c.columns[(run_start + end) / 2];
                auto& fig = g.figures[static_cast<size_t>(mid.spec)];
                if (fig.cut_back_at.size() < 16) fig.cut_back_at.push_back(pt(mid.base));
                in_run = false;
            };
            for (size_t k = 0; k < nc; ++k) {
                const Column& col = c.columns[k];
                auto& fig = g.figures[static_cast<size_t>(col.spec)];
                if (!seen[static_cast<size_t>(col.spec)]) {
                    fig.layers_min = fig.layers_max = col.n;
                    fig.first_height_min = HUGE_VAL;
                    fig.first_height_max = 0.0;
                    seen[static_cast<size_t>(col.spec)] = true;
                }
                fig.layers_min = std::min(fig.layers_min, col.n);
                fig.layers_max = std::max(fig.layers_max, col.n);
                ++fig.columns;
                const bool short_of = col.n < col.want;
                if (short_of) ++fig.cut_back;
                if (short_of && !in_run) {
                    in_run = true;
                    run_start = k;
                } else if (!short_of && in_run) {
                    close_run(k - 1);
                }
                // The first cell's height over the wall segment to the next column.
                if (k + 1 == nc && !c.closed) continue;
                const Column& nxt = c.columns[(k + 1) % nc];
                if (nxt.base == col.base || col.n == 0 || nxt.n == 0) continue;
                const Vec2 a = pt(col.base), b = pt(nxt.base);
                const Vec2 mid = 0.5 * (cell_point(g, col.ids[1]) + cell_point(g, nxt.ids[1]));
                const double h = std::fabs(cross(b - a, mid - a)) / distance(a, b);
                fig.first_height_min = std::min(fig.first_height_min, h);
                fig.first_height_max = std::max(fig.first_height_max, h);
            }
            if (in_run) close_run(nc - 1);
        }
        for (auto& fig : g.figures)
            if (fig.first_height_min == HUGE_VAL) fig.first_height_min = 0.0;
        for (size_t q = 0; q < g.quads.size(); ++q) {
            auto& fig = g.figures[static_cast<size_t>(quad_spec_[q])];
            std::array<Vec2, 4> p;
            for (size_t i = 0; i < 4; ++i) p[i] = cell_point(g, g.quads[q][i]);
            double lo = HUGE_VAL, hi = 0.0;
            for (size_t i = 0; i < 4; ++i) {
                const double len = distance(p[i], p[(i + 1) % 4]);
                lo = std::min(lo, len);
                hi = std::max(hi, len);
                const Vec2 e1 = p[(i + 1) % 4] - p[i], e0 = p[(i + 3) % 4] - p[i];
                fig.scaled_jacobian_min = std::min(fig.scaled_jacobian_min, cross(e1, e0) / (norm(e1) * norm(e0)));
                const double corner = std::atan2(cross(e1, e0), dot(e1, e0));
                fig.skew_max = std::max(fig.skew_max, std::fabs(corner - std::numbers::pi / 2) / (std::numbers::pi / 2));
            }
            fig.aspect_ratio_max = std::max(fig.aspect_ratio_max, hi / lo);
        }
    }

    const Domain& domain_;
    const Discretisation& d_;
    const SizeField& rho_;
    const std::vector<BoundaryLayerSpec>& specs_;
    size_t max_points_;
    Observer* observer_;
    const LayerPlan* plan_;
    const std::vector<LayerColumn>* limits_;
    bool final_ = false;  // run(), not plan(): the walls are placed for good
    std::vector<int> spec_of_;
    std::vector<size_t> loop_offsets_;  // per loop, the index of its first segment
    std::vector<std::vector<double>> level_;
    std::vector<Chain> chains_;
    std::vector<int> quad_spec_;
    mutable std::map<CurveId, std::unique_ptr<CurveParametrisation>> arcs_;  // curves the domain has none for
};

}  // namespace

GrownLayers grow_layers(const Domain& domain, const Discretisation& d, const SizeField& rho,
                        const std::vector<BoundaryLayerSpec>& specs, size_t max_points, Observer* observer,
                        const LayerPlan* plan, const std::vector<LayerColumn>* limits) {
    return Grower(domain, d, rho, specs, max_points, observer, plan, limits).run();
}

namespace {

// `again`'s caps merged into `into`, found by their points: new ones join, and those more than
// a fifth smaller replace theirs; `taken(i, k)` hears of each (i in `again`, k in `into`). True
// when any did.
template <class Taken>
bool merge_caps(SizeCaps& into, const SizeCaps& again, Taken&& taken) {
    bool changed = false;
    const auto at_point = index_of_points(into.points);
    for (size_t i = 0; i < again.points.size(); ++i) {
        const auto at = at_point.find({again.points[i].x, again.points[i].y});
        size_t k = 0;
        if (at == at_point.end()) {
            k = into.points.size();
            into.points.push_back(again.points[i]);
            into.sizes.push_back(again.sizes[i]);
        } else if (again.sizes[i] < 0.8 * into.sizes[at->second]) {
            k = at->second;
            into.sizes[k] = again.sizes[i];
        } else {
            continue;
        }
        taken(i, k);
        changed = true;
    }
    return changed;
}

}  // namespace

bool narrow_fans(LayerPlan& plan, const LayerPlan& again) {
    const bool tops = merge_caps(plan.tops, again.tops, [](size_t, size_t) {});
    // A fan of `again` that `plan` lacks: the first walls left it no room (its columns all cut
    // back), and it stands on the walls placed for the others.
    const bool fans = merge_caps(plan.fans, again.fans, [&](size_t i, size_t k) {
        if (k == plan.fan_heights.size()) {
            plan.fan_heights.push_back(again.fan_heights[i]);
        } else {
            plan.fan_heights[k] = again.fan_heights[i];
        }
    });
    return tops || fans;
}

LayerPlan plan_layers(const Domain& domain, const Discretisation& d, const SizeField& rho,
                      const std::vector<BoundaryLayerSpec>& specs, size_t max_points, Observer* observer) {
    return Grower(domain, d, rho, specs, max_points, observer).plan();
}

}  // namespace meshd::core
