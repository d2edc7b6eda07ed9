#pragma once
/// The job store: where the asynchronous jobs of POST /v1/jobs live, as the HTTP layer sees
/// them. Two implementations: the JobManager itself (in this process's memory: the default,
/// nothing to install) and RedisStore (redis_store.hpp: jobs, queue and results in a Redis
/// shared by several replicas, so that any replica answers for any job). The routes do not
/// know which one runs.

#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include "meshd/api/writers.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::server {

enum class JobStatus { Queued, Running, Succeeded, Failed, Cancelled };
const char* to_string(JobStatus s);
std::optional<JobStatus> parse_status(const std::string& s);
inline bool is_final(JobStatus s) {
    return s == JobStatus::Succeeded || s == JobStatus::Failed || s == JobStatus::Cancelled;
}

/// What a status request answers: a snapshot of one job.
struct JobInfo {
    std::string id;
    JobStatus status = JobStatus::Queued;
    std::string stage = "queued";
    double progress = 0.0;
    std::chrono::system_clock::time_point submitted, started, finished;
    /// The result's metrics object as JSON text (when succeeded).
    std::string metrics;
    std::optional<api::Problem> error;
    /// Succeeded, but the result was dropped (memory budget or age).
    bool expired = false;
    /// Who made it: the id of the API key, or empty on an open server.
    std::string owner;
};

/// A finished job's mesh, ready to be written in any format.
struct JobMesh {
    JobInfo info;
    std::shared_ptr<const core::MeshResult> result;  ///< null unless succeeded and kept
    api::FoamOptions foam;
};

/// A request the store has accepted, or why not.
struct Submission {
    enum class Refusal { None, QueueFull, Draining, OwnerShare };
    Refusal refusal = Refusal::None;
    std::string id;
};

/// The store cannot be reached now (the answer is 503 with Retry-After).
class StoreUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class JobStore {
public:
    virtual ~JobStore() = default;

    /// Queues a parsed request. `body` is its JSON text (a shared store keeps it for the
    /// replica that will run it); `parse_s` the time reading and parsing took. `owner`: the
    /// API key's id; with `owner_share` > 0, refused (OwnerShare) while that many of the
    /// owner's jobs are queued or running.
    virtual Submission submit(const std::string& body, api::MeshRequest request, double parse_s,
                              const std::string& owner, size_t owner_share) = 0;
    /// The job, or nothing when unknown or forgotten.
    virtual std::optional<JobInfo> info(const std::string& id) = 0;
    /// The job with its result, or nothing when unknown.
    virtual std::optional<JobMesh> mesh(const std::string& id) = 0;
    /// Asks the job to stop (a running job stops within a second, wherever it runs); the job
    /// as it is afterwards, or nothing when unknown.
    virtual std::optional<JobInfo> cancel(const std::string& id) = 0;
    /// A token bucket per owner (`rate` per second, `burst` at most), shared by the replicas
    /// of a shared store: 0 when the request may go on, else the seconds until it may.
    virtual double take_token(const std::string& owner, double rate, double burst) = 0;
    /// Whether this store can take work now (always, in memory).
    virtual bool reachable() = 0;
    /// Jobs waiting for a worker (across replicas for a shared store).
    virtual size_t queued() = 0;
    /// Job records held: queued, running, and finished ones still answerable.
    virtual size_t kept() = 0;
    /// A name for logs and metrics: "memory" or the store's address without secrets.
    virtual std::string describe() const = 0;
};

}  // namespace meshd::server
