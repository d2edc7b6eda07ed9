#pragma once
// The job store in a Redis shared by several replicas (--store redis://...): any replica
// answers for any job, and a job accepted by one is run by whichever has a free worker.
//
// Layout (every key under the hash tag {meshd}, so that a Redis Cluster keeps them in one
// slot and the scripts may touch them together):
//   {meshd}:job:<id>      hash: status, stage, progress, submitted, started, finished (ms
//                         since the epoch), owner, request (the JSON body, until the job
//                         ends), foam, metrics, error, expired, cancel, runs, runner, entry
//   {meshd}:queue         stream of {id}; consumer group "workers", one consumer per replica
//   {meshd}:queued        jobs waiting for a worker, all replicas together (the queue bound)
//   {meshd}:result:<id>   hash of the encoded result (api/stored_result.hpp) in chunks
//                         "0".."n-1", and "n" written last
//   {meshd}:results       sorted set of kept results by finish time; with
//   {meshd}:result_sizes  (id -> bytes) and {meshd}:result_bytes, the result budget
//   {meshd}:finished      sorted set of finished jobs by finish time (their bound and age)
//   {meshd}:active        jobs queued or running; {meshd}:owners the same by API key
//   {meshd}:rate:<key>    an API key's token bucket
//
// Every change of a job's status is one Lua script, so that the status moves once from
// queued to running to a final one, whichever replicas race. A running job holds a lease:
// its stream entry stays pending on the replica's consumer, renewed by a heartbeat
// (XCLAIM ... JUSTID) that also carries stage and progress and brings back cancel requests.
// An entry idle longer than the lease (its replica died) is taken over by another replica
// with XAUTOCLAIM and run again from the start: at least once; meshes are deterministic, so
// a rerun gives the same bytes. A draining replica hands its unfinished jobs back at once
// (their entries made idle past any lease), so nothing waits for a lease to lapse.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "meshd/server/config.hpp"
#include "meshd/server/jobs.hpp"
#include "meshd/server/metrics.hpp"
#include "meshd/server/store.hpp"
#include "redis.hpp"

namespace meshd::server {

class RedisStore : public JobStore {
public:
    /// Connects lazily: an unreachable Redis at start makes the replica unready, not dead.
    RedisStore(const Config& config, JobManager& runner, Metrics& metrics);
    ~RedisStore() override;

    /// Starts claiming jobs for `runner`'s idle workers, and the heartbeat.
    void start();
    /// Draining: claims no more; jobs of this replica that end cancelled from now on (the
    /// runner's drain cancels what is left at its grace's end) are handed back.
    void stop_claiming();
    /// Ends the heartbeat (after the runner has drained).
    void stop();

    Submission submit(const std::string& body, api::MeshRequest request, double parse_s,
                      const std::string& owner, size_t owner_share) override;
    double take_token(const std::string& owner, double rate, double burst) override;
    std::optional<JobInfo> info(const std::string& id) override;
    std::optional<JobMesh> mesh(const std::string& id) override;
    std::optional<JobInfo> cancel(const std::string& id) override;
    bool reachable() override;
    size_t queued() override;
    size_t kept() override;
    std::string describe() const override { return "redis " + endpoint_.describe(); }

    /// This replica's consumer name in the group.
    const std::string& consumer() const { return consumer_; }

private:
    // A job this replica has claimed: queued on the runner or running.
    struct InFlight {
        std::shared_ptr<Job> job;
        std::string entry;
        bool user_cancelled = false;  ///< a DELETE reached it (through the store)
        bool moved = false;           ///< another replica took it over, or it ended elsewhere
    };

    // Connections for the HTTP threads, opened as needed and reused.
    class Pool;

    // A job's end, waiting to be written to the store.
    struct Outcome {
        std::string id, entry;
        JobStatus status;
        std::string bytes, metrics, problem;
        std::chrono::steady_clock::time_point until;  ///< retried until then
    };

    void claim_loop();
    void heartbeat_loop();
    /// Writes the outcomes in order, retrying with backoff while the store is away.
    void writer_loop();
    /// One claim (a lapsed lease first, then a new entry); false when none was found.
    bool claim_one(redis::Connection& c);
    void forget_dead_consumers(redis::Connection& c);
    void start_entry(redis::Connection& c, const std::string& entry, const std::string& id, bool reclaimed);
    /// The worker's end of a claimed job: queues its outcome for the writer thread, or hands
    /// it back; returns the outcome for the metrics.
    std::string finish(Job& job);
    /// Writes a final status (and the result) for job `id`; throws redis::Unavailable.
    void write_outcome(redis::Connection& c, const std::string& id, const std::string& entry, JobStatus status,
                       const std::string& result_bytes, const std::string& metrics, const std::string& error);
    void hand_back(redis::Connection& c, const std::string& id, const std::string& entry);
    void ensure_group(redis::Connection& c);
    /// Runs `f` on a pooled connection, timing it; a lost store becomes StoreUnavailable.
    template <class F>
    auto with_store(const char* op, F&& f);
    /// Runs one of the scripts on job `id` (KEYS[1] its key, ARGV[1] the key prefix, then `args`).
    redis::Reply eval(redis::Connection& c, const std::string& script, const std::string& id,
                      const std::vector<std::string>& args);
    /// The same with another first key (a script about no one job).
    redis::Reply eval_on(redis::Connection& c, const std::string& script, const std::string& first_key,
                         const std::vector<std::string>& args);
    std::string ttl_ms() const;
    long long lease_ms() const;
    /// HMGET of the fields a job's status and mesh answers read.
    std::vector<std::string> info_command(const std::string& id) const;
    std::string key(const std::string& kind, const std::string& id = {}) const;
    /// Sleeps up to `d` unless the store stops meanwhile.
    void pause(std::chrono::milliseconds d);

    const Config& config_;
    JobManager& runner_;
    Metrics& metrics_;
    redis::Endpoint endpoint_;
    std::string consumer_;
    std::unique_ptr<Pool> pool_;

    std::mutex m_;
    std::condition_variable cv_;
    std::map<std::string, InFlight> inflight_;
    std::atomic<bool> claiming_{true};
    std::atomic<bool> stopping_{false};
    bool group_ready_ = false;  ///< under m_
    std::string autoclaim_cursor_ = "0-0";  ///< the claimer thread's
    std::deque<Outcome> outcomes_;
    bool writer_stop_ = false;  ///< under m_
    std::chrono::steady_clock::time_point writer_deadline_;
    std::thread claimer_, heartbeat_, writer_;
};

}  // namespace meshd::server
