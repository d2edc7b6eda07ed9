// Density expressions, the per-curve table, clamps, errors, and eq. 6.1 with its bound.

#include <gtest/gtest.h>

#include <numbers>
#include <thread>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <utility>

#include "fixtures.hpp"
#include "boundary/boundary.hpp"
#include "density/gradation.hpp"
#include "density/inverse_distance.hpp"
#include "density/size_field.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/agreement.hpp"
#include "pipeline/estimate.hpp"

using namespace meshd::core;
using namespace meshd::test;

TEST(Expression, OperatorsAndFunctionsOfTheContract) {
    EXPECT_DOUBLE_EQ(Expression("x + y * 2 - 1 / 4")(1, 2), 4.75);
    EXPECT_DOUBLE_EQ(Expression("x ^ 2")(3, 0), 9.0);
    EXPECT_DOUBLE_EQ(Expression("x < 0.5 ? 1 : 2")(0.2, 0), 1.0);
    EXPECT_DOUBLE_EQ(Expression("x < 0.5 ? 1 : 2")(0.7, 0), 2.0);
    EXPECT_DOUBLE_EQ(Expression("x > 0 && y > 0 ? 1 : 0")(1, -1), 0.0);
    EXPECT_DOUBLE_EQ(Expression("x > 0 || y > 0 ? 1 : 0")(1, -1), 1.0);
    EXPECT_DOUBLE_EQ(Expression("x >= 1 ? 1 : 0")(1, 0), 1.0);
    EXPECT_DOUBLE_EQ(Expression("x == y ? 1 : 0")(2, 2), 1.0);
    EXPECT_DOUBLE_EQ(Expression("sqrt(x) + abs(y)")(4, -3), 5.0);
    EXPECT_NEAR(Expression("log(x)")(std::exp(2.0), 0), 2.0, 1e-15);  // natural logarithm
    EXPECT_NEAR(Expression("exp(x)")(1, 0), std::exp(1.0), 1e-15);
    EXPECT_NEAR(Expression("sin(x) + cos(y) + tan(x)")(0.3, 0.2), std::sin(0.3) + std::cos(0.2) + std::tan(0.3), 1e-15);
    EXPECT_DOUBLE_EQ(Expression("min(x, y) + max(x, y)")(1, 5), 6.0);
    EXPECT_DOUBLE_EQ(Expression("pow(x, 3)")(2, 0), 8.0);
    // The paper's Fig. 10 density.
    Expression fig10("x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006");
    EXPECT_NEAR(fig10(0.3, 0.4), 0.1 * 0.5 + 0.007, 1e-15);
    // Copies evaluate independently.
    Expression copy = fig10;
    EXPECT_EQ(copy(0.3, 0.4), fig10(0.3, 0.4));
}

TEST(Expression, PrecedenceAndAssociativity) {
    // Unary minus binds less tightly than ^, which is right associative (the conventions of
    // muParser, which meshd used before it had its own compiler).
    EXPECT_DOUBLE_EQ(Expression("-x^2")(3, 0), -9.0);
    EXPECT_DOUBLE_EQ(Expression("-2^2")(0, 0), -4.0);
    EXPECT_DOUBLE_EQ(Expression("2^3^2")(0, 0), 512.0);
    EXPECT_DOUBLE_EQ(Expression("2^-1")(0, 0), 0.5);
    EXPECT_DOUBLE_EQ(Expression("2*-3")(0, 0), -6.0);
    EXPECT_DOUBLE_EQ(Expression("-x*-y")(2, 3), 6.0);
    EXPECT_DOUBLE_EQ(Expression("x - y - 1")(5, 1), 3.0);
    EXPECT_DOUBLE_EQ(Expression("x / y / 2")(8, 2), 2.0);
    EXPECT_DOUBLE_EQ(Expression("2 - x")(5, 0), -3.0);
    EXPECT_DOUBLE_EQ(Expression("2 / x")(4, 0), 0.5);
    EXPECT_DOUBLE_EQ(Expression("1 + 2 > 2")(0, 0), 1.0);
    EXPECT_DOUBLE_EQ(Expression("3 > 2 == 1")(0, 0), 1.0);
    EXPECT_DOUBLE_EQ(Expression("x && 0 || 1")(1, 0), 1.0);
    EXPECT_DOUBLE_EQ(Expression("x > 1 ? 2 : 3 + 4")(0, 0), 7.0);
    // Nested conditionals associate to the right.
    const Expression steps("x < 1 ? 1 : x < 3 ? 2 : 3");
    EXPECT_EQ(steps(0, 0), 1.0);
    EXPECT_EQ(steps(2, 0), 2.0);
    EXPECT_EQ(steps(5, 0), 3.0);
    // The branch not taken is not evaluated into the result, even when it is not finite.
    EXPECT_EQ(Expression("x > 0 ? x : sqrt(x)")(4, 0), 4.0);
    EXPECT_EQ(Expression("x != 0 ? 1 / x : 5")(0, 0), 5.0);
}

TEST(Expression, FunctionsConstantsAndNumbers) {
    EXPECT_DOUBLE_EQ(Expression("min(x, y, 1)")(2, 3), 1.0);
    EXPECT_DOUBLE_EQ(Expression("max(x, y, 1)")(2, 3), 3.0);
    EXPECT_DOUBLE_EQ(Expression("sum(x, y, 1) * 3")(2, 3), 18.0);
    EXPECT_DOUBLE_EQ(Expression("avg(x, y)")(2, 3), 2.5);
    EXPECT_DOUBLE_EQ(Expression("atan2(1, 1)")(0, 0), std::numbers::pi / 4);
    EXPECT_DOUBLE_EQ(Expression("sign(x) + sign(y) + sign(0)")(-2, 3), 0.0);
    EXPECT_DOUBLE_EQ(Expression("floor(x) + ceil(y) + rint(2.6)")(1.5, 1.5), 6.0);
    EXPECT_NEAR(Expression("ln(x) + log10(100) + log2(8)")(std::exp(1.0), 0), 6.0, 1e-15);
    EXPECT_NEAR(Expression("asin(1) + acos(1) + atan(1)")(0, 0), std::numbers::pi * 0.75, 1e-15);
    EXPECT_NEAR(Expression("cosh(x)^2 - sinh(x)^2 + tanh(0)")(0.7, 0), 1.0, 1e-14);
    EXPECT_DOUBLE_EQ(Expression("_pi * _e")(0, 0), std::numbers::pi * std::numbers::e);
    EXPECT_DOUBLE_EQ(Expression("1e-3 * x + 2.5E2 + .5")(1000, 0), 251.5);
    // Folded constants give the same value as evaluated ones.
    EXPECT_EQ(Expression("sqrt(2) * x")(3, 0), std::sqrt(2.0) * 3);
    EXPECT_EQ(Expression("(1 + 2) * (x + 0.5)")(1, 0), 4.5);
    EXPECT_EQ(Expression("  x  ")(7, 0), 7.0);
}

TEST(Expression, SharedBetweenThreads) {
    const Expression e("0.1*sqrt((x-0.5)^2+y^2)+0.007");
    std::vector<double> out(2);
    std::vector<std::thread> threads;
    for (int k = 0; k < 2; ++k)
        threads.emplace_back([&, k] {
            double sum = 0;
            for (int i = 0; i < 100000; ++i) sum += e(i * 1e-5 * (k + 1), 0.25);
            out[static_cast<size_t>(k)] = sum;
        });
    for (auto& t : threads) t.join();
    double expect0 = 0, expect1 = 0;
    for (int i = 0; i < 100000; ++i) {
        expect0 += e(i * 1e-5, 0.25);
        expect1 += e(i * 2e-5, 0.25);
    }
    EXPECT_EQ(out[0], expect0);
    EXPECT_EQ(out[1], expect1);
}

// Expression::evaluate gives each point of a batch what operator() gives it, to the bit:
// conditionals (both branches computed, one kept; a NaN condition takes the first, as the
// one-point machine's jump does), every operator and function, values that are infinite or
// NaN, counts that are not a multiple of the batch. A chain of conditionals too deep for the
// batch stack runs point by point.
TEST(Expression, BatchesGiveEachPointItsOwnValue) {
    std::string chain = "x";
    for (int i = 40; i >= 1; --i) chain = "x < " + std::to_string(i * 0.05) + " ? " + std::to_string(i) + " : (" + chain + ")";
    const std::vector<std::string> texts{
        "(x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006) * 0.1",
        "sqrt(x - 0.3) ? 1 : 2",  // a NaN condition on the left of 0.3
        "x > y ? (y > 0.2 ? x*y : x/y) : -(x - y)^3",
        "1 / (x - 0.5) + log(y) - exp(x) * sin(3*y) / cos(x)",
        "min(x, y, 0.3) + max(x, 0.1) + avg(x, y, 1) + sum(x, y) + pow(x, y) + atan2(y, x - 0.5)",
        "x <= y && y >= 0.25 || x == y || x != 0.75 ? abs(x - y) + floor(7*x) + sign(y - 0.5) : tanh(x)",
        "2 - x / 3 - 4 / (y + 1) + 0.5 - -x",
        chain,
    };
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    std::vector<double> x, y;
    for (int i = 0; i < 1000; ++i) {
        x.push_back(u(rng));
        y.push_back(u(rng));
    }
    x[10] = 0.5;  // 1 / 0
    y[11] = 0.0;  // log 0
    for (const std::string& text : texts) {
        SCOPED_TRACE(text);
        const Expression e(text);
        for (const size_t n : {size_t{1}, size_t{31}, size_t{32}, size_t{33}, size_t{1000}}) {
            std::vector<double> out(n, -1.0);
            e.evaluate(x.data(), y.data(), out.data(), n);
            for (size_t i = 0; i < n; ++i)
                ASSERT_EQ(std::bit_cast<std::uint64_t>(out[i]), std::bit_cast<std::uint64_t>(e(x[i], y[i])))
                    << "point " << i << " of " << n << ": " << out[i] << " against " << e(x[i], y[i]);
        }
    }
}

// min, max and abs run without a call into the maths library, with a constant second
// operand riding in the instruction; their values stay std::fmin's, std::fmax's and
// std::fabs's to the bit, one point at a time and in batches: NaNs (the number wins; two
// give a NaN), infinities, tiny and huge values. Of two zeros either sign is IEEE 754's
// fmin and fmax (GCC's inline expansion and glibc's call differ), so only the value is
// compared there.
TEST(Expression, MinMaxAndAbsAreTheLibrarysToTheBit) {
    const double inf = HUGE_VAL, nan = std::nan("");
    const std::vector<double> values{0.0, -0.0, 1.5, -2.25, inf, -inf, nan, 1e-300, -7e300};
    struct Case {
        const char* text;
        double (*expected)(double, double);
    };
    const Case cases[] = {
        {"min(x, y)", [](double a, double b) { return std::fmin(a, b); }},
        {"max(x, y)", [](double a, double b) { return std::fmax(a, b); }},
        {"min(x, 0)", [](double a, double) { return std::fmin(a, 0.0); }},
        {"max(x, -0)", [](double a, double) { return std::fmax(a, -0.0); }},
        {"max(0, x)", [](double a, double) { return std::fmax(0.0, a); }},
        {"min(-0, y)", [](double, double b) { return std::fmin(-0.0, b); }},
        {"abs(x)", [](double a, double) { return std::fabs(a); }},
        {"min(abs(x), y, 1.5)", [](double a, double b) { return std::fmin(std::fmin(std::fabs(a), b), 1.5); }},
    };
    std::vector<double> xs, ys;
    for (const double a : values)
        for (const double b : values) {
            xs.push_back(a);
            ys.push_back(b);
        }
    auto same = [](double got, double want) {
        if (std::isnan(want)) return std::isnan(got);
        if (want == 0.0) return got == 0.0;
        return std::bit_cast<std::uint64_t>(got) == std::bit_cast<std::uint64_t>(want);
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        const Expression e(c.text);
        std::vector<double> out(xs.size());
        e.evaluate(xs.data(), ys.data(), out.data(), xs.size());
        for (size_t i = 0; i < xs.size(); ++i) {
            const double want = c.expected(xs[i], ys[i]);
            EXPECT_TRUE(same(e(xs[i], ys[i]), want)) << xs[i] << ", " << ys[i] << ": " << e(xs[i], ys[i]);
            EXPECT_TRUE(same(out[i], want)) << xs[i] << ", " << ys[i] << " (batch): " << out[i];
        }
    }
}

TEST(Expression, SyntaxErrorsAreGeometryErrors) {
    for (const char* bad : {"x +", "sqrt(", "foo(x)", "z * 2", "", "   ", "x ? 1", "1 +* 2", "1.2.3", "x y", "(x",
                            "x)", "sqrt(x, y)", "pow(x)", "min()", "sqrt", "x = 1", "!x", "x ^", "2 ** 3"}) {
        try {
            Expression e(bad);
            ADD_FAILURE() << "accepted " << bad;
        } catch (const GeometryError& e) {
            EXPECT_EQ(e.kind(), GeometryErrorKind::DensityExpression) << bad;
        }
    }
}

std::string parse_error(const std::string& text) {
    try {
        Expression e(text);
    } catch (const GeometryError& e) {
        return e.what();
    }
    return "accepted";
}

TEST(Expression, ErrorsSayWhatAndWhere) {
    EXPECT_NE(parse_error("0.1 * z").find("unknown name 'z'"), std::string::npos) << parse_error("0.1 * z");
    EXPECT_NE(parse_error("0.1 * z").find("position 6"), std::string::npos);
    EXPECT_NE(parse_error("foo(x)").find("unknown name 'foo'"), std::string::npos);
    EXPECT_NE(parse_error("sqrt(x, y)").find("sqrt takes 1 argument, not 2"), std::string::npos) << parse_error("sqrt(x, y)");
    EXPECT_NE(parse_error("(x + 1").find("expected ')' at the end"), std::string::npos) << parse_error("(x + 1");
    EXPECT_NE(parse_error("x + 1)").find("unexpected ')' at position 5"), std::string::npos) << parse_error("x + 1)");
    EXPECT_NE(parse_error("").find("empty"), std::string::npos);
    // Nesting and length are bounded, so that a hostile request cannot exhaust the stack.
    EXPECT_NE(parse_error(std::string(5000, '(') + "x" + std::string(5000, ')')).find("nesting deeper"), std::string::npos);
    EXPECT_NE(parse_error(std::string(5000, '-') + "x").find("nesting deeper"), std::string::npos);
    std::string long_sum = "x";
    for (int i = 0; i < 20000; ++i) long_sum += "+x";
    EXPECT_NE(parse_error(long_sum).find("terms"), std::string::npos);
    // A deep right operand chain needs many intermediate values.
    std::string deep = "x";
    for (int i = 0; i < 40; ++i) deep = "x*(y+" + deep + ")";
    EXPECT_NE(parse_error(deep).find("intermediate values"), std::string::npos) << parse_error(deep).substr(0, 200);
}

namespace {

GeometryError size_field_error(const DensitySpec& spec, const Domain& d) {
    try {
        SizeField f(spec, d);
        // Evaluate on every curve's start so that value errors surface too.
        for (CurveId c = 0; c < d.curves().size(); ++c) f.on_curve(c, d.points()[d.curves()[c].from].position);
        if (!f.interpolates()) f.interior({0.5, 0.5});
    } catch (const GeometryError& e) {
        return e;
    }
    ADD_FAILURE() << "accepted";
    return GeometryError(GeometryErrorKind::BadParameter, "none");
}

}  // namespace

TEST(SizeField, PerCurveByNameBeatsTagBeatsSize) {
    const Domain d = build_domain(unit_square());
    DensitySpec spec;
    spec.size = 0.1;
    spec.curves = {{"wall", 0.05}, {"top", std::string("0.02 + 0*x")}};
    SizeField f(spec, d);
    EXPECT_DOUBLE_EQ(f.on_curve(0, {0.5, 0}), 0.05);  // bottom: tag wall
    EXPECT_DOUBLE_EQ(f.on_curve(2, {0.5, 1}), 0.02);  // top: its own name
    EXPECT_DOUBLE_EQ(f.on_curve(1, {1, 0.5}), 0.1);   // right: size
    EXPECT_DOUBLE_EQ(f.interior({0.5, 0.5}), 0.1);
    EXPECT_FALSE(f.interpolates());
}

TEST(SizeField, ClampsApply) {
    const Domain d = build_domain(unit_square());
    DensitySpec spec;
    spec.size = std::string("x");
    spec.min = 0.2;
    spec.max = 0.5;
    SizeField f(spec, d);
    EXPECT_DOUBLE_EQ(f.interior({0.1, 0.5}), 0.2);
    EXPECT_DOUBLE_EQ(f.interior({0.3, 0.5}), 0.3);
    EXPECT_DOUBLE_EQ(f.interior({0.9, 0.5}), 0.5);
}

TEST(SizeField, InvalidValuesNameThePoint) {
    const Domain d = build_domain(unit_square());
    DensitySpec spec;
    spec.size = std::string("x - 0.5");  // negative on the left half
    SizeField f(spec, d);
    try {
        f.interior({0.25, 0.5});
        ADD_FAILURE();
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::DensityInvalid);
        ASSERT_NE(e.where(), nullptr);
        EXPECT_EQ(e.where()->x, 0.25);
        EXPECT_EQ(e.subjects()[0].kind, Subject::Kind::Density);
        EXPECT_EQ(e.subjects()[0].name, "size");
    }
    spec.size = std::string("1 / (x - 0.5)");  // division by zero at x = 0.5: infinite
    SizeField g(spec, d);
    EXPECT_THROW(g.interior({0.5, 0.5}), GeometryError);
    spec.size = std::string("sqrt(x - 2)");  // NaN
    SizeField h(spec, d);
    EXPECT_THROW(h.interior({0.5, 0.5}), GeometryError);
    spec.size = 0.0;
    EXPECT_EQ(size_field_error(spec, d).kind(), GeometryErrorKind::DensityInvalid);
    spec.size = -1.0;
    EXPECT_EQ(size_field_error(spec, d).kind(), GeometryErrorKind::DensityInvalid);
    spec.size = NAN;
    EXPECT_EQ(size_field_error(spec, d).kind(), GeometryErrorKind::DensityInvalid);
}

// The field over an array of points (the figures' batches) gives each point interior()'s
// value to the bit, clamps and the gradation's cones included, and refuses an invalid value
// as interior() does, naming the first point that has one.
TEST(SizeField, AnArrayOfPointsGetsEachPointsOwnSize) {
    const Domain d = build_domain(unit_square());
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec2> at;
    for (int i = 0; i < 700; ++i) at.push_back({u(rng), u(rng)});
    for (const bool graded : {false, true}) {
        DensitySpec spec;
        spec.size = std::string("x < 0.5 ? 0.01 + 0.3*sqrt(x^2+y^2) : 0.2*y + 0.005");
        spec.min = 0.02;
        spec.max = 0.25;
        if (graded) spec.gradation = 1.2;
        SizeField f(spec, d);
        if (graded) {
            const Discretisation b = discretise_boundary(d, f);
            set_gradation_sources(f, b, triangulate_boundary(b), 1000000);
            ASSERT_TRUE(f.gradation());
        }
        std::vector<double> out(at.size());
        f.interior(at.data(), at.size(), out.data());
        size_t graded_below = 0;
        for (size_t i = 0; i < at.size(); ++i) {
            ASSERT_EQ(std::bit_cast<std::uint64_t>(out[i]), std::bit_cast<std::uint64_t>(f.interior(at[i]))) << i;
            const Vec2 p = at[i];
            const double raw = std::clamp(p.x < 0.5 ? 0.01 + 0.3 * std::sqrt(p.x * p.x + p.y * p.y) : 0.2 * p.y + 0.005, 0.02, 0.25);
            if (graded) {
                graded_below += out[i] < raw ? 1 : 0;
            } else {
                EXPECT_NEAR(out[i], raw, 1e-15);
            }
        }
        if (graded) {
            EXPECT_GT(graded_below, 0u);  // the cones were applied
        }
    }
    DensitySpec bad;
    bad.size = std::string("x - 0.5");
    SizeField g(bad, d);
    const std::vector<Vec2> some{{0.75, 0.5}, {0.6, 0.1}, {0.25, 0.5}, {0.1, 0.5}};
    std::vector<double> out(some.size());
    try {
        g.interior(some.data(), some.size(), out.data());
        ADD_FAILURE() << "a negative size accepted";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::DensityInvalid);
        ASSERT_NE(e.where(), nullptr);
        EXPECT_EQ(e.where()->x, 0.25);
    }
}

TEST(SizeField, SpecErrors) {
    const Domain d = build_domain(unit_square());
    DensitySpec spec;
    spec.size = std::string("x +");
    auto e = size_field_error(spec, d);
    EXPECT_EQ(e.kind(), GeometryErrorKind::DensityExpression);
    EXPECT_EQ(e.subjects()[0].name, "size");

    spec = {};
    spec.curves = {{"wall", 0.1}};
    e = size_field_error(spec, d);  // right and left have no density
    EXPECT_EQ(e.kind(), GeometryErrorKind::DensityMissing);

    spec = {};
    spec.size = 0.1;
    spec.curves = {{"nonexistent", 0.1}};
    e = size_field_error(spec, d);
    EXPECT_EQ(e.kind(), GeometryErrorKind::DensityMissing);
    EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"nonexistent"}));

    spec = {};
    spec.size = 0.1;
    spec.gradation = 0.9;
    EXPECT_EQ(size_field_error(spec, d).kind(), GeometryErrorKind::DensityInvalid);
    spec.gradation = std::nullopt;
    spec.min = 0.5;
    spec.max = 0.1;
    EXPECT_EQ(size_field_error(spec, d).kind(), GeometryErrorKind::DensityInvalid);
}

namespace {
// n sources of eq. 6.1 in the unit square with values in [0.01, 1.01).
std::pair<std::vector<Vec2>, std::vector<double>> random_sources(size_t n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec2> a(n);
    std::vector<double> len(n);
    for (size_t i = 0; i < n; ++i) {
        a[i] = {u(rng), u(rng)};
        len[i] = 0.01 + u(rng);
    }
    return {a, len};
}

// The paper's Fig. 9 setting (with naca_in_circle): NACA 0012 in a far field, boundary
// densities per loop, eq. 6.1 inside.
DensitySpec fig9_density() {
    DensitySpec spec;
    spec.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                   {"wing", std::string("0.05*sqrt((x+0.01)^2+y^2)")}};
    spec.min = 1e-3;
    return spec;
}

// eq. 6.1's sources of a boundary: each segment's start and length.
std::pair<std::vector<Vec2>, std::vector<double>> sources_of(const Discretisation& disc) {
    std::vector<Vec2> starts;
    std::vector<double> lengths;
    for (const auto& s : disc.segments) {
        starts.push_back(disc.point(s.a));
        lengths.push_back(distance(disc.point(s.a), disc.point(s.b)));
    }
    return {starts, lengths};
}
}  // namespace

// The field over an array of points under eq. 6.1 with the interior cap of the curves'
// agreement (Fig. 9), queries in runs as a mesh's edges come: the whole batch's eq. 6.1
// first, then the caps (size_field.cpp); each point's value as a field made alike gives it
// one query at a time, to the bit.
TEST(SizeField, AnArrayOfPointsUnderEq61GetsEachPointsOwnSize) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Domain fig9 = build_domain(naca_in_circle("0012", 20.0));
    SizeField one(fig9_density(), fig9), batched(fig9_density(), fig9), uncapped(fig9_density(), fig9);
    for (SizeField* field : {&one, &batched, &uncapped}) {
        Discretisation b = discretise_boundary(fig9, *field);
        set_interpolation_sources(*field, b);
        ASSERT_GT(agree_with_interior(fig9, *field, BoundaryOptions{}, b).rounds, 0);
    }
    uncapped.restore_interior_cap(nullptr);  // the same sources, no cones inside
    std::vector<Vec2> run;
    Vec2 p{0.5, 0.1};
    for (int k = 0; k < 5000; ++k) {
        // Runs by the leading edge, where the cones of the airfoil's fine points come below
        // eq. 6.1 in places (elsewhere Fig. 9's cap hardly ever binds), and a fifth of them
        // out in the far field.
        if (k % 250 == 0)
            p = k % 1250 == 0 ? Vec2{-8.0 + 16.0 * u(rng), -8.0 + 16.0 * u(rng)}
                              : Vec2{0.05 + 0.2 * u(rng), -0.08 + 0.16 * u(rng)};
        p += Vec2{0.002 * (u(rng) - 0.5), 0.002 * (u(rng) - 0.5)};
        run.push_back(p);
    }
    std::vector<double> out(run.size());
    batched.interior(run.data(), run.size(), out.data());
    size_t capped = 0;
    for (size_t i = 0; i < run.size(); ++i) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(out[i]), std::bit_cast<std::uint64_t>(one.interior(run[i]))) << i;
        capped += out[i] < uncapped.interior(run[i]) ? 1 : 0;
    }
    // The cones were applied, and not everywhere.
    EXPECT_GT(capped, run.size() / 20);
    EXPECT_LT(capped, run.size());
}

// Up to kDirectSources the sum is the formula summed in another order: equal to the
// one-term-at-a-time sum but for rounding, wherever the point; above it, the treecode. Up to
// kCellSources the field is that sum.
TEST(InverseDistance, FewSourcesAreSummedTermByTerm) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t n : {size_t{1}, size_t{3}, size_t{4}, size_t{7}, kCellSources, size_t{150}, kDirectSources, kDirectSources + 1}) {
        const auto [a, len] = random_sources(n, rng);
        const InverseDistanceField field(a, len);
        double worst = 0.0;
        for (int k = 0; k < 500; ++k) {
            const Vec2 p{3.0 * u(rng) - 1.0, 3.0 * u(rng) - 1.0};
            worst = std::fmax(worst, std::fabs(field.summed(p) - field.exact(p)) / field.exact(p));
            if (n <= kCellSources) {
                ASSERT_EQ(field(p), field.summed(p)) << n << " sources";
            }
        }
        // Term by term the weights 1/d are single-precision: a squared distance rounded to
        // float, its square root and the reciprocal each within half a float ulp (2^-24),
        // so each weight within 3 * 2^-24 (1.8e-7) and the ratio of the two sums of positive
        // terms within twice that.
        if (n <= kDirectSources)
            EXPECT_LE(worst, 4e-7) << n << " sources";
        else
            EXPECT_GT(worst, 1e-6) << n << " sources: the treecode";
        for (size_t i = 0; i < n; i += 1 + n / 7) {
            EXPECT_EQ(field(a[i]), len[i]) << n << " sources, at source " << i;
            EXPECT_EQ(field.summed(a[i]), len[i]) << n << " sources, at source " << i;
        }
        // Squared distances beyond the floats' range are summed in double.
        if (n <= kDirectSources) {
            for (const Vec2 far : {Vec2{1e20, 0.0}, Vec2{-3e19, 2e19}})
                EXPECT_NEAR(field(far) / field.exact(far), 1.0, 1e-13) << n << " sources, far away";
        }
    }
}

// The sums on 256-bit registers (where the processor has AVX) do the 128-bit and the scalar
// sums' operations lane for lane, so fields and meshes do not depend on the machine: the same
// value to the bit at every query, the same mesh point for point. Two fields, each of whose
// query cells (made as queries come) are made with the sums it is asked with: the near sums
// and the far polynomials of the cells both compared.
TEST(InverseDistance, WideAndNarrowSumsAgreeToTheBit) {
    const bool wide = detail::wide_sums(true);
    std::printf("[ info ] 256-bit sums %s on this processor\n", wide ? "in use" : "not available");
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t n : {size_t{4}, size_t{5}, size_t{7}, size_t{150}, size_t{1001}, kDirectSources}) {
        const auto [a, len] = random_sources(n, rng);
        const InverseDistanceField narrow_field(a, len), wide_field(a, len);
        // And with room for few copies of the leaves' near sources: the leaves made later sum
        // their near sources node by node.
        const InverseDistanceField narrow_few(a, len, 1e-3, 500), wide_few(a, len, 1e-3, 500);
        for (int k = 0; k < 2000; ++k) {
            // Anywhere around the sources, a hair from one of them, or on one.
            const Vec2 p = k % 3 == 0   ? Vec2{3.0 * u(rng) - 1.0, 3.0 * u(rng) - 1.0}
                           : k % 3 == 1 ? a[k % n] + Vec2{1e-9 * u(rng), -1e-9 * u(rng)}
                                        : a[k % n];
            detail::wide_sums(false);
            const double narrow = narrow_field(p), narrow_node_by_node = narrow_few(p);
            detail::wide_sums(true);
            ASSERT_EQ(std::bit_cast<std::uint64_t>(wide_field(p)), std::bit_cast<std::uint64_t>(narrow))
                << n << " sources, query " << k;
            ASSERT_EQ(std::bit_cast<std::uint64_t>(wide_few(p)), std::bit_cast<std::uint64_t>(narrow_node_by_node))
                << n << " sources, query " << k << ", few copies";
        }
    }
    // A whole mesh with eq. 6.1 inside (the paper's Fig. 9 setting).
    const Domain d = build_domain(naca_in_circle("0012", 20.0));
    const DensitySpec spec = fig9_density();
    detail::wide_sums(false);
    const Mesh narrow = generate_mesh(d, spec).mesh;
    detail::wide_sums(true);
    const Mesh wider = generate_mesh(d, spec).mesh;
    ASSERT_EQ(wider.point_count(), narrow.point_count());
    ASSERT_GT(narrow.point_count(), 1000u);
    for (VertexId v = 0; v < narrow.point_count(); ++v) ASSERT_EQ(wider.point(v), narrow.point(v)) << "point " << v;
    ASSERT_EQ(wider.triangles.size(), narrow.triangles.size());
    for (size_t t = 0; t < narrow.triangles.size(); ++t) ASSERT_EQ(wider.triangles[t].v, narrow.triangles[t].v);
}

TEST(InverseDistance, TreecodeMeetsItsBoundAgainstTheExactFormula) {
    // The paper's Fig. 9 setting: NACA 0012 in a far field, boundary densities per loop.
    const Domain d = build_domain(naca_in_circle("0012", 20.0));
    const DensitySpec spec = fig9_density();
    SizeField f(spec, d);
    ASSERT_TRUE(f.interpolates());
    const Discretisation disc = discretise_boundary(d, f);
    const auto [starts, lengths] = sources_of(disc);
    for (double tol : {1e-2, 1e-3, 1e-4}) {
        InverseDistanceField field(starts, lengths, tol);
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> r(0.0, 1.0);
        double worst = 0.0;
        for (int k = 0; k < 3000; ++k) {
            // Half the probes near the airfoil, half anywhere in the far field.
            Vec2 p;
            if (k % 2) {
                p = {-0.1 + 1.2 * r(rng), -0.2 + 0.4 * r(rng)};
            } else {
                const double rad = 20 * std::sqrt(r(rng)), ang = 2 * std::numbers::pi * r(rng);
                p = {0.5 + rad * std::cos(ang), rad * std::sin(ang)};
            }
            const double exact = field.exact(p);
            worst = std::fmax(worst, std::fabs(field.treecode(p) - exact) / exact);
        }
        EXPECT_LE(worst, tol) << "tolerance " << tol;
        EXPECT_GT(worst, 0.0);  // the approximation is really used
    }
    // At a boundary vertex the formula gives that segment's length, by either path.
    InverseDistanceField field(starts, lengths);
    EXPECT_DOUBLE_EQ(field(starts[10]), lengths[10]);
    EXPECT_DOUBLE_EQ(field.treecode(starts[10]), lengths[10]);
    EXPECT_DOUBLE_EQ(field(starts.back()), lengths.back());  // past the last full pair of pairs
    // Through the size field, after the boundary is known.
    set_interpolation_sources(f, disc);
    const double mid = f.interior({0.5, 0.5});
    EXPECT_GT(mid, 0.0);
    EXPECT_NEAR(mid, field.exact({0.5, 0.5}), 1e-3 * mid);
}

// The cells (inverse_distance.hpp) hold their bound: Fig. 9's boundary and 4,000 random sources,
// probed anywhere, a hair from a source and on one, at several tolerances. Their error comes
// from the far sources' cubic polynomials alone, so it falls with the tolerance.
TEST(InverseDistance, CellsMeetTheirBoundAgainstTheExactFormula) {
    const Domain d = build_domain(naca_in_circle("0012", 20.0));
    const DensitySpec spec = fig9_density();
    SizeField f(spec, d);
    const Discretisation disc = discretise_boundary(d, f);
    const auto [fig9, fig9_lengths] = sources_of(disc);
    ASSERT_GT(fig9.size(), kCellSources);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto [square, square_lengths] = random_sources(4000, rng);
    struct Case {
        const std::vector<Vec2>* a;
        const std::vector<double>* len;
        Vec2 lo, hi;  // where to probe
    };
    for (const Case& c : {Case{&fig9, &fig9_lengths, {-20.0, -20.0}, {21.0, 20.0}},
                          Case{&fig9, &fig9_lengths, {-0.1, -0.2}, {1.1, 0.2}},
                          Case{&square, &square_lengths, {-1.0, -1.0}, {2.0, 2.0}}}) {
        double last = HUGE_VAL;
        for (double tol : {1e-2, 1e-3, 1e-4, 1e-6}) {
            const InverseDistanceField field(*c.a, *c.len, tol);
            // The same cells with room for few copies of the leaves' near sources: most
            // leaves sum theirs node by node, in another order, so the values agree to the
            // rounding of the sums' order (the float weights are the same).
            const InverseDistanceField few(*c.a, *c.len, tol, 2000);
            double worst = 0.0, apart = 0.0;
            for (int k = 0; k < 6000; ++k) {
                const size_t i = static_cast<size_t>(k) % c.a->size();
                Vec2 p = k % 3 == 0 ? Vec2{c.lo.x + (c.hi.x - c.lo.x) * u(rng), c.lo.y + (c.hi.y - c.lo.y) * u(rng)}
                                    : (*c.a)[i] + Vec2{1e-9 * (u(rng) - 0.5), 1e-9 * (u(rng) - 0.5)};
                if (k % 30 == 1) {
                    ASSERT_EQ(field((*c.a)[i]), (*c.len)[i]) << "on source " << i;
                    continue;
                }
                const double exact = field.exact(p), value = field(p);
                worst = std::fmax(worst, std::fabs(value - exact) / exact);
                apart = std::fmax(apart, std::fabs(few(p) - value) / value);
            }
            EXPECT_LE(apart, 1e-13) << c.a->size() << " sources, tolerance " << tol;
            // Both kinds of leaf were asked, and the copies stayed within their room.
            EXPECT_GT(few.packed_sources(), 0u);
            EXPECT_LE(few.packed_sources(), 2000u);
            EXPECT_GT(field.packed_sources(), few.packed_sources());
            std::printf("[ cells ] %zu sources, tolerance %g: worst relative error %.3g\n", c.a->size(), tol, worst);
            EXPECT_LE(worst, tol + 4e-7) << c.a->size() << " sources, tolerance " << tol;  // + the near sums' floats
            EXPECT_GT(worst, 1e-9) << "the polynomials are really used";
            EXPECT_LT(worst, last) << "a smaller tolerance, a smaller error";
            last = worst;
        }
    }
    // Sources that coincide cannot be parted into cells: the cells stop, and the value holds.
    std::vector<Vec2> heap(200, Vec2{0.25, 0.75});
    std::vector<double> heap_lengths(200, 0.5);
    for (size_t i = 0; i < 100; ++i) {
        heap.push_back({u(rng), u(rng)});
        heap_lengths.push_back(0.01 + u(rng));
    }
    const InverseDistanceField field(heap, heap_lengths);
    for (int k = 0; k < 500; ++k) {
        const Vec2 p = k % 2 ? Vec2{u(rng), u(rng)} : Vec2{0.25 + 1e-12 * u(rng), 0.75};
        EXPECT_NEAR(field(p), field.exact(p), 1e-3 * field.exact(p)) << k;
    }
    EXPECT_EQ(field(Vec2{0.25, 0.75}), 0.5);
}

// Found by fuzz/fuzz_request (timeout acae571a): a size of 9e8 on half of a domain 12 wide
// (a typo in an expression) hung the interior stage, whose searches around a candidate point
// span cells in proportion to its size. No edge can be longer than the domain: sizes are
// capped at its extent (the diagonal of its box), whatever density.max says, and the mesh
// is made at once.
TEST(SizeField, SizesAreCappedAtTheDomainsExtent) {
    const Domain dom = build_domain(unit_square());
    DensitySpec spec;
    spec.size = std::string("x < 0.5 ? 0.05 : 9e8");
    spec.max = 1e12;
    const SizeField rho(spec, dom);
    EXPECT_DOUBLE_EQ(rho.interior({0.75, 0.5}), std::sqrt(2.0));
    EXPECT_DOUBLE_EQ(rho.interior({0.25, 0.5}), 0.05);
    const auto v = check_mesh(generate_mesh(dom, spec).mesh);
    for (const auto& s : v) ADD_FAILURE() << s;
}

// The gradation envelope min_i (h_i + (g - 1) |x - s_i|) capped at an upper bound, against the
// formula summed cone by cone. The field answers a query near the last one from that search's
// bound without searching again; the queries here come as the advancing front's do, in runs of
// small steps (and now and then a jump), with bounds below, near and above the envelope, so
// that both the answers without a search and the searches are checked, to the bit. Both
// trees (sources along curves: a k-d tree searched wide; over the domain: a tree over the
// Hilbert order searched up to the bound).
TEST(Gradation, TheEnvelopeAnswersEveryQueryAsTheFormulaDoes) {
    std::mt19937_64 gen(20261204);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    // In the k-d tree 302 and 301 sources make leaves of 18 and 19, 1,000 of 31 and 32; in the
    // other all leaves are of 32 but the last, of 14, 8 and 13 (the leaves are summed four a
    // step: 14 and 13 end in part of one).
    for (const auto spread : {GradationField::Spread::Curves, GradationField::Spread::Domain}) {
        for (const auto& [ratio, sources] : {std::pair{1.25, 302}, std::pair{1.5, 1000}, std::pair{3.0, 301}}) {
            SCOPED_TRACE(ratio);
            SCOPED_TRACE(spread == GradationField::Spread::Curves ? "curves" : "domain");
            std::vector<Vec2> at;
            std::vector<double> size;
            for (int i = 0; i < sources; ++i) {
                at.push_back({unit(gen), unit(gen)});
                size.push_back(0.001 + 0.1 * unit(gen) * unit(gen));
            }
            const GradationField cap(at, size, ratio, spread);
            auto formula = [&](Vec2 x, double upper) {
                double h = upper;
                for (size_t i = 0; i < at.size(); ++i) h = std::fmin(h, size[i] + (ratio - 1.0) * distance(x, at[i]));
                return h;
            };
            Vec2 x{0.5, 0.5};
            size_t below = 0;
            for (int q = 0; q < 20000; ++q) {
                if (unit(gen) < 0.01) x = {1.4 * unit(gen) - 0.2, 1.4 * unit(gen) - 0.2};
                else x = x + Vec2{0.02 * (unit(gen) - 0.5), 0.02 * (unit(gen) - 0.5)};
                const double envelope = formula(x, HUGE_VAL);
                const double upper = envelope * (0.2 + 1.2 * unit(gen));
                below += upper < envelope;
                ASSERT_EQ(cap.capped(x, upper), formula(x, upper)) << "query " << q << " at " << x.x << ", " << x.y;
            }
            EXPECT_GT(below, 10000u);
            EXPECT_EQ(cap(Vec2{0.3, 0.7}), formula({0.3, 0.7}, HUGE_VAL));
        }
    }
}

// A leaf's last step of four cones reads past its end: there the entries stand at the origin,
// sizes at infinity, so that they never win. Every count of sources up to two steps, all
// round the origin, queried there and beside them (a zero size in those entries would answer
// 0 at the origin, where the sources' cones give 0.05 + (ratio - 1) 0.1 and more).
TEST(Gradation, ALeafsLastStepReadsNothingPastItsEnd) {
    for (const auto spread : {GradationField::Spread::Curves, GradationField::Spread::Domain}) {
        for (int count = 1; count <= 8; ++count) {
            SCOPED_TRACE(count);
            std::vector<Vec2> at;
            std::vector<double> size;
            for (int i = 0; i < count; ++i) {
                const double a = 2.0 * std::numbers::pi * i / count;
                at.push_back({0.1 * std::cos(a), 0.1 * std::sin(a)});
                size.push_back(0.05 + 0.01 * i);
            }
            const GradationField cap(at, size, 1.25, spread);
            for (const Vec2 x : {Vec2{0.0, 0.0}, Vec2{0.01, -0.02}, Vec2{-0.05, 0.03}, Vec2{0.2, 0.2}}) {
                double h = HUGE_VAL;
                for (size_t i = 0; i < at.size(); ++i) h = std::fmin(h, size[i] + 0.25 * distance(x, at[i]));
                EXPECT_EQ(cap(x), h) << x.x << ", " << x.y;
                EXPECT_EQ(cap.capped(x, 2.0 * h), h) << x.x << ", " << x.y;
            }
        }
    }
}

// density.min clamps the sizes the request gives, not those the geometry forces: a cap from a
// curve point spaced finer than min (a blunt trailing edge's short base, a layer's fan) takes
// the field below min around it, growing at the cap's ratio, down to the default floor (a
// millionth of the extent) and no further. Away from the cap the given size stays clamped.
TEST(SizeField, CapsFromTheGeometryGoBelowTheMinimum) {
    const Domain d = build_domain(unit_square());  // extent sqrt 2
    DensitySpec spec;
    spec.size = 0.01;
    spec.min = 0.05;
    SizeField f(spec, d);
    EXPECT_DOUBLE_EQ(f.interior({0.5, 0.5}), 0.05);
    EXPECT_DOUBLE_EQ(f.min_size(), 0.05);
    EXPECT_DOUBLE_EQ(f.least_size(), 1e-6 * std::sqrt(2.0));
    // A cap of 0.001 at the middle, growing by 1.5: 0.001 + 0.5 r.
    f.set_interior_cap({{0.5, 0.5}}, {0.001}, 1.5);
    EXPECT_NEAR(f.interior({0.5, 0.5}), 0.001, 1e-12);
    EXPECT_NEAR(f.interior({0.5, 0.52}), 0.011, 1e-12);
    EXPECT_DOUBLE_EQ(f.interior({0.5, 0.9}), 0.05);  // 0.201 under the cap: the clamp holds
    f.set_curve_cap({{0.0, 0.5}}, {0.002}, 1.5);
    EXPECT_NEAR(f.on_curve(3, {0.0, 0.5}), 0.002, 1e-12);
    EXPECT_DOUBLE_EQ(f.on_curve(3, {0.0, 0.1}), 0.05);
    // A cap below the default floor stops there.
    f.set_interior_cap({{0.5, 0.5}}, {1e-9}, 1.5);
    EXPECT_DOUBLE_EQ(f.interior({0.5, 0.5}), f.least_size());
}
