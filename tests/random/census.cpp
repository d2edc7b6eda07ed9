// meshd-random-census: the smallest angle of the random domains' meshes (random_domains.hpp),
// for finding and looking at the cases below 30 degrees. Not a test: the tests hold the seeds
// this tool found once they are fixed.
//
//   meshd-random-census [--no-layers] [--each] [--graded] FROM TO
//       meshes seeds FROM..TO with the defaults (with their boundary layers, layers_for,
//       unless --no-layers; seeds without curves for layers are skipped then; with --graded,
//       only the seeds whose density names a gradation, the meshes a change to the
//       gradation alone can touch where no field jumps) and prints
//       each seed whose smallest free angle is below 30 degrees or whose mesh fails
//       check_mesh, then the counts and the mean of each domain's smallest angle (and how
//       many of the interior's candidates its crossing test refused). With
//       --each, also a line per mesh (its points, smallest free angle and a digest of its
//       points' bits and triangles): two builds' lists side by side (diff) name the meshes
//       a change touched.
//   meshd-random-census --picture SEED [--no-layers] [--zoom Z] [--at X Y] [--half H] [--out F]
//       writes an SVG of the mesh around the smallest angle (or around X Y): a window of Z
//       (default 6) times the longest edge there, or of half-width H. Layer cells blue,
//       triangles below 30 degrees red, curve edges blue and embedded ones green. Prints
//       the curve edges near it.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "meshd/core/errors.hpp"
#include "random_domains.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

struct Case {
    RandomCase rc;
    Domain domain;
    MeshOptions options;
};

// Seed's case with the options the property tests use, or nothing when it asks for layers and
// the domain has no curve to grow them on, or when its domain is refused.
std::optional<Case> case_for(std::uint64_t seed, bool layers) {
    Case c{random_case(seed), {}, {}};
    try {
        c.domain = build_domain(c.rc.domain);
    } catch (const GeometryError&) {
        return std::nullopt;
    }
    if (layers) {
        const auto spec = layers_for(seed, c.rc, c.domain);
        if (!spec) return std::nullopt;
        c.options.boundary_layers = {*spec};
        c.options.max_points = 400000;
    } else {
        c.options.max_points = 200000;
    }
    return c;
}

// FNV-1a over the mesh's point coordinates (their bits) and its triangles' corners in order:
// two builds' --each lists then differ wherever any mesh differs in any bit.
std::uint64_t digest(const Mesh& m) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    auto mix = [&h](std::uint64_t word) {
        for (int k = 0; k < 8; ++k, word >>= 8) h = (h ^ (word & 0xffu)) * 0x100000001b3ull;
    };
    for (std::uint32_t v = 0; v < m.point_count(); ++v) {
        const Vec2 p = m.point(v);
        mix(std::bit_cast<std::uint64_t>(p.x));
        mix(std::bit_cast<std::uint64_t>(p.y));
    }
    for (const Triangle& t : m.triangles)
        for (const VertexId v : t.v) mix(v);
    return h;
}

int census(std::uint64_t from, std::uint64_t to, bool layers, bool each, bool graded_only) {
    int below = 0, meshed = 0, refused = 0, invalid = 0, closed = 0, graded = 0, crossed = 0;
    double sum = 0.0, points = 0.0;
    // The interior's candidates, and those its crossing test refused (after the proximity
    // test (4.22) passed them): how often that test, a tenth of a small request, decides; and
    // the candidates whose test left the short segments to the crossing proof, in how many meshes.
    std::uint64_t candidates = 0, rejected_crossing = 0, proven = 0, blocks = 0;
    int proven_meshes = 0, block_meshes = 0;
    for (std::uint64_t seed = from; seed <= to; ++seed) {
        const auto c = case_for(seed, layers);
        if (!c || (graded_only && !c->rc.density.gradation)) continue;
        try {
            const MeshResult r = generate_mesh(c->domain, c->rc.density, c->options);
            const auto [angle, at] = smallest_free_angle(r.mesh);
            ++meshed;
            if (const auto broken = check_mesh(r.mesh, false); !broken.empty()) {
                ++invalid;
                std::printf("seed %llu: invalid: %s\n", static_cast<unsigned long long>(seed), broken.front().c_str());
            }
            sum += angle;
            points += static_cast<double>(r.quality.points);
            candidates += r.stats.interior.candidates;
            rejected_crossing += r.stats.interior.rejected_crossing;
            crossed += r.stats.interior.rejected_crossing > 0 ? 1 : 0;
            proven += r.stats.interior.crossings_proven;
            proven_meshes += r.stats.interior.crossings_proven > 0 ? 1 : 0;
            blocks += r.stats.interior.blocks_proven;
            block_meshes += r.stats.interior.blocks_proven > 0 ? 1 : 0;
            if (r.stats.interior.rejected_crossing > 0)
                std::printf("seed %llu: %llu candidates refused by the crossing test\n", static_cast<unsigned long long>(seed),
                            static_cast<unsigned long long>(r.stats.interior.rejected_crossing));
            if (each)
                std::printf("seed %llu: %zu points, %.4f degrees, digest %016llx\n", static_cast<unsigned long long>(seed),
                            r.quality.points, angle, static_cast<unsigned long long>(digest(r.mesh)));
            if (r.stats.layer_rounds > 3)
                std::printf("seed %llu: %d layer rounds (none mended all: grown again as at first), %.2f degrees\n",
                            static_cast<unsigned long long>(seed), r.stats.layer_rounds, angle);
            if (r.stats.gradation_applied > 0.0) {
                ++graded;
                std::printf("seed %llu: made again with the jump gradation (%llu jumps), %.2f degrees\n",
                            static_cast<unsigned long long>(seed), static_cast<unsigned long long>(r.stats.interior.jumps),
                            angle);
            }
            if (r.stats.closing_rounds > 0) {
                ++closed;
                std::printf("seed %llu: %d closing rounds, %.2f degrees\n", static_cast<unsigned long long>(seed),
                            r.stats.closing_rounds, angle);
            }
            if (angle < 30.0) {
                ++below;
                std::printf("seed %llu: %.2f degrees at (%.9g, %.9g); %s", static_cast<unsigned long long>(seed), angle, at.x,
                            at.y, c->rc.summary.c_str());
                if (layers) {
                    const BoundaryLayerSpec& s = c->options.boundary_layers.front();
                    std::printf("; layers %g x %g^k, %d; %d rounds", s.first_height, s.growth, s.layers,
                                r.stats.layer_rounds);
                }
                std::printf("\n");
            }
        } catch (const GeometryError& e) {
            ++refused;
            std::printf("seed %llu: refused: %s\n", static_cast<unsigned long long>(seed), e.what());
        }
    }
    std::printf("%d of %d meshes below 30 degrees (%d refused, %d invalid); mean smallest angle %.3f; %.0f points; "
                "%d with closing rounds; %d with the jump gradation\n",
                below, meshed, refused, invalid, sum / std::max(meshed, 1), points, closed, graded);
    std::printf("interior: %llu candidates, %llu refused by the crossing test, in %d meshes; %llu left the short "
                "segments to the crossing proof, in %d meshes; %llu blocks of short segments passed over by the "
                "proof made block by block, in %d meshes\n",
                static_cast<unsigned long long>(candidates), static_cast<unsigned long long>(rejected_crossing), crossed,
                static_cast<unsigned long long>(proven), proven_meshes, static_cast<unsigned long long>(blocks),
                block_meshes);
    return 0;
}

struct PictureOptions {
    std::uint64_t seed = 0;
    bool layers = true;
    double zoom = 6.0;
    std::optional<Vec2> at;
    double half = 0.0;
    std::string out;
};

double smallest_angle_of(const Mesh& m, const Triangle& t) {
    double smallest = 180.0;
    for (std::uint32_t i = 0; i < 3; ++i) {
        const Vec2 a = m.point(t.v[i]), b = m.point(t.v[(i + 1) % 3]), c = m.point(t.v[(i + 2) % 3]);
        smallest = std::min(smallest, std::atan2(cross(b - a, c - a), dot(b - a, c - a)) * 180.0 / std::numbers::pi);
    }
    return smallest;
}

int picture(const PictureOptions& p) {
    const auto c = case_for(p.seed, p.layers);
    if (!c) {
        std::fprintf(stderr, "seed %llu has no case%s\n", static_cast<unsigned long long>(p.seed),
                     p.layers ? " with layers" : "");
        return 1;
    }
    const Mesh m = generate_mesh(c->domain, c->rc.density, c->options).mesh;
    const auto [angle, worst] = smallest_free_angle(m);
    const Vec2 centre = p.at.value_or(worst);
    double half = p.half;
    if (half == 0.0) {
        double longest = 0.0;
        for (const Triangle& t : m.triangles)
            if (std::any_of(t.v.begin(), t.v.end(), [&](VertexId v) { return distance(m.point(v), centre) == 0.0; }))
                for (const VertexId v : t.v) longest = std::max(longest, distance(m.point(v), centre));
        half = p.zoom * (longest > 0.0 ? longest : 1e-3 * c->domain.extent());
    }
    const std::string path = p.out.empty() ? "/tmp/seed_" + std::to_string(p.seed) + ".svg" : p.out;
    FILE* svg = std::fopen(path.c_str(), "w");
    if (svg == nullptr) {
        std::perror(path.c_str());
        return 1;
    }
    const auto X = [&](Vec2 q) { return (q.x - centre.x + half) / (2.0 * half) * 1000.0; };
    const auto Y = [&](Vec2 q) { return 1000.0 - (q.y - centre.y + half) / (2.0 * half) * 1000.0; };
    const auto near = [&](Vec2 q) { return std::fabs(q.x - centre.x) < 1.5 * half && std::fabs(q.y - centre.y) < 1.5 * half; };
    std::fprintf(svg,
                 "<svg xmlns='http://www.w3.org/2000/svg' width='1000' height='1000' viewBox='0 0 1000 1000'>"
                 "<rect width='1000' height='1000' fill='white'/>\n");
    for (const Triangle& t : m.triangles) {
        if (!std::any_of(t.v.begin(), t.v.end(), [&](VertexId v) { return near(m.point(v)); })) continue;
        const char* fill = t.layer ? "#cce" : smallest_angle_of(m, t) < 30.0 ? "#f88" : "#efe";
        std::fprintf(svg, "<polygon points='");
        for (const VertexId v : t.v) std::fprintf(svg, "%.2f,%.2f ", X(m.point(v)), Y(m.point(v)));
        std::fprintf(svg, "' fill='%s' stroke='black' stroke-width='0.7'/>\n", fill);
    }
    for (const auto& q : m.quads) {
        if (!std::any_of(q.begin(), q.end(), [&](VertexId v) { return near(m.point(v)); })) continue;
        std::fprintf(svg, "<polygon points='");
        for (const VertexId v : q) std::fprintf(svg, "%.2f,%.2f ", X(m.point(v)), Y(m.point(v)));
        std::fprintf(svg, "' fill='#ccf' stroke='black' stroke-width='0.5'/>\n");
    }
    for (const MeshEdge& e : m.edges) {
        const Vec2 a = m.point(e.a), b = m.point(e.b);
        if (!near(a) && !near(b)) continue;
        std::fprintf(svg, "<line x1='%.2f' y1='%.2f' x2='%.2f' y2='%.2f' stroke='%s' stroke-width='2.5'/>\n", X(a), Y(a), X(b),
                     Y(b), e.embedded ? "green" : "blue");
        if (distance(a, centre) < 1.2 * half || distance(b, centre) < 1.2 * half)
            std::printf("edge (%.9g, %.9g)-(%.9g, %.9g) length %.4g%s\n", a.x, a.y, b.x, b.y, distance(a, b),
                        e.embedded ? " embedded" : "");
    }
    std::fprintf(svg, "<circle cx='%.2f' cy='%.2f' r='6' fill='none' stroke='red' stroke-width='2'/></svg>\n", X(centre),
                 Y(centre));
    std::fclose(svg);
    std::printf("seed %llu: %.2f degrees at (%.9g, %.9g); window half-width %.4g; %s\n-> %s\n",
                static_cast<unsigned long long>(p.seed), angle, worst.x, worst.y, half, c->rc.summary.c_str(), path.c_str());
    return 0;
}

int usage() {
    std::fprintf(stderr,
                 "usage: meshd-random-census [--no-layers] [--each] [--graded] FROM TO\n"
                 "       meshd-random-census --picture SEED [--no-layers] [--zoom Z] [--at X Y] [--half H] [--out FILE]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        PictureOptions p;
        bool draw = false, each = false, graded_only = false;
        std::vector<std::uint64_t> range;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            const auto next = [&]() -> const char* {
                if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
                return argv[++i];
            };
            if (a == "--no-layers") {
                p.layers = false;
            } else if (a == "--each") {
                each = true;
            } else if (a == "--graded") {
                graded_only = true;
            } else if (a == "--picture") {
                draw = true;
                p.seed = std::stoull(next());
            } else if (a == "--zoom") {
                p.zoom = std::stod(next());
            } else if (a == "--half") {
                p.half = std::stod(next());
            } else if (a == "--at") {
                const double x = std::stod(next());
                p.at = Vec2{x, std::stod(next())};
            } else if (a == "--out") {
                p.out = next();
            } else if (!a.empty() && a[0] != '-') {
                range.push_back(std::stoull(a));
            } else {
                return usage();
            }
        }
        if (draw) return range.empty() ? picture(p) : usage();
        if (range.size() != 2 || range[0] > range[1]) return usage();
        return census(range[0], range[1], p.layers, each, graded_only);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "meshd-random-census: %s\n", e.what());
        return 1;
    }
}
