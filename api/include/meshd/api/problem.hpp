#pragma once
/// Problems (RFC 9457) for everything a request can get wrong: the shape of the request
/// (400), its size (413), its content type (415), a domain or density that is not valid
/// (422). Each carries the JSON pointer of the culprit when there is one.

#include <exception>
#include <stdexcept>
#include <string>

#include "meshd/core/errors.hpp"

namespace meshd::api {

struct Problem {
    int status = 400;
    std::string type;     ///< a URI reference naming the kind: /v1/problems/<kind>
    std::string title;    ///< short, the same for every problem of this kind
    std::string detail;   ///< what is wrong with this request
    std::string pointer;  ///< JSON pointer into the request ("" when none)

    /// The problem as application/problem+json.
    std::string to_json() const;
};

/// Thrown by the request layer; the server answers with the problem.
class RequestError : public std::runtime_error {
public:
    explicit RequestError(Problem p) : std::runtime_error(p.detail), problem_(std::move(p)) {}
    const Problem& problem() const { return problem_; }

private:
    Problem problem_;
};

/// Builds a 400 problem of the given kind.
RequestError bad_request(std::string kind, std::string title, std::string detail, std::string pointer);

/// The 422 (or 413 for too many points) problem for a core error, with the pointer of the
/// request field that holds the named curve, loop, point or density entry.
Problem problem_from(const core::GeometryError& e);

/// The problem for whatever meshing a request threw: a RequestError's own problem, a
/// GeometryError's (problem_from), Cancelled as the "cancelled" problem (is_cancellation),
/// anything else a 500 that asks for the request to be reported (a bug). A 500's detail never
/// holds meshd's source locations; `log`, when given, receives the full message for the
/// server's log.
Problem problem_of(std::exception_ptr error, std::string* log = nullptr);
bool is_cancellation(const Problem& p);

/// A JSON pointer token (RFC 6901): "~" -> "~0", "/" -> "~1".
std::string pointer_token(const std::string& s);

}  // namespace meshd::api
