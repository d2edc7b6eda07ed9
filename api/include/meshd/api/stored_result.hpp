#pragma once
/// A finished mesh as bytes, for a job store shared by several replicas: stored once, read
/// back by any replica and written in whatever format is asked (every writer gives the same
/// bytes from the decoded result as from the original).
///
/// Layout (version 2): the magic "MESHDR02", then every field of core::MeshResult in a fixed
/// order, integers little-endian of fixed width, doubles as their IEEE bits, vectors as a
/// 64-bit count then their elements, strings as a 64-bit length then their bytes. About 90
/// bytes per point (29 for the point, 26 for each of its two triangles, 8 for its size).

#include <stdexcept>
#include <string>
#include <string_view>

#include "meshd/core/mesher.hpp"

namespace meshd::api {

/// The bytes are not a stored result of this version (wrong magic, cut short, counts or
/// indices out of range): a store that lost or mixed data.
class StoredResultError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

std::string encode_result(const core::MeshResult& r);

/// Throws StoredResultError; never reads or allocates past what `bytes` can hold.
core::MeshResult decode_result(std::string_view bytes);

}  // namespace meshd::api
