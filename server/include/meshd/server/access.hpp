#pragma once
// API keys (API.md "Access"): a file of keys stored hashed (SHA-256), named by --api-keys and
// mounted from the same Secret on every replica. A request to /v1/... carries its key as
// `Authorization: Bearer <key>`; the key's id owns the jobs it makes. Each key may carry a
// share of the job queue and a request rate.
//
// The file (JSON):
//   {"keys": [{"id": "ci", "sha256": "<64 hex digits>", "queue_share": 4, "rate_per_s": 20,
//              "burst": 40}, ...]}
// queue_share: the key's jobs not yet finished, at most (0 or absent: no share of its own);
// rate_per_s and burst: a token bucket over all its /v1 requests (absent: unlimited).
// `meshd --hash-key` prints the sha256 of a key read from standard input.

#include <map>
#include <optional>
#include <string>

namespace meshd::server {

struct ApiKey {
    std::string id;
    std::size_t queue_share = 0;  ///< 0: none of its own
    double rate_per_s = 0;        ///< 0: unlimited
    double burst = 0;             ///< bucket size (default: a second's worth, at least 1)
};

class Access {
public:
    /// No keys: every request is let in, as the key "" (an open server).
    Access() = default;
    /// Reads the file; throws std::invalid_argument naming what is wrong (never a key).
    static Access load(const std::string& path);

    bool open() const { return by_hash_.empty(); }
    /// The key whose hash is `sha256(key)`, or nothing.
    const ApiKey* find(const std::string& key) const;
    std::size_t size() const { return by_hash_.size(); }

private:
    std::map<std::string, ApiKey> by_hash_;  ///< lowercase hex digest -> key
};

/// SHA-256 of `text`, in lowercase hex.
std::string sha256_hex(const std::string& text);

}  // namespace meshd::server
