#pragma once
/// The mesh request of docs/api.md: JSON in, core types out. Every field is checked for type and
/// range; unknown fields are refused (a typo must never change a mesh silently); errors name
/// the field by its JSON pointer.

#include <optional>
#include <string_view>

#include "meshd/api/writers.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::api {

struct MeshRequest {
    core::DomainSpec geometry;
    core::DensitySpec density;
    core::MeshOptions options;  ///< max_points 0 when the request gives none
    std::optional<double> timeout_s;
    /// options.patch_types and options.slab_thickness, for format=foam.
    FoamOptions foam;
};

/// Limits of the parser itself.
inline constexpr int kMaxJsonDepth = 64;
/// Longest tag (or curve name used as a tag), in characters.
inline constexpr size_t kMaxTagCharacters = 256;

/// Parses and checks the request's shape. Throws RequestError (400).
MeshRequest parse_request(std::string_view body);

}  // namespace meshd::api
