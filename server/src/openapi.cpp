// GET /v1/openapi.json: the OpenAPI 3 description of the service.

#include <nlohmann/json.hpp>

#include "meshd/api/schema.hpp"
#include "meshd/api/writers.hpp"
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
            {"image/svg+xml", {{"schema", {{"type", "string"}}}}},
            {"application/x-tar", {{"schema", {{"type", "string"}, {"format", "binary"}}}}},
            {"application/x-hdf5", {{"schema", {{"type", "string"}, {"format", "binary"}}}}}};
}

json format_param() {
    json names = json::array();
    for (const api::Format f : api::kFormats) names.push_back(api::format_name(f));
    return {{"name", "format"}, {"in", "query"}, {"required", false},
            {"schema", {{"type", "string"}, {"enum", names}, {"default", "json"}}}};
}

json sizes_param() {
    return {{"name", "sizes"}, {"in", "query"}, {"required", false},
            {"description", "format=json: also the target size at each point (mesh.sizes)"},
            {"schema", {{"type", "boolean"}, {"default", false}}}};
}

json id_param() {
    return {{"name", "id"}, {"in", "path"}, {"required", true}, {"schema", {{"type", "string"}, {"pattern", "^[0-9a-f]+$"}}}};
}

// The job of the asynchronous endpoints; the request, response and problem schemas are
// api's (api/schema.hpp).
json job_schema() {
    return {{"type", "object"},
            {"required", {"id", "status"}},
            {"properties",
             {{"id", {{"type", "string"}}},
              {"status", {{"type", "string"}, {"enum", {"queued", "running", "succeeded", "failed", "cancelled"}}}},
              {"progress", {{"type", "number"}, {"minimum", 0}, {"maximum", 1}}},
              {"stage", {{"type", "string"}}},
              {"submitted_at", {{"type", "string"}, {"format", "date-time"}}},
              {"started_at", {{"type", "string"}, {"format", "date-time"}}},
              {"finished_at", {{"type", "string"}, {"format", "date-time"}}},
              {"expired", {{"type", "boolean"}}},
              {"metrics", ref("Metrics")},
              {"error", ref("Problem")}}}};
}

// The operations, keyed by method and OpenAPI path.
json operation(const std::string& method, const std::string& path) {
    const json req_body = {{"required", true}, {"content", {{"application/json", {{"schema", ref("MeshRequest")}}}}}};
    json busy = problem_response("the queue (or this API key's share of it, or its request rate) is full (429, Retry-After), "
                                 "or the server is draining or its job store unreachable (503, Retry-After)");
    if (method == "post" && path == "/v1/meshes")
        return {{"summary", "Mesh synchronously"},
                {"parameters", {format_param(), sizes_param()}},
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
                {"parameters", {id_param(), format_param(), sizes_param()}},
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
                {"responses", {{"200", {{"description", "ready"}}}, {"503", problem_response("draining, or the job store is unreachable")}}}};
    if (path == "/metrics")
        return {{"summary", "Prometheus metrics"},
                {"responses", {{"200", {{"description", "text exposition format 0.0.4"}, {"content", {{"text/plain", {{"schema", {{"type", "string"}}}}}}}}}}}};
    if (path == "/")
        return {{"summary", "The web page: write or pick a request, mesh it, look at it, download it"},
                {"responses", {{"200", {{"description", "the page"}, {"content", {{"text/html", {{"schema", {{"type", "string"}}}}}}}}}}}};
    if (path == "/v1/openapi.json")
        return {{"summary", "This document"}, {"responses", {{"200", {{"description", "OpenAPI 3"}}}}}};
    return {{"summary", "?"}, {"responses", {{"200", {{"description", "?"}}}}}};
}

// Every /v1 operation: its answers to a missing or unknown API key (on a server with keys), a
// used-up request rate, and a job store that cannot be reached.
json with_access(json op, const std::string& path) {
    if (path.rfind("/v1/", 0) != 0) return op;
    op["security"] = json::array({{{"bearer", json::array()}}, json::object()});
    op["responses"]["401"] = problem_response("no API key (a server started with --api-keys)");
    op["responses"]["403"] = problem_response("an API key this server does not know");
    if (!op["responses"].contains("429")) op["responses"]["429"] = problem_response("this API key's request rate is used up (Retry-After)");
    if (path.rfind("/v1/jobs", 0) == 0 && !op["responses"].contains("503"))
        op["responses"]["503"] = problem_response("the job store cannot be reached (Retry-After)");
    return op;
}

}  // namespace

std::string Service::openapi() const {
    json doc;
    doc["openapi"] = "3.0.3";
    doc["info"] = {{"title", "meshd"}, {"version", "0.1.0"},
                   {"description", "Graded triangular meshes of plane domains from a mesh density function."}};
    json paths = json::object();
    for (const Route& r : routes_) paths[r.path][r.method] = with_access(operation(r.method, r.path), r.path);
    doc["paths"] = paths;
    json schemas = json::parse(api::openapi_schemas());
    schemas["Job"] = job_schema();
    doc["components"] = {{"schemas", schemas},
                         {"securitySchemes", {{"bearer", {{"type", "http"}, {"scheme", "bearer"},
                                                          {"description", "an API key (API.md \"Access\")"}}}}}};
    return doc.dump();
}

}  // namespace meshd::server
