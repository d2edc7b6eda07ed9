// CGAL on the benchmark case, for comparison only: never linked into meshd, built by
// bench/compare/run.sh from Debian's libcgal-dev.
//   cgal_bench naca S      Delaunay_mesher_2 with a size criterion from the Fig. 10 density
//                          times S (longest edge against rho at the centroid) and CGAL's
//                          default shape bound (B = 0.125, about 20.7 degrees)
//   cgal_bench random N    Delaunay_triangulation_2 of N random points (spatially sorted insert)
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Point = K::Point_2;

static double g_s = 1.0;

static double rho(double x, double y) {
    const double a = 0.1 * std::sqrt(x * x + y * y) + 0.007;
    const double b = 0.1 * std::sqrt((x - 1.008930411365) * (x - 1.008930411365) + y * y) + 0.006;
    return (x < 0.5 ? a : b) * g_s;
}

// CGAL's size criteria with the constant bound replaced by rho at the triangle's centroid.
struct RhoCriteria : public CGAL::Delaunay_mesh_size_criteria_2<CDT> {
    using Base = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
    explicit RhoCriteria(double aspect) : Base(aspect, 1.0) {}

    struct Is_bad : public Base::Is_bad {
        explicit Is_bad(double aspect, const K& traits) : Base::Is_bad(aspect, 1.0, traits) {}
        using Base::Is_bad::operator();
        CGAL::Mesh_2::Face_badness operator()(const CDT::Face_handle& fh, Quality& q) const {
            const Point& a = fh->vertex(0)->point();
            const Point& b = fh->vertex(1)->point();
            const Point& c = fh->vertex(2)->point();
            const double la = CGAL::to_double(CGAL::squared_distance(b, c));
            const double lb = CGAL::to_double(CGAL::squared_distance(c, a));
            const double lc = CGAL::to_double(CGAL::squared_distance(a, b));
            const double longest = std::max({la, lb, lc});
            const double second = la + lb + lc - longest - std::min({la, lb, lc});
            const double h = rho((a.x() + b.x() + c.x()) / 3, (a.y() + b.y() + c.y()) / 3);
            q.second = longest / (h * h);
            if (q.size() > 1) {
                q.first = 1;
                return CGAL::Mesh_2::IMPERATIVELY_BAD;
            }
            const double area = 2 * CGAL::to_double(CGAL::area(a, b, c));
            q.first = area * area / (longest * second);
            return q.sine() < this->B ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
        }
    };
    Is_bad is_bad_object() const { return Is_bad(this->bound(), this->traits); }
};

static double peak_mb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;
}

static double thickness(double x) {
    return 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - 0.1036 * x * x * x * x);
}

int main(int argc, char** argv) {
    if (argc < 3) return 2;
    if (std::strcmp(argv[1], "random") == 0) {
        const size_t n = std::strtoull(argv[2], nullptr, 10);
        std::mt19937_64 rng(12345);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<Point> pts;
        pts.reserve(n);
        for (size_t i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng));
        const auto t0 = std::chrono::steady_clock::now();
        CGAL::Delaunay_triangulation_2<K> dt;
        dt.insert(pts.begin(), pts.end());
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        std::printf("{\"tool\":\"CGAL Delaunay_triangulation_2\",\"case\":\"random\",\"points\":%zu,\"triangles\":%zu,\"ms\":%.1f,\"peak_mb\":%.1f}\n",
                    n, static_cast<size_t>(dt.number_of_faces()), ms, peak_mb());
        return 0;
    }
    g_s = std::atof(argv[2]);
    CDT cdt;
    const int n = 200;
    std::vector<Point> foil;
    for (int i = 0; i < n; ++i) {  // upper surface, trailing to leading edge
        const double x = 0.5 * (1 + std::cos(M_PI * i / n));
        foil.emplace_back(x, thickness(x));
    }
    for (int i = 0; i < n; ++i) {  // lower surface, leading to trailing edge
        const double x = 0.5 * (1 - std::cos(M_PI * i / n));
        foil.emplace_back(x, -thickness(x));
    }
    std::vector<Point> ring;
    for (int k = 0; k < 256; ++k) ring.emplace_back(0.5 + 20 * std::cos(2 * M_PI * k / 256), 20 * std::sin(2 * M_PI * k / 256));
    const auto t0 = std::chrono::steady_clock::now();
    cdt.insert_constraint(foil.begin(), foil.end(), true);
    cdt.insert_constraint(ring.begin(), ring.end(), true);
    std::vector<Point> seeds{Point(0.5, 0.0)};
    CGAL::refine_Delaunay_mesh_2(cdt, seeds.begin(), seeds.end(), RhoCriteria(0.125), false);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // Figures over the triangles of the domain.
    size_t tris = 0;
    double qsum = 0, qmin = 1, amin = 180;
    std::vector<double> ratios;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) continue;
        ++tris;
        const Point p[3] = {f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()};
        const double l[3] = {std::sqrt(CGAL::squared_distance(p[1], p[2])), std::sqrt(CGAL::squared_distance(p[2], p[0])),
                             std::sqrt(CGAL::squared_distance(p[0], p[1]))};
        const double area = std::fabs(CGAL::area(p[0], p[1], p[2]));
        const double q = 16 * area * area / (l[0] * l[1] * l[2] * (l[0] + l[1] + l[2]));
        qsum += q;
        qmin = std::min(qmin, q);
        for (int i = 0; i < 3; ++i) {
            const double c = (l[(i + 1) % 3] * l[(i + 1) % 3] + l[(i + 2) % 3] * l[(i + 2) % 3] - l[i] * l[i]) / (2 * l[(i + 1) % 3] * l[(i + 2) % 3]);
            amin = std::min(amin, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
            // Each interior edge is seen twice; close enough for a fraction.
            const Point& a = p[(i + 1) % 3];
            const Point& b = p[(i + 2) % 3];
            ratios.push_back(l[i] / rho((a.x() + b.x()) / 2, (a.y() + b.y()) / 2));
        }
    }
    size_t within = 0;
    for (double r : ratios) within += (r >= 1 / std::sqrt(2.0) && r <= std::sqrt(2.0)) ? 1 : 0;
    std::printf("{\"tool\":\"CGAL Delaunay_mesher_2\",\"case\":\"naca\",\"s\":%g,\"points\":%zu,\"triangles\":%zu,\"ms\":%.1f,"
                "\"peak_mb\":%.1f,\"quality_mean\":%.4f,\"quality_min\":%.4f,\"angle_min\":%.2f,\"within_sqrt2\":%.4f}\n",
                g_s, static_cast<size_t>(cdt.number_of_vertices()), tris, ms, peak_mb(), qsum / tris, qmin, amin,
                static_cast<double>(within) / ratios.size());
    return 0;
}
