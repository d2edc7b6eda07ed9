#include "meshd/server/access.hpp"

#include <openssl/evp.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace meshd::server {

std::string sha256_hex(const std::string& text) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    if (EVP_Digest(text.data(), text.size(), digest, &n, EVP_sha256(), nullptr) != 1)
        throw std::runtime_error("SHA-256 failed");
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < n; ++i) {
        out += hex[digest[i] >> 4];
        out += hex[digest[i] & 15];
    }
    return out;
}

Access Access::load(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::invalid_argument("--api-keys: cannot read " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(ss.str());
    } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument("--api-keys: " + path + " is not JSON: " + e.what());
    }
    if (!doc.is_object() || !doc.contains("keys") || !doc["keys"].is_array() || doc["keys"].empty())
        throw std::invalid_argument("--api-keys: " + path + " wants {\"keys\": [{\"id\": ..., \"sha256\": ...}, ...]}");
    Access a;
    std::map<std::string, int> ids;
    for (size_t i = 0; i < doc["keys"].size(); ++i) {
        const auto& k = doc["keys"][i];
        const std::string where = "--api-keys: keys[" + std::to_string(i) + "]";
        if (!k.is_object() || !k.contains("id") || !k["id"].is_string() || k["id"].get<std::string>().empty())
            throw std::invalid_argument(where + " needs an \"id\" (a non-empty string)");
        ApiKey key;
        key.id = k["id"];
        if (ids[key.id]++) throw std::invalid_argument(where + ": the id \"" + key.id + "\" is used twice");
        std::string digest = k.value("sha256", "");
        for (char& c : digest) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (digest.size() != 64 || digest.find_first_not_of("0123456789abcdef") != std::string::npos)
            throw std::invalid_argument(where + " (\"" + key.id + "\"): \"sha256\" wants the key's SHA-256 as 64 hex digits (meshd --hash-key)");
        for (const char* field : {"queue_share", "rate_per_s", "burst"})
            if (k.contains(field) && (!k[field].is_number() || k[field].get<double>() < 0))
                throw std::invalid_argument(where + " (\"" + key.id + "\"): \"" + field + "\" wants a number >= 0");
        for (const auto& [name, value] : k.items())
            if (name != "id" && name != "sha256" && name != "queue_share" && name != "rate_per_s" && name != "burst")
                throw std::invalid_argument(where + " (\"" + key.id + "\"): unknown field \"" + name + "\"");
        key.queue_share = k.value("queue_share", std::size_t{0});
        key.rate_per_s = k.value("rate_per_s", 0.0);
        key.burst = k.value("burst", std::max(1.0, key.rate_per_s));
        if (!a.by_hash_.emplace(digest, key).second)
            throw std::invalid_argument(where + " (\"" + key.id + "\"): the same key as another entry");
    }
    return a;
}

const ApiKey* Access::find(const std::string& key) const {
    // The lookup is by digest, so its timing says nothing about the key itself.
    auto it = by_hash_.find(sha256_hex(key));
    return it == by_hash_.end() ? nullptr : &it->second;
}

}  // namespace meshd::server
