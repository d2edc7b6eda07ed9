// Interior points by the advancing front (algorithm 4.1); see interior.hpp.

#include "interior/interior.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "triangulation/triangle_soup.hpp"
#include "kernel/size_grid.hpp"
#include "meshd/core/errors.hpp"
#include "kernel/predicates.hpp"

namespace meshd::core {

namespace {

using detail::CellMap;
using detail::SizeClasses;
using detail::next3;
using detail::prev3;

struct FrontSegment {
    std::uint32_t a, b;
    bool alive;
    bool boundary;  // a segment of the discretised boundary (never split onto itself)
};

class AdvancingFront {
public:
    AdvancingFront(const Domain& domain, const Discretisation& d, const BoundaryTriangulation& walls,
                   const SizeField& rho, const InteriorOptions& opt, size_t max_points, Observer* obs,
                   InteriorStats& stats)
        : rho_(rho), opt_(opt), max_points_(max_points), obs_(obs), stats_(stats),
          box_(domain.box()),
          classes_(domain.box().lo - Vec2{domain.extent(), domain.extent()}, domain.extent()),
          wall_points_(walls.points), wall_triangles_(walls.triangles),
          walls_(wall_points_, wall_triangles_, true) {
        // Points: the boundary's, with their curve densities.
        const size_t nb = d.size();
        pts_.reserve(nb * 4);
        for (VertexId v = 0; v < nb; ++v) add_point(d.point(v), d.rho[v], kNoTriangle);
        boundary_count_ = nb;
        for (size_t i = 0; i < d.segments.size(); ++i) {
            const auto& s = d.segments[i];
            push_segment(s.a, s.b, true);
            if (i >= d.loop_segment_count) push_segment(s.b, s.a, true);  // embedded: both sides
        }
    }

    std::vector<Vec2> run() {
        std::uint64_t steps = 0;
        while (!stack_.empty()) {
            if ((++steps & 1023) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Interior, std::fmin(0.99, static_cast<double>(stats_.accepted) /
                                                                      static_cast<double>(stats_.accepted + stack_.size() + 1)));
            }
            const std::uint32_t s = stack_.back();
            stack_.pop_back();
            if (!front_[s].alive) continue;
            step(s);
        }
        std::vector<Vec2> out(pts_.begin() + static_cast<std::ptrdiff_t>(boundary_count_), pts_.end());
        return out;
    }

private:
    void add_point(Vec2 p, double r, TriangleId home) {
        const auto id = static_cast<std::uint32_t>(pts_.size());
        pts_.push_back(p);
        prho_.push_back(r);
        home_.push_back(home);
        const int k = classes_.class_of(r);
        for (int kk = k - 1; kk <= k + 1; ++kk) {
            if (kk < 1 || kk > SizeClasses::kMax) continue;
            points_.push(SizeClasses::key(kk, classes_.ix(p.x, kk), classes_.iy(p.y, kk)), id);
        }
        if (max_points_ && pts_.size() > max_points_)
            throw GeometryError(GeometryErrorKind::TooManyPoints,
                                "the mesh needs more than " + std::to_string(max_points_) + " points");
    }

    void push_segment(std::uint32_t a, std::uint32_t b, bool boundary) {
        const auto id = static_cast<std::uint32_t>(front_.size());
        front_.push_back({a, b, true, boundary});
        stack_.push_back(id);
        const Vec2 pa = pts_[a], pb = pts_[b];
        const int k = classes_.class_of(distance(pa, pb));
        for (auto x = classes_.ix(std::fmin(pa.x, pb.x), k); x <= classes_.ix(std::fmax(pa.x, pb.x), k); ++x)
            for (auto y = classes_.iy(std::fmin(pa.y, pb.y), k); y <= classes_.iy(std::fmax(pa.y, pb.y), k); ++y)
                segments_.push(SizeClasses::key(k, x, y), id);
    }

    // The candidate of (4.3)/(4.7)/(4.12)/(4.19) for segment a -> b with radii ra, rb.
    static bool candidate(Vec2 a, Vec2 b, double ra, double rb, bool boundary, Vec2& c) {
        const Vec2 ab = b - a;
        const double l = norm(ab);
        if (!(l > 0.0)) return false;
        const Vec2 u = ab / l, v = perp(u);
        if (ra + rb > l && ra + l > rb && rb + l > ra) {
            const double x = (l * l + ra * ra - rb * rb) / (2.0 * l);
            const double h = std::sqrt(std::fmax(ra * ra - x * x, 0.0));
            c = a + x * u + h * v;
        } else if (ra + rb <= l) {
            // (4.7-4.9): the point dividing AB as ra : rb. On a segment of the boundary that
            // would put a point on the boundary; there the apex of the equilateral triangle
            // is used instead.
            if (boundary) c = 0.5 * (a + b) + (0.5 * std::sqrt(3.0) * l) * v;
            else c = a + (ra / (ra + rb)) * ab;
        } else if (ra + l <= rb) {
            const double ad = std::sqrt(rb * rb - l * l);
            const double ac = ad - (ad - ra) / (1.0 + rb / ra);  // (4.17-4.18)
            c = a + ac * v;
        } else {
            const double bd = std::sqrt(ra * ra - l * l);
            const double bc = bd - (bd - rb) / (1.0 + ra / rb);  // (4.20)
            c = b + bc * v;
        }
        return is_finite(c);
    }

    // (4.22) against the points of classes k-3 .. k+1 around the class k of C: the grid of
    // class k holds classes k-1 .. k+1 and that of class k-2 holds k-3 .. k-1, so points up
    // to 16 times coarser than C are seen (their reach is largest) and down to 4 times finer.
    // The cell of C in its own class is looked at first: it holds the offending point of most
    // rejected candidates, and any offending point decides.
    bool near_other_point(Vec2 c, double rc, std::uint32_t a, std::uint32_t b) const {
        auto near_in_cell = [&](int kk, std::int64_t x, std::int64_t y) {
            for (auto e = points_.head(SizeClasses::key(kk, x, y)); e != CellMap::kNone; e = points_.next(e)) {
                const std::uint32_t p = points_.item(e);
                if (p == a || p == b) continue;
                const double lim = opt_.proximity * 0.5 * (rc + prho_[p]);
                if (norm2(pts_[p] - c) < lim * lim) return true;
            }
            return false;
        };
        const int k = classes_.class_of(rc);
        const std::int64_t cx = classes_.ix(c.x, k), cy = classes_.iy(c.y, k);
        if (near_in_cell(k, cx, cy)) return true;
        for (int kk : {k, k - 2}) {
            if (kk < 1) continue;
            // Largest rho in grid kk: 2 c_(kk-1) = 2 cell(kk); reach (rc + that) / 2.
            const double reach = opt_.proximity * 0.5 * (rc + 2.0 * classes_.cell(kk));
            const std::int64_t x0 = classes_.ix(c.x - reach, kk), x1 = classes_.ix(c.x + reach, kk);
            const std::int64_t y0 = classes_.iy(c.y - reach, kk), y1 = classes_.iy(c.y + reach, kk);
            for (auto x = x0; x <= x1; ++x)
                for (auto y = y0; y <= y1; ++y)
                    if (!(kk == k && x == cx && y == cy) && near_in_cell(kk, x, y)) return true;
        }
        return false;
    }

    // Does AC or BC cross a segment of the front (any segment ever made, so also those now
    // inside the covered region)? Each is checked against the segments of its class and the
    // two next to it, in one scan of the cells around ABC.
    bool crosses_front(std::uint32_t ia, std::uint32_t ib, Vec2 c) const {
        const Vec2 a = pts_[ia], b = pts_[ib];
        struct Edge {
            Vec2 p, lo, hi;
            int k;
        };
        const Edge edges[2] = {
            {a, {std::fmin(a.x, c.x), std::fmin(a.y, c.y)}, {std::fmax(a.x, c.x), std::fmax(a.y, c.y)}, classes_.class_of(distance(a, c))},
            {b, {std::fmin(b.x, c.x), std::fmin(b.y, c.y)}, {std::fmax(b.x, c.x), std::fmax(b.y, c.y)}, classes_.class_of(distance(b, c))}};
        const int k_lo = std::max(1, std::min(edges[0].k, edges[1].k) - 1);
        const int k_hi = std::min(SizeClasses::kMax, std::max(edges[0].k, edges[1].k) + 1);
        for (int k = k_lo; k <= k_hi; ++k) {
            const bool use[2] = {std::abs(k - edges[0].k) <= 1, std::abs(k - edges[1].k) <= 1};
            Box box;
            for (int i = 0; i < 2; ++i)
                if (use[i]) {
                    box.add(edges[i].lo);
                    box.add(edges[i].hi);
                }
            const std::int64_t x0 = classes_.ix(box.lo.x, k), x1 = classes_.ix(box.hi.x, k);
            const std::int64_t y0 = classes_.iy(box.lo.y, k), y1 = classes_.iy(box.hi.y, k);
            for (auto x = x0; x <= x1; ++x)
                for (auto y = y0; y <= y1; ++y)
                    for (auto e = segments_.head(SizeClasses::key(k, x, y)); e != CellMap::kNone; e = segments_.next(e)) {
                        const FrontSegment& s = front_[segments_.item(e)];
                        // Segments sharing an end with AB meet AC or BC there by construction.
                        if (s.a == ia || s.a == ib || s.b == ia || s.b == ib) continue;
                        const Vec2 sa = pts_[s.a], sb = pts_[s.b];
                        const Vec2 slo{std::fmin(sa.x, sb.x), std::fmin(sa.y, sb.y)};
                        const Vec2 shi{std::fmax(sa.x, sb.x), std::fmax(sa.y, sb.y)};
                        for (int i = 0; i < 2; ++i) {
                            const Edge& g = edges[i];
                            if (!use[i] || shi.x < g.lo.x || slo.x > g.hi.x || shi.y < g.lo.y || slo.y > g.hi.y)
                                continue;  // not this class, or the boxes do not meet
                            if (segments_intersect(g.p, c, sa, sb)) return true;
                        }
                    }
        }
        return false;
    }

    // The triangle of the boundary triangulation that holds c, reached by a straight walk
    // from `from` in triangle t without crossing a constraint; kNoTriangle when the way is
    // blocked, leaves the domain or is degenerate (a walk this long: refuse the point).
    TriangleId inside(TriangleId t, Vec2 from, Vec2 c) const {
        const detail::WalkEnd end = walls_.walk(t, from, c, 100000);
        return end.edge < 0 ? end.triangle : kNoTriangle;
    }

    // Triangle of the boundary triangulation from which to walk out of point v.
    TriangleId start_of(std::uint32_t v, Vec2 target) const {
        if (v < boundary_count_) return walls_.wedge(v, target);
        return home_[v];
    }

    void step(std::uint32_t s) {
        const FrontSegment seg = front_[s];
        const Vec2 a = pts_[seg.a], b = pts_[seg.b];
        const double ra = prho_[seg.a], rb = prho_[seg.b];
        Vec2 c;
        ++stats_.candidates;
        if (!candidate(a, b, ra, rb, seg.boundary, c)) {
            front_[s].alive = false;
            return;
        }
        if (orient2d(a, b, c) != Orientation::Left) {
            front_[s].alive = false;
            return;
        }
        // Outside the domain's box (far outside when the radii are very unequal): no search
        // should span the plane for it, nor rho be asked there.
        if (!box_.contains(c)) {
            ++stats_.rejected_outside;
            front_[s].alive = false;
            return;
        }
        double rc = rho_.interior(c);
        if (opt_.newton) {
            // One step towards the fixed point of (4.4): the radii become the mean sizes of
            // the new edges. (A second step changed the figures of the benchmark case by
            // less than 1e-3 and cost 9% of this stage.)
            Vec2 c2;
            if (candidate(a, b, 0.5 * (ra + rc), 0.5 * (rb + rc), seg.boundary, c2) &&
                orient2d(a, b, c2) == Orientation::Left && box_.contains(c2)) {
                c = c2;
                rc = rho_.interior(c);
            }
        }
        // The cheap local tests first: (4.22) rejects about half of all candidates.
        if (near_other_point(c, rc, seg.a, seg.b)) {
            ++stats_.rejected_near;
            front_[s].alive = false;
            return;
        }
        if (crosses_front(seg.a, seg.b, c)) {
            ++stats_.rejected_crossing;
            front_[s].alive = false;
            return;
        }
        // Paths from A and B to C must stay in the domain (this also decides C is inside).
        const TriangleId ta = start_of(seg.a, c);
        const TriangleId home_c = ta == kNoTriangle ? kNoTriangle : inside(ta, a, c);
        const TriangleId tb = home_c == kNoTriangle ? kNoTriangle : start_of(seg.b, c);
        if (home_c == kNoTriangle || tb == kNoTriangle || inside(tb, b, c) == kNoTriangle) {
            ++stats_.rejected_outside;
            front_[s].alive = false;
            return;
        }
        const auto id = static_cast<std::uint32_t>(pts_.size());
        add_point(c, rc, home_c);
        ++stats_.accepted;
        front_[s].alive = false;
        push_segment(seg.a, id, false);
        push_segment(id, seg.b, false);
    }

    const SizeField& rho_;
    const InteriorOptions& opt_;
    size_t max_points_;
    Observer* obs_;
    InteriorStats& stats_;
    Box box_;
    SizeClasses classes_;
    // The constrained triangulation of the boundary, for the walks that decide "inside".
    std::vector<Vec2> wall_points_;
    std::vector<Triangle> wall_triangles_;
    detail::TriangleSoup walls_;
    std::vector<Vec2> pts_;
    std::vector<double> prho_;
    std::vector<TriangleId> home_;
    size_t boundary_count_ = 0;
    std::vector<FrontSegment> front_;
    std::vector<std::uint32_t> stack_;
    CellMap points_, segments_;
};

}  // namespace

std::vector<Vec2> generate_interior_points(const Domain& domain, const Discretisation& boundary,
                                           const BoundaryTriangulation& walls, const SizeField& rho,
                                           const InteriorOptions& options, size_t max_points,
                                           Observer* observer, InteriorStats* stats) {
    InteriorStats local;
    AdvancingFront af(domain, boundary, walls, rho, options, max_points, observer, stats ? *stats : local);
    return af.run();
}

}  // namespace meshd::core
