#pragma once
/// The mesh request of API.md: JSON in, core types out. Every field is checked for type and
/// range; unknown fields are refused (a typo must never change a mesh silently); errors name
/// the field by its JSON pointer.

#include <optional>
#include <string_view>

#include "meshd/core/density.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::api {

struct MeshRequest {
    core::DomainSpec geometry;
    core::DensitySpec density;
    core::MeshOptions options;  ///< max_points 0 when the request gives none
    std::optional<double> timeout_s;
};

/// Limits of the parser itself.
inline constexpr int kMaxJsonDepth = 64;

/// Parses and checks the request's shape. Throws RequestError (400).
MeshRequest parse_request(std::string_view body);

/// From a parsed request to the finished mesh: builds the domain and the density, refuses
/// what is not supported, meshes. The one path of the server and the CLI. Throws
/// RequestError, core::GeometryError (see problem_from), core::Cancelled.
core::MeshResult run_request(const MeshRequest& request, core::Observer* observer = nullptr);

}  // namespace meshd::api
