#pragma once
// What the HTTP integration tests share: requests, a client of a ServerProcess, waiting for
// a job to end.

#include <httplib.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "server_process.hpp"
#include "support.hpp"

namespace meshd::test {

inline const std::string& naca_request() {
    static const std::string s = read_file(MESHD_SOURCE_DIR "/examples/naca0012.json");
    return s;
}

// A request that takes a while (about a second or more): a fine uniform square.
inline std::string slow_request(double size = 0.0015) {
    nlohmann::json j = nlohmann::json::parse(R"({"geometry": {"points": {"A": [0,0], "B": [1,0], "C": [1,1], "D": [0,1]},
        "curves": {"b": {"type": "line", "from": "A", "to": "B"}, "r": {"type": "line", "from": "B", "to": "C"},
                   "t": {"type": "line", "from": "C", "to": "D"}, "l": {"type": "line", "from": "D", "to": "A"}},
        "loops": [["b", "r", "t", "l"]]}, "density": {"size": 0.1}})");
    j["density"]["size"] = size;
    return j.dump();
}

inline httplib::Client client(const ServerProcess& s) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_read_timeout(60, 0);
    c.set_write_timeout(60, 0);
    return c;
}

inline nlohmann::ordered_json wait_for_job(httplib::Client& c, const std::string& id, double seconds = 60) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    nlohmann::ordered_json j;
    while (std::chrono::steady_clock::now() < until) {
        auto r = c.Get(("/v1/jobs/" + id).c_str());
        if (!r || r->status != 200) return nlohmann::ordered_json{{"status", "http-" + std::to_string(r ? r->status : -1)}};
        j = nlohmann::ordered_json::parse(r->body);
        if (j["status"] != "queued" && j["status"] != "running") return j;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return j;
}

// Polls until `done` holds, at most `seconds` (a bound for failures, not a timing).
template <class F>
inline bool eventually(F&& done, double seconds = 120) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
}

}  // namespace meshd::test
