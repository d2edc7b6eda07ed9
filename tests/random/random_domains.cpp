#include "random_domains.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "core/fixtures.hpp"

namespace meshd::test {

using namespace core;

namespace {

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

}  // namespace

RandomCase random_case(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double scale = std::pow(10.0, -6.0 + 12.0 * u(rng));
    const double far = u(rng) < 0.5 ? 0.0 : std::pow(10.0, 5.0 * u(rng));
    const Vec2 shift{scale * far * (u(rng) - 0.5), scale * far * (u(rng) - 0.5)};
    auto world = [&](Vec2 p) { return Vec2{scale * p.x + shift.x, scale * p.y + shift.y}; };

    RandomCase rc;
    DomainSpec& s = rc.domain;
    const int kind = static_cast<int>(u(rng) * 3);  // 0 lines, 1 spline, 2 circle
    const int n = 5 + static_cast<int>(u(rng) * 8);
    std::vector<Vec2> outer;
    for (int i = 0; i < n; ++i) {
        const double t = 2.0 * std::numbers::pi * (i + 0.2 + 0.6 * u(rng)) / n;
        const double r = kind == 2 ? 1.0 : 0.75 + 0.25 * u(rng);
        outer.push_back({r * std::cos(t), r * std::sin(t)});
    }
    std::vector<std::string> outer_names;
    if (kind == 0) {
        for (int i = 0; i < n; ++i) s.points.push_back({"P" + std::to_string(i), world(outer[static_cast<size_t>(i)])});
        for (int i = 0; i < n; ++i) {
            const std::string name = "side" + std::to_string(i);
            s.curves.push_back(line(name, "P" + std::to_string(i), "P" + std::to_string((i + 1) % n),
                                    i == 0 ? std::optional<std::string>("inlet") : std::nullopt));
            outer_names.push_back(name);
        }
    } else if (kind == 1) {
        SplineShape sp;
        for (const Vec2& p : outer) sp.through.push_back(world(p));
        sp.through.push_back(world(outer.front()));
        s.curves.push_back({"outer", sp, std::nullopt, std::nullopt, std::string("wall")});
        outer_names.push_back("outer");
    } else {
        s.points.push_back({"P0", world({1.0, 0.0})});
        s.curves.push_back(arc("outer", "P0", "P0", world({0.0, 0.0})));
        outer_names.push_back("outer");
        outer = {{1.0, 0.0}};
    }
    std::vector<LoopItem> outer_loop;
    for (const auto& nm : outer_names) outer_loop.push_back({nm, false});
    s.loops.push_back(outer_loop);

    // Holes inside the disk of radius 0.55 (the outer loop stays outside 0.7 of the centre: a
    // spline through points at 0.75..1 may swing inside them, by less than that).
    std::vector<std::pair<Vec2, double>> holes;
    const int hole_count = static_cast<int>(u(rng) * 4);
    for (int attempt = 0; attempt < 50 && static_cast<int>(holes.size()) < hole_count; ++attempt) {
        const double r = 0.04 + 0.08 * u(rng);
        const double t = 2.0 * std::numbers::pi * u(rng), d = (0.5 - r) * std::sqrt(u(rng));
        const Vec2 c{d * std::cos(t), d * std::sin(t)};
        bool ok = true;
        for (const auto& [c2, r2] : holes) ok = ok && distance(c, c2) > r + r2 + 0.05;
        if (ok) holes.push_back({c, r});
    }
    for (size_t i = 0; i < holes.size(); ++i) {
        const auto [c, r] = holes[i];
        const std::string h = "h" + std::to_string(i);
        if (u(rng) < 0.5) {
            s.points.push_back({h, world(c + Vec2{r, 0.0})});
            s.curves.push_back(arc(h, h, h, world(c), u(rng) < 0.5 ? ArcDirection::Ccw : ArcDirection::Cw,
                                   std::string("hole")));
            s.loops.push_back({{h, false}});
            if (u(rng) < 0.4) {
                // A short embedded spoke ending on the circle (which is split there): holes are
                // more than 0.05 apart and the wake below keeps 0.05 off them.
                const double t = 2.0 * std::numbers::pi * u(rng);
                const Vec2 dir{std::cos(t), std::sin(t)};
                s.points.push_back({h + "s0", world(c + r * dir)});
                s.points.push_back({h + "s1", world(c + (r + 0.03) * dir)});
                s.curves.push_back(line(h + "spoke", h + "s0", h + "s1", std::string("spoke")));
                s.embedded.push_back(h + "spoke");
            }
        } else {
            // A triangle or square hole.
            const int m = 3 + static_cast<int>(u(rng) * 2);
            std::vector<LoopItem> l;
            for (int k = 0; k < m; ++k) {
                const double t = 2.0 * std::numbers::pi * k / m;
                s.points.push_back({h + "p" + std::to_string(k), world(c + r * Vec2{std::cos(t), std::sin(t)})});
            }
            for (int k = 0; k < m; ++k) {
                const std::string e = h + "e" + std::to_string(k);
                s.curves.push_back(line(e, h + "p" + std::to_string(k), h + "p" + std::to_string((k + 1) % m),
                                        std::string("hole")));
                l.push_back({e, false});
            }
            s.loops.push_back(l);
        }
    }

    // An embedded line from a corner of the outer loop (or its start) towards the centre, when
    // it keeps clear of the holes.
    if (kind != 1 && u(rng) < 0.6) {
        const Vec2 from = outer.front();
        const Vec2 to = (0.3 + 0.4 * u(rng)) * from + Vec2{0.1 * (u(rng) - 0.5), 0.1 * (u(rng) - 0.5)};
        bool clear = true;
        for (const auto& [c, r] : holes) {
            const Vec2 d = to - from;
            const double t = std::clamp(dot(c - from, d) / dot(d, d), 0.0, 1.0);
            clear = clear && distance(c, from + t * d) > r + 0.05;
        }
        if (clear) {
            s.points.push_back({"W", world(to)});
            s.curves.push_back(line("wake", "P0", "W", std::string("wake")));
            s.embedded.push_back("wake");
        }
    }

    // The density, in world coordinates.
    const double base = scale * (0.03 + 0.07 * u(rng));
    const Vec2 q = world({u(rng) - 0.5, u(rng) - 0.5});
    const std::string X = "((x-" + num(q.x) + ")/" + num(scale) + ")", Y = "((y-" + num(q.y) + ")/" + num(scale) + ")";
    switch (static_cast<int>(u(rng) * 3)) {
        case 0: rc.density.size = base; break;
        case 1: rc.density.size = num(base) + "*(1.2+0.5*" + X + ")"; break;
        default: rc.density.size = num(0.3 * base) + "+" + num(base) + "*sqrt(" + X + "^2+" + Y + "^2)"; break;
    }
    if (u(rng) < 0.3) rc.density.gradation = 1.2 + 0.3 * u(rng);
    rc.summary = "kind " + std::to_string(kind) + ", " + std::to_string(holes.size()) + " holes, " +
                 std::to_string(s.embedded.size()) + " embedded, scale " + num(scale) + ", shift (" +
                 num(shift.x) + ", " + num(shift.y) + ")";
    return rc;
}

std::optional<BoundaryLayerSpec> layers_for(std::uint64_t seed, const RandomCase& rc, const Domain& domain) {
    BoundaryLayerSpec spec;
    for (const std::string tag : {"hole", "wall", "inlet"}) {
        const bool present = std::any_of(rc.domain.curves.begin(), rc.domain.curves.end(), [&](const CurveSpec& c) {
            return c.tag == tag &&
                   std::find(rc.domain.embedded.begin(), rc.domain.embedded.end(), c.name) == rc.domain.embedded.end();
        });
        if (present) spec.curves.push_back(tag);
    }
    if (spec.curves.empty()) return std::nullopt;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    spec.first_height = domain.extent() * std::pow(10.0, -5.0 + 2.0 * u(rng));
    spec.growth = 1.1 + 0.2 * u(rng);
    spec.layers = 5 + static_cast<int>(u(rng) * 26);
    spec.quads = seed % 4 != 0;
    return spec;
}

std::pair<double, Vec2> smallest_free_angle(const Mesh& m) {
    std::pair<double, Vec2> worst{180.0, {}};
    for (const Triangle& t : m.triangles) {
        if (t.layer) continue;
        for (std::uint32_t i = 0; i < 3; ++i) {
            const Vec2 a = m.point(t.v[i]), b = m.point(t.v[(i + 1) % 3]), c = m.point(t.v[(i + 2) % 3]);
            const double angle = std::atan2(cross(b - a, c - a), dot(b - a, c - a)) * 180.0 / std::numbers::pi;
            // Edges (i+1) and (i+2) of t meet at its corner i.
            const bool wedge = edge_bit(t.constrained, (i + 1) % 3) && edge_bit(t.constrained, (i + 2) % 3);
            if (!wedge && angle < worst.first) worst = {angle, a};
        }
    }
    return worst;
}

bool same_mesh(const Mesh& a, const Mesh& b) {
    if (a.point_count() != b.point_count() || a.triangles.size() != b.triangles.size()) return false;
    for (size_t i = 0; i < a.point_count(); ++i)
        if (a.x[i] != b.x[i] || a.y[i] != b.y[i]) return false;
    for (size_t t = 0; t < a.triangles.size(); ++t)
        if (a.triangles[t].v != b.triangles[t].v) return false;
    return true;
}

}  // namespace meshd::test
