#include "meshd/api/problem.hpp"

#include <nlohmann/json.hpp>

namespace meshd::api {

std::string Problem::to_json() const {
    nlohmann::ordered_json j;
    j["type"] = type;
    j["title"] = title;
    j["status"] = status;
    j["detail"] = detail;
    if (!pointer.empty()) j["pointer"] = pointer;
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

RequestError bad_request(std::string kind, std::string title, std::string detail, std::string pointer) {
    return RequestError(Problem{400, "/v1/problems/" + kind, std::move(title), std::move(detail), std::move(pointer)});
}

std::string pointer_token(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

namespace {

std::string pointer_of(const core::Subject& s) {
    using K = core::Subject::Kind;
    std::string p;
    switch (s.kind) {
        case K::None: return "";
        case K::Point: p = "/geometry/points/" + pointer_token(s.name); break;
        case K::Curve: p = "/geometry/curves/" + pointer_token(s.name); break;
        case K::Loop: p = "/geometry/loops/" + std::to_string(s.index); break;
        case K::Embedded: p = "/geometry/embedded/" + std::to_string(s.index); break;
        case K::Density: p = "/density/" + pointer_token(s.name); break;
        case K::Layers: p = "/boundary_layers/" + std::to_string(s.index); break;
    }
    for (const std::string& f : s.field) p += "/" + pointer_token(f);
    return p;
}

const char* title_of(core::GeometryErrorKind k) {
    using K = core::GeometryErrorKind;
    switch (k) {
        case K::DensityExpression: return "Density expression does not parse";
        case K::DensityInvalid: return "Density is not finite and positive";
        case K::DensityMissing: return "Density is missing";
        case K::TooManyPoints: return "Mesh too large";
        default: return "Not a valid domain";
    }
}

}  // namespace

Problem problem_from(const core::GeometryError& e) {
    Problem p;
    p.status = e.kind() == core::GeometryErrorKind::TooManyPoints ? 413 : 422;
    p.type = std::string("/v1/problems/") + core::to_string(e.kind());
    p.title = title_of(e.kind());
    p.detail = e.what();
    for (const core::Subject& s : e.subjects()) {
        // The most specific subject with a place in the request.
        std::string ptr = pointer_of(s);
        if (!ptr.empty()) {
            p.pointer = ptr;
            break;
        }
    }
    if (p.pointer.empty() && e.kind() == core::GeometryErrorKind::TooManyPoints) p.pointer = "/options/max_points";
    return p;
}

namespace {
constexpr const char* kCancelledType = "/v1/problems/cancelled";
}  // namespace

Problem problem_of(std::exception_ptr error, std::string* log) {
    try {
        std::rethrow_exception(error);
    } catch (const RequestError& e) {
        return e.problem();
    } catch (const core::GeometryError& e) {
        return problem_from(e);
    } catch (const core::Cancelled&) {
        return Problem{503, kCancelledType, "Cancelled", "the mesh was cancelled before it was finished", ""};
    } catch (const core::InternalError& e) {
        if (log) *log = e.what();
        return Problem{500, "/v1/problems/internal", "Internal error",
                       "meshd failed on this request (a bug; please report it with the request): " + e.message(), ""};
    } catch (const std::exception& e) {
        if (log) *log = e.what();
        return Problem{500, "/v1/problems/internal", "Internal error",
                       std::string("meshd failed on this request (a bug; please report it with the request): ") +
                           e.what(),
                       ""};
    } catch (...) {
        return Problem{500, "/v1/problems/internal", "Internal error",
                       "meshd failed on this request (a bug; please report it with the request)", ""};
    }
}

bool is_cancellation(const Problem& p) { return p.type == kCancelledType; }

}  // namespace meshd::api
