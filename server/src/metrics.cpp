#include "meshd/server/metrics.hpp"

#include <sys/resource.h>

#include <cstdio>

namespace meshd::server {

namespace {

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

const std::vector<double> kRequestBounds{0.001, 0.005, 0.01, 0.05, 0.1, 0.5, 1, 5, 10, 60};

}  // namespace

void Histogram::observe(double v) {
    size_t i = 0;
    while (i < bounds_.size() && v > bounds_[i]) ++i;
    ++counts_[i];
    sum_ += v;
    ++count_;
}

void Histogram::render(std::string& out, const std::string& name, const std::string& labels) const {
    const std::string sep = labels.empty() ? "" : ",";
    std::uint64_t acc = 0;
    for (size_t i = 0; i < bounds_.size(); ++i) {
        acc += counts_[i];
        out += name + "_bucket{" + labels + sep + "le=\"" + num(bounds_[i]) + "\"} " + std::to_string(acc) + "\n";
    }
    acc += counts_.back();
    out += name + "_bucket{" + labels + sep + "le=\"+Inf\"} " + std::to_string(acc) + "\n";
    const std::string l = labels.empty() ? "" : "{" + labels + "}";
    out += name + "_sum" + l + " " + num(sum_) + "\n";
    out += name + "_count" + l + " " + std::to_string(count_) + "\n";
}

void Metrics::request(const std::string& route, int status, double seconds) {
    std::lock_guard<std::mutex> lock(m_);
    ++requests_[{route, status}];
    request_seconds_.try_emplace(route, kRequestBounds).first->second.observe(seconds);
}

void Metrics::job_finished(const std::string& status, double seconds, std::uint64_t points, std::uint64_t triangles) {
    std::lock_guard<std::mutex> lock(m_);
    ++jobs_[status];
    job_seconds_.observe(seconds);
    points_ += points;
    triangles_ += triangles;
}

void Metrics::set_jobs_kept(size_t kept) {
    std::lock_guard<std::mutex> lock(m_);
    jobs_kept_ = kept;
}

void Metrics::set_queue(size_t depth, size_t busy) {
    std::lock_guard<std::mutex> lock(m_);
    queue_depth_ = depth;
    busy_ = busy;
}

void Metrics::set_memory(size_t reserved, size_t waiting, size_t budget) {
    std::lock_guard<std::mutex> lock(m_);
    memory_reserved_ = reserved;
    memory_waiting_ = waiting;
    memory_budget_ = budget;
}

const std::vector<double> kStoreBounds{0.0001, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.05, 0.1, 0.5, 1};

void Metrics::store_op(const std::string& op, double seconds, bool ok) {
    std::lock_guard<std::mutex> lock(m_);
    shared_store_ = true;
    if (ok) store_seconds_.try_emplace(op, kStoreBounds).first->second.observe(seconds);
    else ++store_errors_[op];
}

void Metrics::store_event(const std::string& what) {
    std::lock_guard<std::mutex> lock(m_);
    shared_store_ = true;
    ++store_events_[what];
}

void Metrics::set_store_up(bool up) {
    std::lock_guard<std::mutex> lock(m_);
    shared_store_ = true;
    store_up_ = up;
}

std::string Metrics::render() const {
    std::lock_guard<std::mutex> lock(m_);
    std::string o;
    o += "# HELP meshd_http_requests_total HTTP requests by route and status.\n# TYPE meshd_http_requests_total counter\n";
    for (const auto& [k, v] : requests_)
        o += "meshd_http_requests_total{route=\"" + k.first + "\",status=\"" + std::to_string(k.second) + "\"} " + std::to_string(v) + "\n";
    o += "# HELP meshd_http_request_duration_seconds Time to answer a request.\n# TYPE meshd_http_request_duration_seconds histogram\n";
    for (const auto& [route, h] : request_seconds_) h.render(o, "meshd_http_request_duration_seconds", "route=\"" + route + "\"");
    o += "# HELP meshd_jobs_total Jobs by final status.\n# TYPE meshd_jobs_total counter\n";
    for (const char* s : {"succeeded", "failed", "cancelled"}) {
        auto it = jobs_.find(s);
        o += std::string("meshd_jobs_total{status=\"") + s + "\"} " + std::to_string(it == jobs_.end() ? 0 : it->second) + "\n";
    }
    o += "# HELP meshd_job_duration_seconds Time from start to end of a job.\n# TYPE meshd_job_duration_seconds histogram\n";
    job_seconds_.render(o, "meshd_job_duration_seconds", "");
    o += "# HELP meshd_queue_depth Jobs waiting for a worker.\n# TYPE meshd_queue_depth gauge\nmeshd_queue_depth " + std::to_string(queue_depth_) + "\n";
    o += "# HELP meshd_workers_busy Workers meshing now.\n# TYPE meshd_workers_busy gauge\nmeshd_workers_busy " + std::to_string(busy_) + "\n";
    o += "# HELP meshd_jobs_kept Job records held (queued, running, finished and still answerable).\n"
         "# TYPE meshd_jobs_kept gauge\nmeshd_jobs_kept " + std::to_string(jobs_kept_) + "\n";
    o += "# HELP meshd_memory_reserved_bytes Memory reserved by running jobs (their forecast peaks, grown with a mesh that outgrew its forecast).\n"
         "# TYPE meshd_memory_reserved_bytes gauge\nmeshd_memory_reserved_bytes " + std::to_string(memory_reserved_) + "\n";
    o += "# HELP meshd_memory_budget_bytes Memory running jobs may reserve together.\n"
         "# TYPE meshd_memory_budget_bytes gauge\nmeshd_memory_budget_bytes " + std::to_string(memory_budget_) + "\n";
    o += "# HELP meshd_jobs_waiting_for_memory Jobs started but waiting for their memory.\n"
         "# TYPE meshd_jobs_waiting_for_memory gauge\nmeshd_jobs_waiting_for_memory " + std::to_string(memory_waiting_) + "\n";
    if (shared_store_) {
        o += "# HELP meshd_store_up Whether the shared job store answered last time.\n# TYPE meshd_store_up gauge\nmeshd_store_up " +
             std::string(store_up_ ? "1" : "0") + "\n";
        o += "# HELP meshd_store_operation_duration_seconds Round trips to the shared job store, by kind.\n"
             "# TYPE meshd_store_operation_duration_seconds histogram\n";
        for (const auto& [op, h] : store_seconds_) h.render(o, "meshd_store_operation_duration_seconds", "op=\"" + op + "\"");
        o += "# HELP meshd_store_errors_total Round trips to the shared job store that failed, by kind.\n"
             "# TYPE meshd_store_errors_total counter\n";
        for (const auto& [op, n] : store_errors_) o += "meshd_store_errors_total{op=\"" + op + "\"} " + std::to_string(n) + "\n";
        o += "# HELP meshd_store_jobs_total Jobs taken from or given back to the shared queue by this replica.\n"
             "# TYPE meshd_store_jobs_total counter\n";
        for (const char* e : {"claimed", "reclaimed", "handed_back"}) {
            auto it = store_events_.find(e);
            o += std::string("meshd_store_jobs_total{event=\"") + e + "\"} " + std::to_string(it == store_events_.end() ? 0 : it->second) + "\n";
        }
    }
    // The process's CPU time, user and system, every thread's: with the requests' count, what
    // one answer costs the machine (scripts/load.sh reports it per request).
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) == 0) {
        const double cpu = static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
                           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
        char b[32];
        std::snprintf(b, sizeof b, "%.6f", cpu);
        o += "# HELP process_cpu_seconds_total CPU time of the server process (user and system), in seconds.\n"
             "# TYPE process_cpu_seconds_total counter\nprocess_cpu_seconds_total " + std::string(b) + "\n";
    }
    o += "# HELP meshd_points_total Points of all meshes made.\n# TYPE meshd_points_total counter\nmeshd_points_total " + std::to_string(points_) + "\n";
    o += "# HELP meshd_triangles_total Triangles of all meshes made.\n# TYPE meshd_triangles_total counter\nmeshd_triangles_total " + std::to_string(triangles_) + "\n";
    return o;
}

}  // namespace meshd::server
