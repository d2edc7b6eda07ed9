// Airfoils from coordinate files, in the two layouts in common use:
// - Selig: a name line, then x y pairs from the trailing edge over one surface to the
//   leading edge and back over the other surface to the trailing edge;
// - Lednicer: a name line, a line with the point counts of the two surfaces, then the upper
//   surface and the lower surface, each from leading to trailing edge, in blocks usually
//   separated by blank lines.
// The parser accepts either surface first, a repeated leading-edge point and blunt trailing
// edges; it refuses text that is not an airfoil (too few points, lines that are not pairs of
// numbers inside the data, a contour that crosses itself, no leading edge between the ends).
// The contour becomes a cubic spline through the points (make_spline_through), placed by
// chord, leading edge and angle like a NACA section.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>

#include "geometry/composite.hpp"
#include "kernel/crossings.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

GeometryError bad_airfoil(const std::string& msg) {
    return GeometryError(GeometryErrorKind::BadAirfoil, msg, {Subject::curve({}, {"coordinates"})});
}

// Splits a line into numbers; false when some token is not a number.
bool parse_numbers(std::string_view line, std::vector<double>& out) {
    out.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == ',' || line[i] == '\r'))
            ++i;
        if (i >= line.size()) break;
        size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != ',' && line[j] != '\r')
            ++j;
        std::string token(line.substr(i, j - i));
        // Accept Fortran exponents (1.0D-03).
        std::replace(token.begin(), token.end(), 'D', 'E');
        std::replace(token.begin(), token.end(), 'd', 'e');
        if (!token.empty() && token[0] == '+') token.erase(0, 1);
        double v = 0.0;
        const char* first = token.data();
        const char* last = token.data() + token.size();
        auto [ptr, ec] = std::from_chars(first, last, v);
        if (ec != std::errc() || ptr != last) return false;
        out.push_back(v);
        i = j;
    }
    return true;
}

struct Line {
    std::string_view raw;
    std::vector<double> values;
    bool numeric = false;
    bool blank = false;
    int number = 0;  // 1-based line number
};

// The leading edge: the point farthest from the trailing-edge midpoint (the ends' mean).
size_t leading_edge_index(const std::vector<Vec2>& pts, double& chord) {
    const Vec2 te = 0.5 * (pts.front() + pts.back());
    size_t le = 0;
    chord = -1.0;
    for (size_t k = 0; k < pts.size(); ++k) {
        const double d = distance(te, pts[k]);
        if (d > chord) {
            chord = d;
            le = k;
        }
    }
    return le;
}

}  // namespace

AirfoilPoints parse_airfoil_dat(std::string_view text) {
    std::vector<Line> lines;
    {
        size_t pos = 0;
        int number = 0;
        while (pos <= text.size()) {
            size_t end = text.find('\n', pos);
            if (end == std::string_view::npos) end = text.size();
            std::string_view raw = text.substr(pos, end - pos);
            Line l;
            l.raw = raw;
            l.number = ++number;
            l.blank = raw.find_first_not_of(" \t\r") == std::string_view::npos;
            l.numeric = !l.blank && parse_numbers(raw, l.values);
            lines.push_back(std::move(l));
            if (end == text.size()) break;
            pos = end + 1;
        }
    }
    AirfoilPoints result;
    size_t i = 0;
    // Header: everything before the first numeric line; its first non-blank line is the name.
    while (i < lines.size() && !lines[i].numeric) {
        if (result.name.empty() && !lines[i].blank) {
            std::string_view raw = lines[i].raw;
            while (!raw.empty() && (raw.back() == '\r' || raw.back() == ' ')) raw.remove_suffix(1);
            while (!raw.empty() && raw.front() == ' ') raw.remove_prefix(1);
            result.name = std::string(raw);
        }
        ++i;
    }
    if (i == lines.size()) throw bad_airfoil("no coordinates found");

    std::vector<std::vector<Vec2>> blocks(1);
    auto take_pairs = [&](size_t from) {
        for (size_t k = from; k < lines.size(); ++k) {
            const Line& l = lines[k];
            if (l.blank) {
                if (!blocks.back().empty()) blocks.emplace_back();
                continue;
            }
            if (!l.numeric || l.values.size() != 2)
                throw bad_airfoil("line " + std::to_string(l.number) +
                                  " is not a pair of coordinates \"x y\"");
            const Vec2 p{l.values[0], l.values[1]};
            if (!is_finite(p))
                throw bad_airfoil("line " + std::to_string(l.number) + " has a non-finite coordinate");
            blocks.back().push_back(p);
        }
        if (blocks.back().empty()) blocks.pop_back();
    };

    const Line& first = lines[i];
    const bool counts = first.values.size() == 2 && first.values[0] >= 2.0 && first.values[1] >= 2.0 &&
                        first.values[0] == std::floor(first.values[0]) &&
                        first.values[1] == std::floor(first.values[1]) && first.values[0] < 1e7 &&
                        first.values[1] < 1e7;
    std::vector<Vec2> contour;
    if (counts) {
        result.lednicer = true;
        const size_t nu = static_cast<size_t>(first.values[0]);
        const size_t nl = static_cast<size_t>(first.values[1]);
        take_pairs(i + 1);
        std::vector<Vec2> all;
        for (const auto& b : blocks) all.insert(all.end(), b.begin(), b.end());
        if (all.size() != nu + nl)
            throw bad_airfoil("Lednicer header announces " + std::to_string(nu) + " + " +
                              std::to_string(nl) + " points, the file has " + std::to_string(all.size()));
        // Both surfaces run from the leading to the trailing edge: reverse the first.
        contour.assign(all.rbegin() + static_cast<std::ptrdiff_t>(nl), all.rend());
        contour.insert(contour.end(), all.begin() + static_cast<std::ptrdiff_t>(nu), all.end());
    } else {
        take_pairs(i);
        for (const auto& b : blocks) contour.insert(contour.end(), b.begin(), b.end());
    }
    // Repeated points (a duplicated leading edge) carry nothing.
    std::vector<Vec2> pts;
    for (Vec2 p : contour)
        if (pts.empty() || !(p == pts.back())) pts.push_back(p);
    if (pts.size() < 7) throw bad_airfoil("an airfoil needs at least 7 distinct points, got " + std::to_string(pts.size()));

    // Structure: the leading edge (the point farthest from the trailing-edge midpoint) lies
    // strictly between the ends, and the trailing-edge gap is small against the chord.
    const Vec2 te = 0.5 * (pts.front() + pts.back());
    double far = 0.0;
    const size_t le = leading_edge_index(pts, far);
    if (le == 0 || le + 1 == pts.size())
        throw bad_airfoil("the points do not go from the trailing edge round the leading edge and back");
    double gap = distance(pts.front(), pts.back());
    if (gap > 0.0 && gap <= 1e-9 * far) {
        // Rounding left a gap (or a tiny overlap) at a sharp trailing edge: close it.
        pts.back() = pts.front();
        gap = 0.0;
    }
    if (gap > 0.2 * far)
        throw bad_airfoil("the contour's ends are " + std::to_string(gap / far) +
                          " chords apart: not a trailing edge");
    // Every point within the chord's span (a little slack for real files).
    const Vec2 axis = (te - pts[le]) / far;
    for (size_t k = 0; k < pts.size(); ++k) {
        const double xi = dot(pts[k] - pts[le], axis) / far;
        if (xi < -0.05 || xi > 1.05)
            throw bad_airfoil("point " + std::to_string(k + 1) + " lies outside the chord");
    }
    // A simple contour (closed by the base when blunt).
    detail::SegmentSoup soup;
    soup.points = pts;
    const auto np = static_cast<std::uint32_t>(pts.size());
    for (std::uint32_t k = 0; k + 1 < np; ++k) soup.segments.push_back({k, k + 1});
    if (gap > 0.0) soup.segments.push_back({np - 1, 0});
    else soup.points.back() = pts.front(), soup.segments.back()[1] = 0;
    if (auto c = detail::find_crossing(soup))
        throw bad_airfoil("the contour crosses itself near point " + std::to_string(c->first + 1));
    result.points = std::move(pts);
    return result;
}

std::unique_ptr<Curve> make_airfoil(const AirfoilSpec& spec) {
    const AirfoilPlacement& pl = spec.placement;
    if (!(pl.chord > 0.0) || !std::isfinite(pl.chord))
        throw GeometryError(GeometryErrorKind::BadParameter, "chord must be positive and finite",
                            {Subject::curve({}, {"chord"})});
    if (!is_finite(pl.leading_edge))
        throw GeometryError(GeometryErrorKind::NonFinite, "leading edge is not finite",
                            {Subject::curve({}, {"leading_edge"})});
    if (!std::isfinite(pl.angle_deg))
        throw GeometryError(GeometryErrorKind::NonFinite, "angle is not finite",
                            {Subject::curve({}, {"angle_deg"})});
    AirfoilPoints parsed = parse_airfoil_dat(spec.coordinates);
    std::vector<Vec2>& pts = parsed.points;

    // Chord frame: leading edge at the origin, trailing-edge midpoint at (1, 0).
    const Vec2 te = 0.5 * (pts.front() + pts.back());
    double c = 0.0;  // the file's chord
    const size_t le = leading_edge_index(pts, c);
    const Vec2 origin = pts[le];
    const Vec2 ex = (te - origin) / c;
    const Vec2 ey = perp(ex);
    for (Vec2& p : pts) {
        const Vec2 d = p - origin;
        p = {dot(d, ex) / c, dot(d, ey) / c};
    }
    const Vec2 gap = pts.front() - pts.back();
    if (spec.trailing_edge == TrailingEdge::Closed && !(gap == Vec2{0.0, 0.0})) {
        // Sharpen: move each surface by half the gap, in proportion to x/c.
        for (size_t k = 0; k < pts.size(); ++k) {
            const double w = std::clamp(pts[k].x, 0.0, 1.0) * 0.5;
            pts[k] = k < le ? pts[k] - w * gap : pts[k] + w * gap;
        }
        pts.back() = pts.front() = 0.5 * (pts.front() + pts.back());
    }
    const double a = pl.angle_deg * std::numbers::pi / 180.0;
    const double ca = std::cos(a), sa = std::sin(a);
    for (Vec2& p : pts)
        p = {pl.leading_edge.x + pl.chord * (ca * p.x + sa * p.y),
             pl.leading_edge.y + pl.chord * (-sa * p.x + ca * p.y)};
    const bool blunt = !(pts.front() == pts.back());
    auto surface = detail::make_spline(pts, /*allow_periodic=*/false, CurveType::Airfoil);
    if (!blunt) return surface;
    std::vector<std::unique_ptr<Curve>> pieces;
    pieces.push_back(std::move(surface));
    pieces.push_back(make_line(pts.back(), pts.front()));
    return std::make_unique<detail::CompositeCurve>(CurveType::Airfoil, std::move(pieces));
}

}  // namespace meshd::core
