#pragma once
/// Server configuration: command-line flags, each with an environment variable (12-factor).
/// A flag wins over its variable; both over the default.

#include <cstddef>
#include <string>
#include <vector>

namespace meshd::server {

struct Config {
    std::string host = "127.0.0.1";       ///< --host, MESHD_HOST
    int port = 8080;                      ///< --port, MESHD_PORT (0: any free port)
    int workers = 2;                      ///< --workers, MESHD_WORKERS: meshing threads
    int http_threads = 16;                ///< --http-threads, MESHD_HTTP_THREADS
    /// --probe-port, MESHD_PROBE_PORT: a second listener for /healthz, /livez, /readyz and
    /// /metrics with threads of its own (0: any free port; -1: none).
    int probe_port = -1;
    size_t queue_length = 16;             ///< --queue, MESHD_QUEUE: jobs waiting for a worker
    size_t max_body_bytes = 32u << 20;    ///< --max-body-mb, MESHD_MAX_BODY_MB
    size_t max_points = 5'000'000;        ///< --max-points, MESHD_MAX_POINTS: per job
    double job_timeout_s = 300;           ///< --job-timeout-s, MESHD_JOB_TIMEOUT_S: wall time per job
    double job_ttl_s = 900;               ///< --job-ttl-s, MESHD_JOB_TTL_S: finished jobs kept this long
    size_t result_memory_bytes = 1u << 30;///< --result-memory-mb, MESHD_RESULT_MEMORY_MB
    /// --memory-budget-mb, MESHD_MEMORY_BUDGET_MB: the forecast peaks of running jobs together
    /// (core::peak_bytes_for); a job waits until its own fits, one that never fits gets 413.
    size_t memory_budget_bytes = size_t{1536} << 20;
    size_t max_finished_jobs = 10000;     ///< --max-finished-jobs, MESHD_MAX_FINISHED_JOBS: records kept, oldest dropped first
    double drain_s = 30;                  ///< --drain-s, MESHD_DRAIN_S: grace on SIGTERM
    /// --store, MESHD_STORE: where asynchronous jobs live: "memory" (default: this process)
    /// or redis://[:password@]host[:port][/db] or unix:///path[?db=N] (shared by replicas).
    std::string store = "memory";
    /// MESHD_STORE_PASSWORD only (never a flag, never logged): overrides the URL's password.
    std::string store_password;
    /// --lease-s, MESHD_LEASE_S: a running job's lease in a shared store; a job whose
    /// replica stops renewing it for this long is run again by another replica.
    double lease_s = 10;
    /// --api-keys, MESHD_API_KEYS: a file of hashed API keys (access.hpp); none: open.
    std::string api_keys_file;
    /// --ui, MESHD_UI: the web page at / and its files under /ui/ ("off" for an API-only
    /// deployment: both then answer 404).
    bool ui = true;
    std::string log_level = "info";       ///< --log-level, MESHD_LOG_LEVEL
    bool log_json = false;                ///< --log-json, MESHD_LOG_JSON=1
};

/// Parses flags over environment over defaults. Throws std::invalid_argument with a message
/// naming the flag. Sets `help` when --help was given.
Config parse_config(const std::vector<std::string>& args, bool& help);

/// The --help text.
std::string help_text();

}  // namespace meshd::server
