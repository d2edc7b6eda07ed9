// GET /v1/openapi.json: the OpenAPI 3 description of the service.

#include <nlohmann/json.hpp>

#include "meshd/server/service.hpp"

namespace meshd::server {

namespace {

using json = nlohmann::ordered_json;

json ref(const std::string& name) { return {{"$ref", "#/components/schemas/" + name}}; }

json problem_response(const std::string& what) {
    return {{"description", what}, {"content", {{"application/problem+json", {{"schema", ref("Problem")}}}}}};
}

json mesh_content() {
    return {{"application/json", {{"schema", ref("MeshResponse")}}},
            {"application/octet-stream", {{"schema", {{"type", "string"}, {"format", "binary"}}}}},
            {"text/plain", {{"schema", {{"type", "string"}}}}},
            {"image/svg+xml", {{"schema", {{"type", "string"}}}}}};
}

json format_param() {
    return {{"name", "format"}, {"in", "query"}, {"required", false},
            {"schema", {{"type", "string"}, {"enum", {"json", "vtk", "su2", "msh", "svg"}}, {"default", "json"}}}};
}

json id_param() {
    return {{"name", "id"}, {"in", "path"}, {"required", true}, {"schema", {{"type", "string"}, {"pattern", "^[0-9a-f]+$"}}}};
}

json scalar() {
    return {{"oneOf", {{{"type", "number"}, {"exclusiveMinimum", 0}}, {{"type", "string"}, {"description", "expression in x and y"}}}}};
}

json point() { return {{"type", "array"}, {"items", {{"type", "number"}}}, {"minItems", 2}, {"maxItems", 2}}; }

json schemas() {
    json curve = {
        {"type", "object"},
        {"required", {"type"}},
        {"properties",
         {{"type", {{"type", "string"}, {"enum", {"line", "arc", "bspline", "spline", "naca", "airfoil"}}}},
          {"tag", {{"type", "string"}}},
          {"from", {{"type", "string"}}},
          {"to", {{"type", "string"}}},
          {"center", point()},
          {"direction", {{"type", "string"}, {"enum", {"ccw", "cw"}}}},
          {"control_points", {{"type", "array"}, {"items", point()}}},
          {"degree", {{"type", "integer"}, {"minimum", 1}, {"maximum", 15}}},
          {"knots", {{"type", "array"}, {"items", {{"type", "number"}}}}},
          {"through", {{"type", "array"}, {"items", point()}}},
          {"code", {{"type", "string"}, {"pattern", "^[0-9]{4,5}$"}}},
          {"chord", {{"type", "number"}, {"exclusiveMinimum", 0}}},
          {"leading_edge", point()},
          {"angle_deg", {{"type", "number"}}},
          {"trailing_edge", {{"type", "string"}, {"enum", {"closed", "open"}}}},
          {"surface", {{"type", "string"}, {"enum", {"both", "upper", "lower"}}}},
          {"coordinates", {{"type", "string"}, {"description", "Selig or Lednicer .dat text"}}}}},
        {"additionalProperties", false}};
    json request = {
        {"type", "object"},
        {"required", {"geometry", "density"}},
        {"additionalProperties", false},
        {"properties",
         {{"geometry",
           {{"type", "object"},
            {"required", {"curves", "loops"}},
            {"additionalProperties", false},
            {"properties",
             {{"points", {{"type", "object"}, {"additionalProperties", point()}}},
              {"curves", {{"type", "object"}, {"additionalProperties", curve}}},
              {"loops", {{"type", "array"}, {"items", {{"type", "array"}, {"items", {{"type", "string"}}}}}}},
              {"embedded", {{"type", "array"}, {"items", {{"type", "string"}}}}}}}}},
          {"density",
           {{"type", "object"},
            {"additionalProperties", false},
            {"properties",
             {{"size", scalar()},
              {"curves", {{"type", "object"}, {"additionalProperties", scalar()}}},
              {"interior", {{"type", "string"}, {"description", "\"interpolate\" (eq. 6.1) or an expression"}}},
              {"gradation", {{"type", "number"}, {"exclusiveMinimum", 1}}},
              {"min", {{"type", "number"}, {"exclusiveMinimum", 0}}},
              {"max", {{"type", "number"}, {"exclusiveMinimum", 0}}}}}}},
          {"options",
           {{"type", "object"},
            {"additionalProperties", false},
            {"properties",
             {{"smoothing_iterations", {{"type", "integer"}, {"minimum", 0}, {"default", 5}}},
              {"triangulator", {{"type", "string"}, {"enum", {"delaunay", "advancing-front"}}, {"default", "delaunay"}}},
              {"max_points", {{"type", "integer"}, {"minimum", 1}}},
              {"timeout_s", {{"type", "number"}, {"exclusiveMinimum", 0}}},
              {"min_angle_deg", {{"type", "number"}, {"minimum", 0}, {"maximum", 34}}}}}}}}}};
    json stats = {{"type", "object"}, {"properties", {{"min", {{"type", "number"}}}, {"max", {{"type", "number"}}}, {"mean", {{"type", "number"}}}}}};
    json metrics = {
        {"type", "object"},
        {"properties",
         {{"points", {{"type", "integer"}}},
          {"boundary_points", {{"type", "integer"}}},
          {"interior_points", {{"type", "integer"}}},
          {"triangles", {{"type", "integer"}}},
          {"angle_deg", stats},
          {"quality",
           {{"type", "object"},
            {"properties",
             {{"min", {{"type", "number"}}},
              {"mean", {{"type", "number"}}},
              {"histogram", {{"type", "array"}, {"items", {{"type", "integer"}}}, {"minItems", 10}, {"maxItems", 10}}}}}}},
          {"size_ratio", {{"type", "object"}, {"properties", {{"mean", {{"type", "number"}}}, {"within_sqrt2", {{"type", "number"}}}}}}},
          {"timings_ms", {{"type", "object"}, {"additionalProperties", {{"type", "number"}}}}}}}};
    json mesh_response = {
        {"type", "object"},
        {"properties",
         {{"mesh",
           {{"type", "object"},
            {"properties",
             {{"points", {{"type", "array"}, {"items", point()}}},
              {"triangles", {{"type", "array"}, {"items", {{"type", "array"}, {"items", {{"type", "integer"}}}}}}},
              {"boundaries", {{"type", "object"}, {"additionalProperties", {{"type", "array"}}}}}}}}},
          {"metrics", ref("Metrics")}}}};
    json job = {{"type", "object"},
                {"required", {"id", "status"}},
                {"properties",
                 {{"id", {{"type", "string"}}},
                  {"status", {{"type", "string"}, {"enum", {"queued", "running", "succeeded", "failed", "cancelled"}}}},
                  {"progress", {{"type", "number"}, {"minimum", 0}, {"maximum", 1}}},
                  {"stage", {{"type", "string"}}},
                  {"submitted_at", {{"type", "string"}, {"format", "date-time"}}},
                  {"started_at", {{"type", "string"}, {"format", "date-time"}}},
                  {"finished_at", {{"type", "string"}, {"format", "date-time"}}},
                  {"metrics", ref("Metrics")},
                  {"error", ref("Problem")}}}};
    json problem = {{"type", "object"},
                    {"required", {"type", "title", "status", "detail"}},
                    {"properties",
                     {{"type", {{"type", "string"}}},
                      {"title", {{"type", "string"}}},
                      {"status", {{"type", "integer"}}},
                      {"detail", {{"type", "string"}}},
                      {"pointer", {{"type", "string"}, {"description", "JSON pointer into the request"}}}}}};
    return {{"MeshRequest", request}, {"MeshResponse", mesh_response}, {"Metrics", metrics}, {"Job", job}, {"Problem", problem}};
}

// The operations, keyed by method and OpenAPI path.
json operation(const std::string& method, const std::string& path) {
    const json req_body = {{"required", true}, {"content", {{"application/json", {{"schema", ref("MeshRequest")}}}}}};
    json busy = problem_response("the queue is full (429, Retry-After) or the server is draining (503)");
    if (method == "post" && path == "/v1/meshes")
        return {{"summary", "Mesh synchronously"},
                {"parameters", {format_param()}},
                {"requestBody", req_body},
                {"responses",
                 {{"200", {{"description", "the mesh in the asked format"}, {"content", mesh_content()}}},
                  {"400", problem_response("malformed request")},
                  {"413", problem_response("too large")},
                  {"415", problem_response("not JSON")},
                  {"422", problem_response("no valid domain or density")},
                  {"429", busy},
                  {"503", busy}}}};
    if (method == "post" && path == "/v1/jobs")
        return {{"summary", "Queue a mesh request"},
                {"requestBody", req_body},
                {"responses",
                 {{"202", {{"description", "queued"}, {"headers", {{"Location", {{"schema", {{"type", "string"}}}}}}},
                           {"content", {{"application/json", {{"schema", ref("Job")}}}}}}},
                  {"400", problem_response("malformed request")},
                  {"413", problem_response("too large")},
                  {"415", problem_response("not JSON")},
                  {"429", busy},
                  {"503", busy}}}};
    if (method == "get" && path == "/v1/jobs/{id}")
        return {{"summary", "Job status"},
                {"parameters", {id_param()}},
                {"responses", {{"200", {{"description", "the job"}, {"content", {{"application/json", {{"schema", ref("Job")}}}}}}},
                               {"404", problem_response("unknown or expired job")}}}};
    if (method == "get" && path == "/v1/jobs/{id}/mesh")
        return {{"summary", "The finished mesh"},
                {"parameters", {id_param(), format_param()}},
                {"responses",
                 {{"200", {{"description", "the mesh"}, {"content", mesh_content()}}},
                  {"404", problem_response("unknown job")},
                  {"409", problem_response("not finished")},
                  {"410", problem_response("cancelled or expired")},
                  {"422", problem_response("the job failed")}}}};
    if (method == "delete" && path == "/v1/jobs/{id}")
        return {{"summary", "Cancel a job"},
                {"parameters", {id_param()}},
                {"responses",
                 {{"200", {{"description", "cancelled"}, {"content", {{"application/json", {{"schema", ref("Job")}}}}}}},
                  {"202", {{"description", "cancelling a running job"}, {"content", {{"application/json", {{"schema", ref("Job")}}}}}}},
                  {"404", problem_response("unknown job")}}}};
    if (path == "/healthz" || path == "/livez")
        return {{"summary", "Liveness"}, {"responses", {{"200", {{"description", "alive"}}}}}};
    if (path == "/readyz")
        return {{"summary", "Readiness"},
                {"responses", {{"200", {{"description", "ready"}}}, {"503", problem_response("draining or queue full")}}}};
    if (path == "/metrics")
        return {{"summary", "Prometheus metrics"},
                {"responses", {{"200", {{"description", "text exposition format 0.0.4"}, {"content", {{"text/plain", {{"schema", {{"type", "string"}}}}}}}}}}}};
    if (path == "/v1/openapi.json")
        return {{"summary", "This document"}, {"responses", {{"200", {{"description", "OpenAPI 3"}}}}}};
    return {{"summary", "?"}, {"responses", {{"200", {{"description", "?"}}}}}};
}

}  // namespace

std::string Service::openapi() const {
    json doc;
    doc["openapi"] = "3.0.3";
    doc["info"] = {{"title", "meshd"}, {"version", "0.1.0"},
                   {"description", "Graded triangular meshes of plane domains from a mesh density function."}};
    json paths = json::object();
    for (const Route& r : routes_) paths[r.path][r.method] = operation(r.method, r.path);
    doc["paths"] = paths;
    doc["components"] = {{"schemas", schemas()}};
    return doc.dump();
}

}  // namespace meshd::server
