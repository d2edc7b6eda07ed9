// The one-dimensional point generator of section 3.1.

#include <gtest/gtest.h>

#include <cmath>

#include "meshd/core/errors.hpp"
#include "boundary/spacing.hpp"

using namespace meshd::core;

namespace {

std::vector<double> generate(double length, const std::function<double(double)>& rho) {
    return graded_stations(sample_density(length, rho, 1e-9, 1u << 24));
}

// Largest |segment / ((rho(a) + rho(b)) / 2) - 1|.
double worst_ratio_error(const std::vector<double>& x, const std::function<double(double)>& rho) {
    double worst = 0.0;
    for (size_t i = 0; i + 1 < x.size(); ++i) {
        const double want = 0.5 * (rho(x[i]) + rho(x[i + 1]));
        worst = std::fmax(worst, std::fabs((x[i + 1] - x[i]) / want - 1.0));
    }
    return worst;
}

}  // namespace

TEST(Spacing, UniformDensityGivesEqualSegmentsAndExactEnds) {
    for (double h : {0.1, 0.07, 0.033}) {
        auto rho = [h](double) { return h; };
        const auto x = generate(1.0, rho);
        EXPECT_EQ(x.front(), 0.0);
        EXPECT_EQ(x.back(), 1.0);
        EXPECT_EQ(x.size() - 1, static_cast<size_t>(std::lround(1.0 / h)));
        for (size_t i = 0; i + 1 < x.size(); ++i) EXPECT_NEAR(x[i + 1] - x[i], 1.0 / (x.size() - 1), 1e-12);
    }
}

TEST(Spacing, LinearDensityFollowsTheSpacingLaw) {
    auto rho = [](double s) { return 0.01 + 0.05 * s; };
    const auto x = generate(10.0, rho);
    EXPECT_EQ(x.back(), 10.0);
    EXPECT_LT(worst_ratio_error(x, rho), 0.03);
    for (size_t i = 1; i < x.size(); ++i) EXPECT_GT(x[i], x[i - 1]);
}

TEST(Spacing, SmoothAndSteepDensities) {
    const std::vector<std::function<double(double)>> cases = {
        [](double s) { return 0.02 + 0.01 * std::sin(3 * s); },
        [](double s) { return 0.001 + 0.1 * std::fabs(s - 0.5); },        // kink, strong grading
        [](double s) { return 0.002 * std::exp(3 * s); },                   // geometric growth
        [](double s) { return 0.05 / (1 + 100 * (s - 0.3) * (s - 0.3)); },  // local refinement
    };
    for (size_t k = 0; k < cases.size(); ++k) {
        const auto x = generate(1.0, cases[k]);
        EXPECT_EQ(x.back(), 1.0);
        EXPECT_LT(worst_ratio_error(x, cases[k]), 0.05) << "case " << k << " with " << x.size() << " points";
    }
}

TEST(Spacing, ShortIntervalGetsOneSegment) {
    const auto x = generate(0.01, [](double) { return 1.0; });
    ASSERT_EQ(x.size(), 2u);
    EXPECT_EQ(x[1], 0.01);
}

TEST(Spacing, TooManySamplesIsRefused) {
    EXPECT_THROW(sample_density(1.0, [](double) { return 1e-7; }, 1e-9, 1000), GeometryError);
}

// The samples of rho stay proportional to the points: halving until an interval is no longer
// than half the local size leaves intervals of a quarter to a half of it (at most four per
// point), and each costs at most two samples (its end and the midpoint check): eight per
// point at most. The time at up to 10^6 points is bench/'s (BM_SpacingInterval).
TEST(Spacing, SamplesProportionalToThePoints) {
    for (const double h : {1e-2, 1e-3, 1e-4}) {
        size_t calls = 0;
        auto rho = [&](double) { ++calls; return h; };
        const auto prof = sample_density(1.0, rho, 1e-9, 1u << 24);
        const auto x = graded_stations(prof);
        EXPECT_EQ(x.size(), static_cast<size_t>(std::lround(1.0 / h)) + 1);
        EXPECT_LE(calls, 8u * x.size());
    }
}
