#pragma once
/// The JSON Schemas of the service's documents (OpenAPI 3.0.3 dialect): the mesh request,
/// the JSON mesh response, its metrics and problems. The request's schema accepts a document
/// exactly when parse_request() does (tests/openapi holds the two to each other with the
/// bad-request catalogue); what it cannot say (a name given twice in one object) is refused
/// by the parser alone.

#include <string>

namespace meshd::api {

/// The `components/schemas` object of an OpenAPI document, as JSON text.
std::string openapi_schemas();

}  // namespace meshd::api
