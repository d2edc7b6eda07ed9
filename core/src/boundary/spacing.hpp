#pragma once
/// Graded points on an interval (paper, section 3.1, after Lo 1991).
///
/// rho along [0, M] is replaced by its piecewise-linear interpolant h on stations
/// 0 = s_0 < ... < s_m = M (the paper uses m equal steps of a given dx; here the stations
/// are adaptive: an interval is split while it is longer than half the local size or while h
/// misses rho at its midpoint by more than kDensityInterpolation, so no dx has to be chosen).
/// From A the next point B solves |AB| = (h(A) + h(B)) / 2 (3.4); on each station interval
/// that relation is linear in B, so B is found exactly by scanning forward (3.13, 3.20).
/// When the next point would pass M, the number of segments n is fixed (the last point
/// moved onto M, or one more point moved back onto it, whichever is the smaller change), and
/// the leftover is spread over all segments (3.21-3.22): not by moving the points, which
/// would shift them by many local sizes where rho is small, but by scaling the target by a
/// common factor so that the n-th point lands on M. The end is hit exactly; cost: a few
/// marches, linear in m plus the number of points.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace meshd::core {

struct DensityProfile {
    std::vector<double> s;  ///< stations, increasing, s.front() == 0, s.back() == M
    std::vector<double> h;  ///< rho at the stations
};

/// Samples rho on [0, length]. Throws GeometryError(TooManyPoints) beyond max_stations.
/// rho must return finite positive values (the SizeField checks and throws otherwise).
/// An interval shorter than `floor` times the smaller size at its ends is not split further
/// (0: split down to the interpolation tolerance).
DensityProfile sample_density(double length, const std::function<double(double)>& rho,
                              double min_size, size_t max_stations, double floor = 0.0);

/// The graded points of the profile: 0 = x_0 < x_1 < ... < x_n = M, n >= 1. Throws
/// GeometryError(TooManyPoints) when n would exceed max_segments, after one march.
std::vector<double> graded_stations(const DensityProfile& profile, size_t max_segments = SIZE_MAX);

}  // namespace meshd::core
