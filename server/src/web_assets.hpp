#pragma once
// The web page's files and the examples, built into the binary (server/embed_web.cmake).

#include <cstddef>

namespace meshd::server {

struct WebAsset {
    const char* path;          ///< URL path, "/ui/app.js", "/ui/examples/naca0012.json"
    const char* content_type;
    const unsigned char* data;
    std::size_t size;
};

extern const WebAsset kWebAssets[];
extern const std::size_t kWebAssetCount;

}  // namespace meshd::server
