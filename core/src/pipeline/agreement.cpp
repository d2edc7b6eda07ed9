// Curve spacing made to agree with the interior field; see agreement.hpp.

#include "pipeline/agreement.hpp"

#include <algorithm>
#include <cmath>

#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

// A violating segment is probed at this many places at most (its length over the field,
// rounded up): enough for the caps' cones to cover it between probes.
constexpr double kMaxProbesPerSegment = 256.0;

// rho inside at p, or NaN where the interior density is not defined (a probe that fell
// outside a narrow part of the domain, where an expression may be invalid): no cap from it.
double field_at(const SizeField& rho, Vec2 p) {
    try {
        return rho.interior(p);
    } catch (const GeometryError&) {
        return NAN;
    }
}

}  // namespace

AgreementStats agree_with_interior(const Domain& domain, SizeField& rho, const BoundaryOptions& options,
                                   Discretisation& d, Observer* observer) {
    AgreementStats stats;
    std::vector<Vec2> caps;
    std::vector<double> sizes;
    for (int round = 0; round < kAgreementRounds; ++round) {
        const size_t before = caps.size();
        for (size_t i = 0; i < d.segments.size(); ++i) {
            const BoundarySegment& s = d.segments[i];
            const Vec2 a = d.point(s.a), b = d.point(s.b);
            const double l = distance(a, b);
            if (!(l > 0.0)) continue;
            const Vec2 n = perp((b - a) / l);  // the domain's side of a loop segment
            const bool embedded = i >= d.loop_segment_count;
            // Half a segment inside: where the first interior points would go, and far enough
            // from the segment's own ends that eq. 6.1 is not just their length there.
            auto probe = [&](Vec2 at) {
                double f = field_at(rho, at + (0.5 * l) * n);
                if (embedded) f = std::fmin(f, field_at(rho, at - (0.5 * l) * n));
                return f;
            };
            const double f = probe(0.5 * (a + b));
            if (!(l > kAgreementRatio * f)) continue;  // agrees (or no field there)
            const int k = static_cast<int>(std::fmin(kMaxProbesPerSegment, std::ceil(l / f)));
            for (int j = 0; j < k; ++j) {
                const Vec2 at = a + ((j + 0.5) / k) * (b - a);
                const double fj = probe(at);
                if (!(fj > 0.0)) continue;
                caps.push_back(at);
                sizes.push_back(fj);
            }
        }
        if (caps.size() == before) break;
        if (observer && observer->should_stop()) throw Cancelled();
        stats.probes = caps.size();
        ++stats.rounds;
        rho.set_curve_cap(caps, sizes, kAgreementCapRatio);
        d = discretise_boundary(domain, rho, options, observer);
        if (rho.interpolates()) set_interpolation_sources(rho, d);
    }
    return stats;
}

}  // namespace meshd::core
