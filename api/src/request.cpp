// JSON -> core types (docs/api.md, "The mesh request").

#include "meshd/api/request.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <map>
#include <set>

#include "meshd/api/problem.hpp"

namespace meshd::api {

namespace {

// Objects as ordered maps would make parsing quadratic in the number of names of one object
// (each insertion scans the object); the order of the named points and curves, which numbers
// the mesh, is kept by NameOrder below instead.
using json = nlohmann::json;

// Fed by a second, SAX pass over the body: finds the first member name that occurs twice in one object
// (RFC 8259 leaves the meaning of such a document open: one of the two would be dropped
// silently), as the JSON pointer of the second occurrence; and keeps the document order of
// the names in the objects whose order matters (kOrdered).
class NameOrder {
public:
    static constexpr const char* kOrdered[] = {"/geometry/points", "/geometry/curves", "/density/curves"};

    // A SAX handler (nlohmann's json_sax interface), run over the body once the DOM parse has
    // found it valid JSON. (A parser callback would do the same in one pass, but nlohmann's
    // callback parser scans the enclosing object at every nested object's end: quadratic in
    // the curves of a request.)
    bool start_object(std::size_t) {
        stack_.push_back({false, 0, {}, {}, depth_pointer()});
        return true;
    }
    bool start_array(std::size_t) {
        stack_.push_back({true, 0, {}, {}, {}});
        return true;
    }
    bool key(std::string& k) {
        Frame& f = stack_.back();
        f.key = k;
        if (!f.seen.insert(f.key).second && !found_) {
            found_ = pointer();
            name_ = f.key;
        }
        for (const char* o : kOrdered)
            if (f.pointer == o) order_[o].push_back(f.key);
        return true;
    }
    bool end_object() { return end(); }
    bool end_array() { return end(); }
    bool null() { return value(); }
    bool boolean(bool) { return value(); }
    bool number_integer(json::number_integer_t) { return value(); }
    bool number_unsigned(json::number_unsigned_t) { return value(); }
    bool number_float(json::number_float_t, const std::string&) { return value(); }
    bool string(std::string&) { return value(); }
    bool binary(json::binary_t&) { return value(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) { return false; }

    /// The pointer of the repeated member, and its name.
    const std::optional<std::string>& found() const { return found_; }
    const std::string& name() const { return name_; }
    /// The names of the object at `pointer` (one of kOrdered) in document order.
    const std::vector<std::string>& names(const std::string& pointer) const {
        static const std::vector<std::string> none;
        const auto it = order_.find(pointer);
        return it == order_.end() ? none : it->second;
    }

private:
    bool end() {
        stack_.pop_back();
        return value();
    }
    bool value() {
        if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
        return true;
    }

    struct Frame {
        bool array;
        size_t index;             // arrays: the element being read
        std::string key;          // objects: the member being read
        std::set<std::string> seen;
        std::string pointer;      // objects: where the object is (only as deep as kOrdered)
    };
    std::string pointer() const {
        std::string p;
        for (const Frame& f : stack_) p += "/" + (f.array ? std::to_string(f.index) : pointer_token(f.key));
        return p;
    }
    // The pointer of an object starting now, when it may be one of kOrdered (two levels down
    // from the top); "" otherwise.
    std::string depth_pointer() const {
        if (stack_.size() != 2 || stack_[0].array || stack_[1].array) return {};
        return "/" + pointer_token(stack_[0].key) + "/" + pointer_token(stack_[1].key);
    }
    std::vector<Frame> stack_;
    std::optional<std::string> found_;
    std::string name_;
    std::map<std::string, std::vector<std::string>> order_;
};


[[noreturn]] void fail(const std::string& pointer, const std::string& detail, const std::string& kind = "invalid-field") {
    throw bad_request(kind, "Invalid request", detail, pointer);
}

const char* type_name(const json& j) {
    switch (j.type()) {
        case json::value_t::null: return "null";
        case json::value_t::object: return "an object";
        case json::value_t::array: return "an array";
        case json::value_t::string: return "a string";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float: return "a number";
        default: return "something else";
    }
}

void expect_object(const json& j, const std::string& ptr, std::initializer_list<const char*> allowed) {
    if (!j.is_object()) fail(ptr, std::string("expected an object, got ") + type_name(j), "wrong-type");
    const std::set<std::string> ok(allowed.begin(), allowed.end());
    for (const auto& [k, v] : j.items()) {
        if (!ok.count(k)) {
            std::string list;
            for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
            fail(ptr + "/" + pointer_token(k), "unknown field \"" + k + "\" (allowed: " + list + ")", "unknown-field");
        }
    }
}

double number(const json& j, const std::string& ptr) {
    if (!j.is_number()) fail(ptr, std::string("expected a number, got ") + type_name(j), "wrong-type");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(ptr, "number is not finite");
    return v;
}

std::string string(const json& j, const std::string& ptr) {
    if (!j.is_string()) fail(ptr, std::string("expected a string, got ") + type_name(j), "wrong-type");
    return j.get<std::string>();
}

long long integer(const json& j, const std::string& ptr, long long lo, long long hi) {
    if (!j.is_number_integer() && !(j.is_number_float() && std::floor(j.get<double>()) == j.get<double>()))
        fail(ptr, std::string("expected an integer, got ") + type_name(j), "wrong-type");
    const double v = j.get<double>();
    if (v < static_cast<double>(lo) || v > static_cast<double>(hi))
        fail(ptr, "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
    return static_cast<long long>(v);
}

core::Vec2 point(const json& j, const std::string& ptr) {
    if (!j.is_array() || j.size() != 2) fail(ptr, "expected a point [x, y]", "wrong-type");
    return {number(j[0], ptr + "/0"), number(j[1], ptr + "/1")};
}

std::vector<core::Vec2> points(const json& j, const std::string& ptr) {
    if (!j.is_array()) fail(ptr, std::string("expected an array of points, got ") + type_name(j), "wrong-type");
    std::vector<core::Vec2> out;
    out.reserve(j.size());
    for (size_t i = 0; i < j.size(); ++i) out.push_back(point(j[i], ptr + "/" + std::to_string(i)));
    return out;
}

core::ScalarSpec scalar(const json& j, const std::string& ptr) {
    if (j.is_number()) return number(j, ptr);
    if (j.is_string()) return j.get<std::string>();
    fail(ptr, std::string("expected a number or an expression string, got ") + type_name(j), "wrong-type");
}

// The rule for tags, one for every format (docs/api.md): 1 to 256 characters, no control
// characters (below U+0020, U+007F) and no double quote; the writers escape what their
// format needs beyond that. Returns what is wrong, or nullptr.
const char* bad_tag(const std::string& tag) {
    if (tag.empty()) return "is empty";
    size_t characters = 0;  // UTF-8: every byte but continuation bytes starts one
    for (const char ch : tag) characters += (static_cast<unsigned char>(ch) & 0xc0) != 0x80;
    if (characters > kMaxTagCharacters) return "is longer than 256 characters";
    for (const char ch : tag) {
        const auto u = static_cast<unsigned char>(ch);
        if (u < 0x20 || u == 0x7f) return "holds a control character";
        if (ch == '"') return "holds a double quote";
    }
    return nullptr;
}

core::AirfoilPlacement placement(const json& c, const std::string& ptr) {
    core::AirfoilPlacement p;
    if (c.contains("chord")) p.chord = number(c["chord"], ptr + "/chord");
    if (c.contains("leading_edge")) p.leading_edge = point(c["leading_edge"], ptr + "/leading_edge");
    if (c.contains("angle_deg")) p.angle_deg = number(c["angle_deg"], ptr + "/angle_deg");
    return p;
}

core::TrailingEdge trailing_edge(const json& c, const std::string& ptr, core::TrailingEdge dflt) {
    if (!c.contains("trailing_edge")) return dflt;
    const std::string s = string(c["trailing_edge"], ptr + "/trailing_edge");
    if (s == "closed") return core::TrailingEdge::Closed;
    if (s == "open") return core::TrailingEdge::Open;
    fail(ptr + "/trailing_edge", "trailing_edge must be \"closed\" or \"open\"");
}

core::CurveSpec curve(const std::string& name, const json& c, const std::string& ptr) {
    if (!c.is_object()) fail(ptr, std::string("expected a curve object, got ") + type_name(c), "wrong-type");
    if (!c.contains("type")) fail(ptr + "/type", "a curve needs a \"type\"", "missing-field");
    const std::string type = string(c["type"], ptr + "/type");
    core::CurveSpec cs;
    cs.name = name;
    auto ends = [&](bool required) {
        for (const char* k : {"from", "to"}) {
            if (c.contains(k)) {
                const std::string v = string(c[k], ptr + "/" + k);
                (std::string(k) == "from" ? cs.from : cs.to) = v;
            } else if (required) {
                fail(ptr + "/" + k, "a " + type + " needs \"" + k + "\"", "missing-field");
            }
        }
    };
    if (c.contains("tag")) cs.tag = string(c["tag"], ptr + "/tag");
    // The tag (the curve's name when it has none) names a boundary in every output format.
    if (const char* why = bad_tag(cs.tag.value_or(name)))
        fail(cs.tag ? ptr + "/tag" : ptr,
             std::string(cs.tag ? "the tag" : "the curve's name, its tag when it has no \"tag\",") + " " + why);
    if (type == "line") {
        expect_object(c, ptr, {"type", "tag", "from", "to"});
        ends(true);
        cs.shape = core::LineShape{};
    } else if (type == "arc") {
        expect_object(c, ptr, {"type", "tag", "from", "to", "center", "direction"});
        ends(true);
        if (!c.contains("center")) fail(ptr + "/center", "an arc needs a \"center\"", "missing-field");
        core::ArcShape a{point(c["center"], ptr + "/center"), core::ArcDirection::Ccw};
        if (c.contains("direction")) {
            const std::string d = string(c["direction"], ptr + "/direction");
            if (d == "cw") a.direction = core::ArcDirection::Cw;
            else if (d != "ccw") fail(ptr + "/direction", "direction must be \"ccw\" or \"cw\"");
        }
        cs.shape = a;
    } else if (type == "bspline") {
        expect_object(c, ptr, {"type", "tag", "from", "to", "control_points", "degree", "knots"});
        ends(false);
        if (!c.contains("control_points")) fail(ptr + "/control_points", "a bspline needs \"control_points\"", "missing-field");
        core::BSplineShape b;
        b.control_points = points(c["control_points"], ptr + "/control_points");
        if (c.contains("degree")) b.degree = static_cast<int>(integer(c["degree"], ptr + "/degree", 1, 15));
        if (c.contains("knots")) {
            const json& k = c["knots"];
            if (!k.is_array()) fail(ptr + "/knots", "expected an array of numbers", "wrong-type");
            std::vector<double> knots;
            for (size_t i = 0; i < k.size(); ++i) knots.push_back(number(k[i], ptr + "/knots/" + std::to_string(i)));
            b.knots = std::move(knots);
        }
        cs.shape = std::move(b);
    } else if (type == "spline") {
        expect_object(c, ptr, {"type", "tag", "from", "to", "through"});
        ends(false);
        if (!c.contains("through")) fail(ptr + "/through", "a spline needs \"through\"", "missing-field");
        cs.shape = core::SplineShape{points(c["through"], ptr + "/through")};
    } else if (type == "naca") {
        expect_object(c, ptr, {"type", "tag", "from", "to", "code", "chord", "leading_edge", "angle_deg",
                               "trailing_edge", "surface"});
        ends(false);
        if (!c.contains("code")) fail(ptr + "/code", "a naca curve needs a \"code\"", "missing-field");
        core::NacaSpec n;
        // A string: as a number, "0012" would lose its leading zeros.
        n.code = string(c["code"], ptr + "/code");
        n.placement = placement(c, ptr);
        n.trailing_edge = trailing_edge(c, ptr, core::TrailingEdge::Closed);
        if (c.contains("surface")) {
            const std::string s = string(c["surface"], ptr + "/surface");
            if (s == "upper") n.surface = core::AirfoilSurface::Upper;
            else if (s == "lower") n.surface = core::AirfoilSurface::Lower;
            else if (s != "both") fail(ptr + "/surface", "surface must be \"both\", \"upper\" or \"lower\"");
        }
        cs.shape = n;
    } else if (type == "airfoil") {
        expect_object(c, ptr, {"type", "tag", "from", "to", "coordinates", "chord", "leading_edge", "angle_deg",
                               "trailing_edge"});
        ends(false);
        if (!c.contains("coordinates")) fail(ptr + "/coordinates", "an airfoil needs \"coordinates\"", "missing-field");
        core::AirfoilSpec a;
        a.coordinates = string(c["coordinates"], ptr + "/coordinates");
        a.placement = placement(c, ptr);
        a.trailing_edge = trailing_edge(c, ptr, core::TrailingEdge::Open);
        cs.shape = std::move(a);
    } else {
        fail(ptr + "/type", "unknown curve type \"" + type + "\" (line, arc, bspline, spline, naca, airfoil)");
    }
    return cs;
}

void geometry(const json& g, const NameOrder& order, core::DomainSpec& out) {
    const std::string ptr = "/geometry";
    expect_object(g, ptr, {"points", "curves", "loops", "embedded"});
    if (g.contains("points")) {
        const json& p = g["points"];
        if (!p.is_object()) fail(ptr + "/points", std::string("expected an object of named points, got ") + type_name(p), "wrong-type");
        for (const std::string& name : order.names("/geometry/points"))
            out.points.push_back({name, point(p.at(name), ptr + "/points/" + pointer_token(name))});
    }
    if (!g.contains("curves")) fail(ptr + "/curves", "geometry needs \"curves\"", "missing-field");
    const json& cs = g["curves"];
    if (!cs.is_object()) fail(ptr + "/curves", std::string("expected an object of named curves, got ") + type_name(cs), "wrong-type");
    for (const std::string& name : order.names("/geometry/curves"))
        out.curves.push_back(curve(name, cs.at(name), ptr + "/curves/" + pointer_token(name)));
    if (!g.contains("loops")) fail(ptr + "/loops", "geometry needs \"loops\"", "missing-field");
    const json& ls = g["loops"];
    if (!ls.is_array()) fail(ptr + "/loops", std::string("expected an array of loops, got ") + type_name(ls), "wrong-type");
    for (size_t i = 0; i < ls.size(); ++i) {
        const std::string lp = ptr + "/loops/" + std::to_string(i);
        if (!ls[i].is_array()) fail(lp, std::string("expected an array of curve names, got ") + type_name(ls[i]), "wrong-type");
        std::vector<core::LoopItem> items;
        for (size_t j = 0; j < ls[i].size(); ++j) {
            std::string n = string(ls[i][j], lp + "/" + std::to_string(j));
            const bool rev = !n.empty() && n[0] == '-';
            if (rev) n.erase(0, 1);
            items.push_back({n, rev});
        }
        out.loops.push_back(std::move(items));
    }
    if (g.contains("embedded")) {
        const json& e = g["embedded"];
        if (!e.is_array()) fail(ptr + "/embedded", std::string("expected an array of curve names, got ") + type_name(e), "wrong-type");
        for (size_t i = 0; i < e.size(); ++i) out.embedded.push_back(string(e[i], ptr + "/embedded/" + std::to_string(i)));
    }
}

void density(const json& d, const NameOrder& order, core::DensitySpec& out) {
    const std::string ptr = "/density";
    expect_object(d, ptr, {"size", "curves", "interior", "gradation", "min", "max"});
    if (d.contains("size")) out.size = scalar(d["size"], ptr + "/size");
    if (d.contains("curves")) {
        const json& c = d["curves"];
        if (!c.is_object()) fail(ptr + "/curves", std::string("expected an object, got ") + type_name(c), "wrong-type");
        for (const std::string& k : order.names("/density/curves"))
            out.curves.push_back({k, scalar(c.at(k), ptr + "/curves/" + pointer_token(k))});
    }
    if (d.contains("interior")) {
        const std::string s = string(d["interior"], ptr + "/interior");
        if (s == "interpolate") {
            out.interior = core::InteriorMode::Interpolate;
        } else {
            out.interior = core::InteriorMode::Expression;
            out.interior_expression = s;
        }
    }
    if (d.contains("gradation")) out.gradation = number(d["gradation"], ptr + "/gradation");
    if (d.contains("min")) out.min = number(d["min"], ptr + "/min");
    if (d.contains("max")) out.max = number(d["max"], ptr + "/max");
    if (!out.size && out.curves.empty()) fail(ptr, "density needs \"size\" or \"curves\"", "missing-field");
}

void options(const json& o, MeshRequest& r) {
    const std::string ptr = "/options";
    expect_object(o, ptr, {"smoothing_iterations", "triangulator", "max_points", "timeout_s", "min_angle_deg",
                           "patch_types", "slab_thickness", "order"});
    if (o.contains("order")) r.options.order = static_cast<int>(integer(o["order"], ptr + "/order", 1, 2));
    if (o.contains("smoothing_iterations"))
        r.options.smoothing_iterations = static_cast<int>(integer(o["smoothing_iterations"], ptr + "/smoothing_iterations", 0, 1000));
    if (o.contains("triangulator")) {
        const std::string t = string(o["triangulator"], ptr + "/triangulator");
        if (t == "delaunay") r.options.triangulator = core::Triangulator::Delaunay;
        else if (t == "advancing-front") r.options.triangulator = core::Triangulator::AdvancingFront;
        else fail(ptr + "/triangulator", "triangulator must be \"delaunay\" or \"advancing-front\"");
    }
    if (o.contains("max_points"))
        r.options.max_points = static_cast<size_t>(
            integer(o["max_points"], ptr + "/max_points", 1, static_cast<long long>(core::kMaxPointsLimit)));
    if (o.contains("timeout_s")) {
        const double t = number(o["timeout_s"], ptr + "/timeout_s");
        if (!(t > 0.0)) fail(ptr + "/timeout_s", "timeout_s must be positive");
        r.timeout_s = t;
    }
    if (o.contains("patch_types")) {
        // Tag -> OpenFOAM patch type, for format=foam; every key must be a tag of the geometry.
        const json& p = o["patch_types"];
        const std::string at = ptr + "/patch_types";
        if (!p.is_object()) fail(at, std::string("expected an object, got ") + type_name(p), "wrong-type");
        std::set<std::string> tags;
        for (const core::CurveSpec& c : r.geometry.curves) tags.insert(c.tag.value_or(c.name));
        for (const auto& [tag, value] : p.items()) {
            const std::string here = at + "/" + pointer_token(tag);
            const std::string type = string(value, here);
            if (type != "patch" && type != "wall" && type != "symmetryPlane" && type != "symmetry")
                fail(here, "patch type \"" + type + "\" is not one of patch, wall, symmetryPlane, symmetry");
            if (!tags.count(tag)) fail(here, "\"" + tag + "\" is not a tag of the geometry");
            r.foam.patch_types[tag] = type;
        }
    }
    if (o.contains("slab_thickness")) {
        const double t = number(o["slab_thickness"], ptr + "/slab_thickness");
        if (!(t > 0.0) || !(t <= 1e30)) fail(ptr + "/slab_thickness", "slab_thickness must be positive and at most 1e30");
        r.foam.slab_thickness = t;
    }
    if (o.contains("min_angle_deg")) {
        const double a = number(o["min_angle_deg"], ptr + "/min_angle_deg");
        if (a < 0.0 || a > 34.0) fail(ptr + "/min_angle_deg", "min_angle_deg must be between 0 and 34");
        r.options.min_angle_deg = a;
        // 0 asked in so many words is the contract's "off, the paper's pure method": not even
        // the defaults' last resort for 30 degrees (which an absent member keeps).
        r.options.sharp_last_resort = a > 0.0;
    }
}

void boundary_layers(const json& b, MeshRequest& r) {
    const std::string ptr = "/boundary_layers";
    if (!b.is_array()) fail(ptr, std::string("expected an array of layer entries, got ") + type_name(b), "wrong-type");
    if (b.size() > 100) fail(ptr, "at most 100 boundary layer entries");
    for (size_t i = 0; i < b.size(); ++i) {
        const std::string at = ptr + "/" + std::to_string(i);
        const json& e = b[i];
        expect_object(e, at, {"curves", "first_height", "growth", "layers", "thickness", "cells"});
        core::BoundaryLayerSpec s;
        if (!e.contains("curves")) fail(at + "/curves", "a layer entry needs \"curves\"", "missing-field");
        const json& c = e["curves"];
        if (!c.is_array() || c.empty())
            fail(at + "/curves", "expected a non-empty array of curve names or tags", "wrong-type");
        for (size_t k = 0; k < c.size(); ++k) s.curves.push_back(string(c[k], at + "/curves/" + std::to_string(k)));
        if (!e.contains("first_height"))
            fail(at + "/first_height", "a layer entry needs \"first_height\"", "missing-field");
        s.first_height = number(e["first_height"], at + "/first_height");
        if (!(s.first_height > 0.0) || s.first_height > 1e30)
            fail(at + "/first_height", "first_height must be positive and at most 1e30");
        if (e.contains("growth")) {
            s.growth = number(e["growth"], at + "/growth");
            if (!(s.growth >= 1.0 && s.growth <= 5.0)) fail(at + "/growth", "growth must be between 1 and 5");
        }
        if (e.contains("layers") == e.contains("thickness"))
            fail(at, "a layer entry needs one of \"layers\" and \"thickness\"", "missing-field");
        if (e.contains("layers"))
            s.layers = static_cast<int>(integer(e["layers"], at + "/layers", 1, core::kMaxLayers));
        if (e.contains("thickness")) {
            s.thickness = number(e["thickness"], at + "/thickness");
            if (!(s.thickness > 0.0) || s.thickness > 1e30)
                fail(at + "/thickness", "thickness must be positive and at most 1e30");
        }
        if (e.contains("cells")) {
            const std::string cells = string(e["cells"], at + "/cells");
            if (cells != "quads" && cells != "triangles") fail(at + "/cells", "cells must be \"quads\" or \"triangles\"");
            s.quads = cells == "quads";
        }
        r.options.boundary_layers.push_back(std::move(s));
    }
}

// Depth of nesting, outside strings: refuse deep documents before the parser sees them.
int nesting_depth(std::string_view s) {
    int depth = 0, worst = 0;
    bool in_string = false, escape = false;
    for (char c : s) {
        if (in_string) {
            if (escape) escape = false;
            else if (c == '\\') escape = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') in_string = true;
        else if (c == '[' || c == '{') worst = std::max(worst, ++depth);
        else if (c == ']' || c == '}') --depth;
    }
    return worst;
}

}  // namespace

MeshRequest parse_request(std::string_view body) {
    if (nesting_depth(body) > kMaxJsonDepth)
        throw bad_request("too-deep", "Malformed request",
                          "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels", "");
    json j;
    NameOrder names;
    try {
        j = json::parse(body.begin(), body.end());
        json::sax_parse(body.begin(), body.end(), &names);
    } catch (const json::parse_error& e) {
        throw bad_request("malformed-json", "Malformed request",
                          "the body is not valid JSON (at byte " + std::to_string(e.byte) + ")", "");
    } catch (const json::out_of_range&) {
        throw bad_request("malformed-json", "Malformed request",
                          "the body holds a number beyond the range of a double (about 1.8e308)", "");
    }
    if (const auto& where = names.found())
        throw bad_request("duplicate-field", "Invalid request",
                          "the name \"" + names.name() + "\" occurs twice in one object",
                          *where);
    MeshRequest r;
    expect_object(j, "", {"geometry", "density", "options", "boundary_layers"});
    if (!j.contains("geometry")) fail("/geometry", "the request needs \"geometry\"", "missing-field");
    if (!j.contains("density")) fail("/density", "the request needs \"density\"", "missing-field");
    geometry(j["geometry"], names, r.geometry);
    density(j["density"], names, r.density);
    if (j.contains("options")) options(j["options"], r);
    if (j.contains("boundary_layers")) boundary_layers(j["boundary_layers"], r);
    return r;
}

}  // namespace meshd::api
