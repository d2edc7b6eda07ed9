#pragma once
/// Jobs: a bounded queue feeding a pool of meshing threads, separate from the HTTP threads.
/// Jobs get unguessable ids, can be cancelled while queued or running (a running job stops at
/// the core's next check, well within a second), expire some time after they finish, and
/// their results share a memory budget (the oldest finished results are dropped first).
///
/// Running jobs share a second budget, for the memory meshing takes: once the core has
/// forecast a job's size (before any stage), the job reserves its peak (core::peak_bytes_for)
/// and waits until it fits beside the others; a job whose peak exceeds the whole budget fails
/// with 413. A job's time limit counts the reading and parsing of its request, its run
/// (validation included) and, for a synchronous request, the writing of the answer; not the
/// time it waited in the queue.
///
/// The manager is also the in-memory job store (store.hpp). With a shared store, the store
/// hands the jobs it claims to run() as external jobs: the manager runs them on the same
/// workers and gives them back through their on_finish hook, keeping no record of them.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include <nlohmann/json.hpp>

#include "meshd/core/mesher.hpp"
#include "meshd/server/config.hpp"
#include "meshd/server/metrics.hpp"
#include "meshd/server/store.hpp"

namespace meshd::server {

/// Thrown through the core by a job's observer to end the job with this problem.
struct JobRefused {
    api::Problem problem;
};
struct Job {
    std::string id;
    /// With the server's point limit applied; released when the job has run.
    api::MeshRequest request;
    /// The point limit in force is the server's, not one the request asked for.
    bool server_point_limit = false;
    /// Seconds spent reading and parsing the request: counted in the job's time limit.
    double parse_s = 0.0;
    /// How the mesh is written as format=foam (kept after the request is released).
    api::FoamOptions foam;
    /// The API key's id that made it (empty on an open server).
    std::string owner;
    /// Counted in its owner's share of the queue until it ends (under the manager's m_).
    bool in_owner_share = false;
    std::chrono::system_clock::time_point submitted, started, finished;
    /// For a job of a shared store (run_external): called by the worker once the job has
    /// ended, instead of keeping it in the manager's records. Returns the outcome to count
    /// in the metrics ("succeeded", "failed", "cancelled"; anything else is not counted).
    std::function<std::string(Job&)> on_finish;

    // Written by the worker, read by HTTP threads: under `m`.
    mutable std::mutex m;
    std::condition_variable done_cv;
    JobStatus status = JobStatus::Queued;
    std::string stage = "queued";
    double progress = 0.0;
    std::shared_ptr<const core::MeshResult> result;
    /// The result's metrics object, rendered once when the job ends.
    nlohmann::ordered_json metrics;
    std::optional<api::Problem> error;
    bool expired = false;  ///< result dropped (memory or age); the job record remains a while
    size_t result_bytes = 0;
    /// When the job's time limit ends (set as it starts to run).
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();

    std::atomic<bool> cancel{false};

    bool finished_locked() const {
        return status == JobStatus::Succeeded || status == JobStatus::Failed || status == JobStatus::Cancelled;
    }
};

class JobManager : public JobStore {
public:
    JobManager(const Config& config, Metrics& metrics);
    ~JobManager() override;

    /// Queues the request; nullptr when the queue is full or the manager is draining.
    /// `parse_s`: the time its reading and parsing took, counted in its limit.
    std::shared_ptr<Job> submit(api::MeshRequest request, double parse_s = 0.0, std::string owner = {});
    /// The job, or nullptr (unknown or forgotten).
    std::shared_ptr<Job> find(const std::string& id);
    /// Asks the job to stop; false when unknown.
    bool cancel_job(const std::string& id);

    // JobStore: the jobs in this process's memory.
    Submission submit(const std::string& body, api::MeshRequest request, double parse_s,
                      const std::string& owner, size_t owner_share) override;
    double take_token(const std::string& owner, double rate, double burst) override;
    std::optional<JobInfo> info(const std::string& id) override;
    std::optional<JobMesh> mesh(const std::string& id) override;
    std::optional<JobInfo> cancel(const std::string& id) override;
    bool reachable() override { return true; }
    size_t queued() override;
    size_t kept() override;
    std::string describe() const override { return "memory"; }

    /// Runs a job of a shared store on this manager's workers: `job` has its id and
    /// on_finish set; the server's point limit is applied to `request` as in submit(). False
    /// when draining (the caller keeps the job).
    bool run_external(std::shared_ptr<Job> job, api::MeshRequest request);
    /// Workers neither busy nor promised to a queued job.
    size_t idle_workers() const;
    /// Waits until a worker is idle (or the manager stops), at most `at_most`.
    void wait_idle(std::chrono::milliseconds at_most);
    /// Drops a finished job's record and its result from the store (a synchronous request's
    /// job, once its answer is taken: nobody asks for it again).
    void forget(const std::shared_ptr<Job>& job);

    size_t busy() const;
    bool full() const;
    bool draining() const { return draining_; }

    /// Stops taking jobs; waits up to `grace` for queued and running jobs to end, then
    /// cancels what is left and joins the workers.
    void drain(std::chrono::duration<double> grace);
    /// The same with the grace ending at `until` (a drain whose grace began earlier).
    void drain_until(std::chrono::steady_clock::time_point until);

    /// 128 bits from the system's entropy source, as 32 hex digits: ids cannot be guessed.
    static std::string new_id();
    /// The snapshot of a job the routes answer with.
    static JobInfo info_of(const Job& job);

    /// Waits until `bytes` fit in the memory budget beside the running jobs and reserves them;
    /// `stop` is asked while waiting (Cancelled when it says so). Throws JobRefused (413) when
    /// `bytes` exceed the whole budget.
    void reserve_memory(size_t bytes, const std::function<bool()>& stop);
    void release_memory(size_t bytes);
    /// A running job's reservation grows from `from` to `to` bytes (its mesh outgrew the
    /// forecast, now at `points`): at once, even past the budget beside the other running
    /// jobs (jobs waiting for memory wait longer). Throws JobRefused (413) when `to` exceeds the
    /// whole budget: the job stops.
    void grow_memory(size_t from, size_t to, double points);

private:
    void work();
    void run(const std::shared_ptr<Job>& job);
    void housekeeping();
    /// With m_ held: the job's result leaves the store and its memory budget.
    void release_result_locked(Job& job);
    /// Gives the job its request, with the server's point limit unless it asks for fewer.
    void take_request(Job& job, api::MeshRequest request) const;

    const Config& config_;
    Metrics& metrics_;
    mutable std::mutex m_;
    std::condition_variable cv_;
    std::condition_variable idle_cv_;
    std::deque<std::shared_ptr<Job>> queue_;
    std::set<std::shared_ptr<Job>> running_;
    std::map<std::string, size_t> owner_active_;  ///< jobs queued or running, by owner
    /// With m_ held: the job no longer counts in its owner's share.
    void leave_owner_share_locked(Job& job);
    struct Bucket {
        double tokens = 0;
        std::chrono::steady_clock::time_point at;
    };
    std::mutex buckets_m_;
    std::map<std::string, Bucket> buckets_;
    std::map<std::string, std::shared_ptr<Job>> jobs_;
    std::deque<std::shared_ptr<Job>> finished_order_;  // for eviction, oldest first
    size_t result_bytes_ = 0;
    size_t busy_ = 0;
    bool stop_ = false;
    std::atomic<bool> draining_{false};
    std::vector<std::thread> workers_;

    std::mutex memory_m_;
    std::condition_variable memory_cv_;
    size_t memory_reserved_ = 0, memory_waiting_ = 0;
};

}  // namespace meshd::server
