#include "meshd/server/config.hpp"

#include <cstdlib>
#include <functional>
#include <map>
#include <stdexcept>

#include "meshd/core/mesher.hpp"
#include "redis.hpp"

namespace meshd::server {

namespace {

struct Option {
    const char* flag;
    const char* env;
    const char* help;
    std::function<void(Config&, const std::string&)> set;
};

long long to_int(const std::string& flag, const std::string& v, long long lo, long long hi) {
    size_t used = 0;
    long long x = 0;
    try {
        x = std::stoll(v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v.size() || v.empty() || x < lo || x > hi)
        throw std::invalid_argument(flag + " wants an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got \"" + v + "\"");
    return x;
}

double to_double(const std::string& flag, const std::string& v, double lo) {
    size_t used = 0;
    double x = 0;
    try {
        x = std::stod(v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v.size() || v.empty() || !(x >= lo))
        throw std::invalid_argument(flag + " wants a number >= " + std::to_string(lo) + ", got \"" + v + "\"");
    return x;
}

const std::vector<Option>& options() {
    static const std::vector<Option> opts = {
        {"--host", "MESHD_HOST", "address to bind (default 127.0.0.1)", [](Config& c, const std::string& v) { c.host = v; }},
        {"--port", "MESHD_PORT", "port (default 8080; 0 picks a free one)",
         [](Config& c, const std::string& v) { c.port = static_cast<int>(to_int("--port", v, 0, 65535)); }},
        {"--workers", "MESHD_WORKERS", "meshing threads (default 2)",
         [](Config& c, const std::string& v) { c.workers = static_cast<int>(to_int("--workers", v, 1, 256)); }},
        {"--http-threads", "MESHD_HTTP_THREADS", "HTTP threads (default 16)",
         [](Config& c, const std::string& v) { c.http_threads = static_cast<int>(to_int("--http-threads", v, 1, 1024)); }},
        {"--probe-port", "MESHD_PROBE_PORT", "port for /healthz, /livez, /readyz, /metrics on threads of their own (0: any free one; default: none)",
         [](Config& c, const std::string& v) { c.probe_port = static_cast<int>(to_int("--probe-port", v, -1, 65535)); }},
        {"--queue", "MESHD_QUEUE", "jobs waiting for a worker before 429 (default 16)",
         [](Config& c, const std::string& v) { c.queue_length = static_cast<size_t>(to_int("--queue", v, 0, 100000)); }},
        {"--max-body-mb", "MESHD_MAX_BODY_MB", "largest request body in MiB (default 32)",
         [](Config& c, const std::string& v) { c.max_body_bytes = static_cast<size_t>(to_int("--max-body-mb", v, 1, 4096)) << 20; }},
        {"--max-points", "MESHD_MAX_POINTS", "largest mesh of one job, in points (default 5000000)",
         [](Config& c, const std::string& v) { c.max_points = static_cast<size_t>(
             to_int("--max-points", v, 10, static_cast<long long>(meshd::core::kMaxPointsLimit))); }},
        {"--job-timeout-s", "MESHD_JOB_TIMEOUT_S", "wall time of one job (default 300)",
         [](Config& c, const std::string& v) { c.job_timeout_s = to_double("--job-timeout-s", v, 0.001); }},
        {"--job-ttl-s", "MESHD_JOB_TTL_S", "how long finished jobs are kept (default 900)",
         [](Config& c, const std::string& v) { c.job_ttl_s = to_double("--job-ttl-s", v, 0.0); }},
        {"--result-memory-mb", "MESHD_RESULT_MEMORY_MB", "memory for kept results, oldest evicted first (default 1024)",
         [](Config& c, const std::string& v) { c.result_memory_bytes = static_cast<size_t>(to_int("--result-memory-mb", v, 1, 1 << 20)) << 20; }},
        {"--memory-budget-mb", "MESHD_MEMORY_BUDGET_MB", "memory of running jobs together, by their forecasts (raised as a mesh outgrows its own); larger jobs wait, one larger than this gets 413 (default 1536)",
         [](Config& c, const std::string& v) { c.memory_budget_bytes = static_cast<size_t>(to_int("--memory-budget-mb", v, 16, 1 << 24)) << 20; }},
        {"--max-finished-jobs", "MESHD_MAX_FINISHED_JOBS", "finished jobs kept, oldest dropped first (default 10000)",
         [](Config& c, const std::string& v) { c.max_finished_jobs = static_cast<size_t>(to_int("--max-finished-jobs", v, 1, 10'000'000)); }},
        {"--drain-s", "MESHD_DRAIN_S", "grace for running jobs on SIGTERM (default 30)",
         [](Config& c, const std::string& v) { c.drain_s = to_double("--drain-s", v, 0.0); }},
        {"--store", "MESHD_STORE", "where jobs live: memory (default), or redis://[:password@]host[:port][/db] or unix:///socket[?db=N] shared by replicas (password better in MESHD_STORE_PASSWORD)",
         [](Config& c, const std::string& v) {
             if (v.rfind("rediss://", 0) == 0)
                 throw std::invalid_argument("--store: TLS (rediss://) needs hiredis 1.0 or later, and Debian 12 has 0.14: "
                                             "reach Redis over a private network, a unix socket or a TLS tunnel (stunnel)");
             if (v != "memory") redis::parse_url(v);  // refused here, with its reason, not at the first job
             c.store = v;
         }},
        {"--lease-s", "MESHD_LEASE_S", "a running job's lease in a shared store: its replica silent this long, another runs it (default 10)",
         [](Config& c, const std::string& v) { c.lease_s = to_double("--lease-s", v, 0.05); }},
        {"--api-keys", "MESHD_API_KEYS", "a JSON file of hashed API keys with their queue shares and rates; every /v1 request then needs one (default: none, open)",
         [](Config& c, const std::string& v) { c.api_keys_file = v; }},
        {"--ui", "MESHD_UI", "the web page at / (on or off; default on)",
         [](Config& c, const std::string& v) {
             if (v == "on" || v == "1" || v == "true") c.ui = true;
             else if (v == "off" || v == "0" || v == "false") c.ui = false;
             else throw std::invalid_argument("--ui wants on or off");
         }},
        {"--log-level", "MESHD_LOG_LEVEL", "trace, debug, info, warn, error, off (default info)",
         [](Config& c, const std::string& v) {
             static const std::map<std::string, int> ok{{"trace", 0}, {"debug", 0}, {"info", 0}, {"warn", 0}, {"error", 0}, {"off", 0}};
             if (!ok.count(v)) throw std::invalid_argument("--log-level wants trace, debug, info, warn, error or off");
             c.log_level = v;
         }},
    };
    return opts;
}

}  // namespace

Config parse_config(const std::vector<std::string>& args, bool& help) {
    Config c;
    help = false;
    for (const Option& o : options())
        if (const char* e = std::getenv(o.env)) o.set(c, e);
    if (const char* e = std::getenv("MESHD_LOG_JSON")) c.log_json = std::string(e) == "1" || std::string(e) == "true";
    if (const char* e = std::getenv("MESHD_STORE_PASSWORD")) c.store_password = e;
    for (size_t i = 0; i < args.size(); ++i) {
        std::string a = args[i], value;
        if (a == "--help" || a == "-h") {
            help = true;
            continue;
        }
        if (a == "--log-json") {
            c.log_json = true;
            continue;
        }
        const auto eq = a.find('=');
        bool inline_value = false;
        if (eq != std::string::npos) {
            value = a.substr(eq + 1);
            a = a.substr(0, eq);
            inline_value = true;
        }
        const Option* match = nullptr;
        for (const Option& o : options())
            if (a == o.flag) match = &o;
        if (!match) throw std::invalid_argument("unknown option " + a + " (see --help)");
        if (!inline_value) {
            if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
            value = args[++i];
        }
        match->set(c, value);
    }
    return c;
}

std::string help_text() {
    std::string s =
        "usage: meshd [options]\n"
        "Graded triangular meshes over HTTP (docs/api.md). Every option can also be set by the\n"
        "environment variable shown; a flag wins over its variable.\n\n";
    for (const Option& o : options()) {
        std::string f = std::string("  ") + o.flag + " VALUE ";
        if (f.size() < 24) f.resize(24, ' ');
        s += f + o.help + " [" + o.env + "]\n";
    }
    s += "  --log-json            log as JSON lines [MESHD_LOG_JSON=1]\n"
         "  --openapi             print the OpenAPI 3.0.3 document (as GET /v1/openapi.json) and exit\n"
         "  --hash-key            read an API key from standard input, print its sha256 for --api-keys, exit\n"
         "  --help                this text\n";
    return s;
}

}  // namespace meshd::server
