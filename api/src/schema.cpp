// The schemas of schema.hpp. Numbers that the core checks (a chord, a density) carry no
// bounds here: a bad value there is a 422 from the core, not a malformed request.

#include "meshd/api/schema.hpp"

#include <nlohmann/json.hpp>

#include "meshd/api/request.hpp"

namespace meshd::api {

namespace {

using json = nlohmann::ordered_json;

// The request of examples/naca0012.json (the API's own example), embedded at build time.
constexpr const char* kExampleRequest =
#include "naca0012_example.inc"
    ;

json ref(const std::string& name) { return {{"$ref", "#/components/schemas/" + name}}; }
json string() { return {{"type", "string"}}; }
json number() { return {{"type", "number"}}; }
json point() { return {{"type", "array"}, {"items", number()}, {"minItems", 2}, {"maxItems", 2}}; }
json points() { return {{"type", "array"}, {"items", ref("Point")}}; }

// A curve of one type: its own members, the ones every curve has, and the required ones.
json curve(const char* type, json members, std::vector<std::string> required) {
    json props = {
        {"type", {{"type", "string"}, {"enum", {type}}}},
        {"tag",
         {{"type", "string"},
          {"pattern", "^[^\\u0000-\\u001f\\u007f\"]{1,256}$"},
          {"description",
           "boundary marker; the curve's name when absent (1 to 256 characters, no control "
           "character, no double quote)"}}},
        {"from", {{"type", "string"}, {"description", "name of the start point"}}},
        {"to", {{"type", "string"}, {"description", "name of the end point"}}}};
    props.update(members);
    required.insert(required.begin(), "type");
    return {{"type", "object"},
            {"required", required},
            {"properties", props},
            {"additionalProperties", false}};
}

json placement() {
    return {{"chord", number()},
            {"leading_edge", ref("Point")},
            {"angle_deg",
             {{"type", "number"},
              {"description", "angle of attack: rotation about the leading edge, nose up"}}}};
}

json curves() {
    json naca = placement();
    naca["code"] = {{"type", "string"},
                    {"description", "a NACA 4- or 5-digit designation such as \"0012\" or \"23012\""}};
    naca["trailing_edge"] = {
        {"type", "string"}, {"enum", {"closed", "open"}}, {"default", "closed"}};
    naca["surface"] = {
        {"type", "string"}, {"enum", {"both", "upper", "lower"}}, {"default", "both"}};
    json airfoil = placement();
    airfoil["coordinates"] = {{"type", "string"},
                              {"description", "the text of a Selig or Lednicer .dat file"}};
    airfoil["trailing_edge"] = {
        {"type", "string"}, {"enum", {"closed", "open"}}, {"default", "open"}};
    return {
        {"LineCurve", curve("line", json::object(), {"from", "to"})},
        {"ArcCurve",
         curve("arc",
               {{"center", ref("Point")},
                {"direction", {{"type", "string"}, {"enum", {"ccw", "cw"}}, {"default", "ccw"}}}},
               {"from", "to", "center"})},
        {"BSplineCurve",
         curve("bspline",
               {{"control_points", points()},
                {"degree", {{"type", "integer"}, {"minimum", 1}, {"maximum", 15}, {"default", 3}}},
                {"knots", {{"type", "array"}, {"items", number()}}}},
               {"control_points"})},
        {"SplineCurve", curve("spline", {{"through", points()}}, {"through"})},
        {"NacaCurve", curve("naca", naca, {"code"})},
        {"AirfoilCurve", curve("airfoil", airfoil, {"coordinates"})},
    };
}

json request() {
    json curve_kinds = json::array();
    for (const char* k :
         {"LineCurve", "ArcCurve", "BSplineCurve", "SplineCurve", "NacaCurve", "AirfoilCurve"})
        curve_kinds.push_back(ref(k));
    const json scalar = {
        {"oneOf", {number(), {{"type", "string"}, {"description", "an expression in x and y"}}}}};
    const json names = {{"type", "array"}, {"items", string()}};
    return {
        {"type", "object"},
        {"required", {"geometry", "density"}},
        {"additionalProperties", false},
        {"properties",
         {{"geometry",
           {{"type", "object"},
            {"required", {"curves", "loops"}},
            {"additionalProperties", false},
            {"properties",
             {{"points", {{"type", "object"}, {"additionalProperties", ref("Point")}}},
              {"curves", {{"type", "object"}, {"additionalProperties", {{"oneOf", curve_kinds}}}}},
              {"loops",
               {{"type", "array"},
                {"items", names},
                {"description",
                 "curve names; \"-name\" runs a curve backwards; the outer loop and the holes"}}},
              {"embedded", names}}}}},
          {"density",
           {{"type", "object"},
            {"additionalProperties", false},
            {"anyOf", {{{"required", {"size"}}}, {{"required", {"curves"}}}}},
            {"properties",
             {{"size", scalar},
              {"curves", {{"type", "object"}, {"additionalProperties", scalar}}},
              {"interior",
               {{"type", "string"},
                {"description", "\"interpolate\" (the paper's eq. 6.1) or an expression"}}},
              {"gradation", number()},
              {"min", number()},
              {"max", number()}}}}},
          {"options",
           {{"type", "object"},
            {"additionalProperties", false},
            {"properties",
             {{"smoothing_iterations",
               {{"type", "integer"}, {"minimum", 0}, {"maximum", 1000}, {"default", 5}}},
              {"triangulator",
               {{"type", "string"},
                {"enum", {"delaunay", "advancing-front"}},
                {"default", "delaunay"}}},
              {"max_points", {{"type", "integer"}, {"minimum", 1}, {"maximum", static_cast<long long>(core::kMaxPointsLimit)}}},
              {"timeout_s", {{"type", "number"}, {"minimum", 0}, {"exclusiveMinimum", true}}},
              {"min_angle_deg",
               {{"type", "number"},
                {"description",
                 "refine until no angle is below this; absent: only the defaults' last resort for 30 degrees "
                 "(a few meshes in 100,000); 0: no refinement at all (the paper's method)"},
                {"minimum", 0},
                {"maximum", 34}}},
              {"order",
               {{"type", "integer"},
                {"description", "2: 6-node triangles, their edge nodes on the curves (not for su2 and foam)"},
                {"minimum", 1},
                {"maximum", 2},
                {"default", 1}}},
              {"patch_types",
               {{"type", "object"},
                {"description", "for format=foam: tag -> OpenFOAM patch type; other tags are patch"},
                {"additionalProperties", {{"type", "string"}, {"enum", {"patch", "wall", "symmetryPlane", "symmetry"}}}}}},
              {"slab_thickness",
               {{"type", "number"},
                {"description", "for format=foam: the extrusion's thickness (default: the mean boundary edge length)"},
                {"minimum", 0},
                {"exclusiveMinimum", true},
                {"maximum", 1e30}}}}}}},
          {"boundary_layers",
           {{"type", "array"},
            {"description", "thin stretched cells along walls, for viscous flow"},
            {"maxItems", 100},
            {"items",
             {{"type", "object"},
              {"required", {"curves", "first_height"}},
              {"additionalProperties", false},
              {"oneOf", {{{"required", {"layers"}}}, {{"required", {"thickness"}}}}},
              {"properties",
               {{"curves", {{"type", "array"}, {"items", string()}, {"minItems", 1},
                            {"description", "names or tags of loop curves (the walls)"}}},
                {"first_height", {{"type", "number"}, {"minimum", 0}, {"exclusiveMinimum", true}}},
                {"growth", {{"type", "number"}, {"minimum", 1}, {"maximum", 5}, {"default", 1.2}}},
                {"layers", {{"type", "integer"}, {"minimum", 1}, {"maximum", core::kMaxLayers}}},
                {"thickness", {{"type", "number"}, {"minimum", 0}, {"exclusiveMinimum", true}}},
                {"cells", {{"type", "string"}, {"enum", {"quads", "triangles"}}, {"default", "quads"}}}}}}}}}}},
        {"example", json::parse(kExampleRequest)}};
}

json metrics() {
    const json number_stats = {
        {"type", "object"},
        {"properties", {{"min", number()}, {"max", number()}, {"mean", number()}}}};
    return {
        {"type", "object"},
        {"properties",
         {{"points", {{"type", "integer"}}},
          {"boundary_points", {{"type", "integer"}}},
          {"interior_points", {{"type", "integer"}}},
          {"triangles", {{"type", "integer"}}},
          {"quads", {{"type", "integer"}}},
          {"boundary_layers",
           {{"type", "array"},
            {"description", "per boundary_layers entry: the layers made"},
            {"items",
             {{"type", "object"},
              {"properties",
               {{"columns", {{"type", "integer"}}},
                {"layers", number_stats},
                {"first_height", number_stats},
                {"aspect_ratio_max", number()},
                {"scaled_jacobian_min", number()},
                {"skew_max", number()},
                {"cut_back",
                 {{"type", "object"},
                  {"properties",
                   {{"columns", {{"type", "integer"}}},
                    {"at", {{"type", "array"}, {"items", ref("Point")}}}}}}}}}}}}},
          {"angle_deg", number_stats},
          {"quality",
           {{"type", "object"},
            {"properties",
             {{"min", number()},
              {"mean", number()},
              {"histogram",
               {{"type", "array"},
                {"items", {{"type", "integer"}}},
                {"minItems", 10},
                {"maxItems", 10}}}}}}},
          {"size_ratio",
           {{"type", "object"}, {"properties", {{"mean", number()}, {"within_sqrt2", number()}}}}},
          {"curved",
           {{"type", "object"},
            {"description", "order 2 only: curve edges with their node on the curve, those left straight so "
                            "that no triangle folds, the smallest scaled Jacobian of any triangle"},
            {"properties",
             {{"edges", {{"type", "integer"}}},
              {"straightened", {{"type", "integer"}}},
              {"scaled_jacobian_min", number()}}}}},
          {"timings_ms", {{"type", "object"}, {"additionalProperties", number()}}},
          {"predicates_exact",
           {{"type", "object"}, {"additionalProperties", {{"type", "integer"}}}}},
          {"gradation_applied",
           {{"type", "number"},
            {"description", "present when the request gave no density.gradation and its size field jumped "
                            "faster than one element can follow: the gradation the mesh was made with"}}}}}};
}

}  // namespace

std::string openapi_schemas() {
    json s = {{"Point", point()}};
    s.update(curves());
    s["MeshRequest"] = request();
    s["MeshResponse"] = {
        {"type", "object"},
        {"properties",
         {{"mesh",
           {{"type", "object"},
            {"properties",
             {{"points", points()},
              {"sizes",
               {{"type", "array"},
                {"description", "with ?sizes=true: the target size (rho) at each point"},
                {"items", {{"type", "number"}}}}},
              {"triangles",
               {{"type", "array"},
                {"items",
                 {{"type", "array"},
                  {"items", {{"type", "integer"}}},
                  {"minItems", 3},
                  {"maxItems", 6}}}}},
              {"quads",
               {{"type", "array"},
                {"description", "the boundary layers' quadrilaterals, counter-clockwise"},
                {"items",
                 {{"type", "array"},
                  {"items", {{"type", "integer"}}},
                  {"minItems", 4},
                  {"maxItems", 4}}}}},
              {"boundaries",
               {{"type", "object"},
                {"description", "tag -> edges [a, b] (loop edges with the domain on their left)"},
                {"additionalProperties",
                 {{"type", "array"},
                  {"items", {{"type", "array"}, {"items", {{"type", "integer"}}}}}}}}}}}}},
          {"metrics", ref("Metrics")}}}};
    s["Metrics"] = metrics();
    s["Problem"] = {{"type", "object"},
                    {"required", {"type", "title", "status", "detail"}},
                    {"properties",
                     {{"type", string()},
                      {"title", string()},
                      {"status", {{"type", "integer"}}},
                      {"detail", string()},
                      {"pointer",
                       {{"type", "string"},
                        {"description", "JSON pointer to the offending field of the request"}}}}}};
    return s.dump();
}

}  // namespace meshd::api
