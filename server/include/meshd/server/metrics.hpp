#pragma once
/// The service's figures in the Prometheus text exposition format (version 0.0.4).

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace meshd::server {

class Histogram {
public:
    explicit Histogram(std::vector<double> bounds) : bounds_(std::move(bounds)), counts_(bounds_.size() + 1, 0) {}
    void observe(double v);
    void render(std::string& out, const std::string& name, const std::string& labels) const;

private:
    std::vector<double> bounds_;
    std::vector<std::uint64_t> counts_;
    double sum_ = 0;
    std::uint64_t count_ = 0;
};

class Metrics {
public:
    void request(const std::string& route, int status, double seconds);
    void job_finished(const std::string& status, double seconds, std::uint64_t points, std::uint64_t triangles);
    void set_queue(size_t depth, size_t busy);
    /// Job records held: queued, running and finished ones still answerable.
    void set_jobs_kept(size_t kept);
    /// Memory reserved by running jobs (their forecast peaks), jobs waiting for it, and the
    /// budget.
    void set_memory(size_t reserved, size_t waiting, size_t budget);
    /// One round trip to a shared job store: its kind, time, and whether the store answered.
    void store_op(const std::string& op, double seconds, bool ok);
    /// Jobs this replica took from a shared store's queue: "claimed" (new), "reclaimed"
    /// (a lapsed lease or a job handed back), "handed_back" (by this replica's drain).
    void store_event(const std::string& what);
    void set_store_up(bool up);

    std::string render() const;

private:
    mutable std::mutex m_;
    std::map<std::pair<std::string, int>, std::uint64_t> requests_;
    std::map<std::string, Histogram> request_seconds_;
    std::map<std::string, std::uint64_t> jobs_;
    Histogram job_seconds_{{0.01, 0.05, 0.1, 0.5, 1, 5, 10, 30, 60, 300}};
    std::uint64_t points_ = 0, triangles_ = 0;
    size_t queue_depth_ = 0, busy_ = 0, jobs_kept_ = 0;
    size_t memory_reserved_ = 0, memory_waiting_ = 0, memory_budget_ = 0;
    bool shared_store_ = false, store_up_ = true;
    std::map<std::string, Histogram> store_seconds_;
    std::map<std::string, std::uint64_t> store_errors_, store_events_;
};

}  // namespace meshd::server
