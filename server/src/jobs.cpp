#include "meshd/server/jobs.hpp"

#include <spdlog/spdlog.h>

#include <fstream>
#include <random>

#include "meshd/api/writers.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::server {

const char* to_string(JobStatus s) {
    switch (s) {
        case JobStatus::Queued: return "queued";
        case JobStatus::Running: return "running";
        case JobStatus::Succeeded: return "succeeded";
        case JobStatus::Failed: return "failed";
        case JobStatus::Cancelled: return "cancelled";
    }
    return "?";
}

std::optional<JobStatus> parse_status(const std::string& s) {
    for (JobStatus v : {JobStatus::Queued, JobStatus::Running, JobStatus::Succeeded, JobStatus::Failed, JobStatus::Cancelled})
        if (s == to_string(v)) return v;
    return std::nullopt;
}

namespace {

// Progress, cancellation and the memory reservation of one job, as the core sees them.
class JobObserver : public core::Observer {
public:
    JobObserver(JobManager& manager, Job& job, std::chrono::steady_clock::time_point deadline)
        : manager_(manager), job_(job), deadline_(deadline) {}
    ~JobObserver() override {
        if (reserved_) manager_.release_memory(reserved_);
    }
    void on_progress(core::Stage stage, double fraction) override {
        std::lock_guard<std::mutex> lock(job_.m);
        job_.stage = core::to_string(stage);
        job_.progress = fraction;
    }
    bool should_stop() override {
        if (job_.cancel.load()) return true;
        if (std::chrono::steady_clock::now() > deadline_) {
            timed_out_ = true;
            return true;
        }
        return false;
    }
    double seconds_left() override {
        return std::chrono::duration<double>(deadline_ - std::chrono::steady_clock::now()).count();
    }
    void on_forecast(double points, std::size_t peak_bytes) override {
        if (reserved_ > 0) {
            // The mesh outgrew its forecast: the reservation follows it, without waiting (the
            // run holds its memory; two such runs waiting on each other would wait to their
            // limits), and a run that would need more than the whole budget stops here.
            if (peak_bytes > reserved_) {
                manager_.grow_memory(reserved_, peak_bytes, points);
                reserved_ = peak_bytes;
            }
            return;
        }
        {
            std::lock_guard<std::mutex> lock(job_.m);
            job_.stage = "waiting for memory";
        }
        manager_.reserve_memory(peak_bytes, [this] { return should_stop(); });
        reserved_ = peak_bytes;
    }
    bool timed_out() const { return timed_out_; }

private:
    JobManager& manager_;
    Job& job_;
    std::chrono::steady_clock::time_point deadline_;
    bool timed_out_ = false;
    size_t reserved_ = 0;
};

std::string megabytes(size_t bytes) { return std::to_string((bytes + (size_t{1} << 20) - 1) >> 20) + " MB"; }

// 413 memory-budget: `need` says what the mesh needs while meshing (a forecast, or what it grew to).
JobRefused over_budget(const std::string& need, size_t budget) {
    return JobRefused{api::Problem{413, "/v1/problems/memory-budget", "Mesh too large for this server",
                                   need + " while meshing, more than the server's budget of " + megabytes(budget) +
                                       " (--memory-budget-mb): ask for fewer points",
                                   "/density"}};
}

}  // namespace

JobManager::JobManager(const Config& config, Metrics& metrics) : config_(config), metrics_(metrics) {
    metrics_.set_memory(0, 0, config.memory_budget_bytes);
    for (int i = 0; i < config.workers; ++i) workers_.emplace_back([this] { work(); });
}

JobManager::~JobManager() { drain(std::chrono::duration<double>(0)); }

std::string JobManager::new_id() {
    // 128 bits from the system's entropy source: ids cannot be guessed.
    static thread_local std::random_device rd;
    std::string id;
    static const char* hex = "0123456789abcdef";
    for (int i = 0; i < 4; ++i) {
        std::uint32_t v = rd();
        for (int k = 0; k < 8; ++k) {
            id += hex[v & 15u];
            v >>= 4;
        }
    }
    return id;
}

void JobManager::take_request(Job& job, api::MeshRequest request) const {
    job.foam = request.foam;
    // The server's point limit, unless the request asks for fewer.
    const size_t cap = config_.max_points;
    size_t& asked = request.options.max_points;
    job.server_point_limit = asked == 0 || asked > cap;
    asked = job.server_point_limit ? cap : asked;
    job.request = std::move(request);
}

std::shared_ptr<Job> JobManager::submit(api::MeshRequest request, double parse_s, std::string owner) {
    auto job = std::make_shared<Job>();
    job->parse_s = parse_s;
    job->owner = std::move(owner);
    take_request(*job, std::move(request));
    job->submitted = std::chrono::system_clock::now();
    {
        std::lock_guard<std::mutex> lock(m_);
        // Room for one job per worker plus the waiting queue.
        if (draining_ || stop_ || queue_.size() + busy_ >= config_.queue_length + static_cast<size_t>(config_.workers))
            return nullptr;
        do job->id = new_id();
        while (jobs_.count(job->id));
        jobs_[job->id] = job;
        queue_.push_back(job);
        metrics_.set_queue(queue_.size(), busy_);
        metrics_.set_jobs_kept(jobs_.size());
    }
    cv_.notify_one();
    return job;
}

std::shared_ptr<Job> JobManager::find(const std::string& id) {
    housekeeping();
    std::lock_guard<std::mutex> lock(m_);
    auto it = jobs_.find(id);
    return it == jobs_.end() ? nullptr : it->second;
}

bool JobManager::cancel_job(const std::string& id) {
    std::shared_ptr<Job> job = find(id);
    if (!job) return false;
    job->cancel = true;
    bool now_cancelled = false;
    {
        std::lock_guard<std::mutex> lock(m_);
        // A queued job is cancelled at once; a running one by its worker.
        for (auto it = queue_.begin(); it != queue_.end(); ++it) {
            if (*it == job) {
                queue_.erase(it);
                now_cancelled = true;
                break;
            }
        }
        metrics_.set_queue(queue_.size(), busy_);
    }
    if (now_cancelled) {
        {
            std::lock_guard<std::mutex> lock(job->m);
            job->status = JobStatus::Cancelled;
            job->stage = "cancelled";
            job->finished = std::chrono::system_clock::now();
        }
        {
            std::lock_guard<std::mutex> lock(m_);
            finished_order_.push_back(job);
            leave_owner_share_locked(*job);
        }
        job->done_cv.notify_all();
        metrics_.job_finished("cancelled", 0.0, 0, 0);
        spdlog::info("job {} cancelled while queued", job->id);
    }
    return true;
}

void JobManager::forget(const std::shared_ptr<Job>& job) {
    std::lock_guard<std::mutex> lock(m_);
    release_result_locked(*job);
    jobs_.erase(job->id);
    // It has just finished: look from the newest end.
    for (auto it = finished_order_.rbegin(); it != finished_order_.rend(); ++it) {
        if (*it == job) {
            finished_order_.erase(std::next(it).base());
            break;
        }
    }
    metrics_.set_jobs_kept(jobs_.size());
}

size_t JobManager::queued() {
    std::lock_guard<std::mutex> lock(m_);
    return queue_.size();
}

size_t JobManager::kept() {
    housekeeping();
    std::lock_guard<std::mutex> lock(m_);
    return jobs_.size();
}

Submission JobManager::submit(const std::string&, api::MeshRequest request, double parse_s, const std::string& owner,
                              size_t owner_share) {
    if (owner_share > 0) {
        std::lock_guard<std::mutex> lock(m_);
        auto it = owner_active_.find(owner);
        if (it != owner_active_.end() && it->second >= owner_share) return {Submission::Refusal::OwnerShare, ""};
    }
    auto job = submit(std::move(request), parse_s, owner);
    if (!job) return {draining_ ? Submission::Refusal::Draining : Submission::Refusal::QueueFull, ""};
    {
        std::lock_guard<std::mutex> lock(m_);
        bool ended;
        {
            std::lock_guard<std::mutex> jl(job->m);
            ended = job->finished_locked();
        }
        if (!ended) {
            ++owner_active_[owner];
            job->in_owner_share = true;
        }
    }
    return {Submission::Refusal::None, job->id};
}

void JobManager::leave_owner_share_locked(Job& job) {
    if (!job.in_owner_share) return;
    job.in_owner_share = false;
    auto it = owner_active_.find(job.owner);
    if (it != owner_active_.end() && --it->second == 0) owner_active_.erase(it);
}

double JobManager::take_token(const std::string& owner, double rate, double burst) {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(buckets_m_);
    auto [it, fresh] = buckets_.try_emplace(owner, Bucket{burst, now});
    Bucket& b = it->second;
    if (!fresh) b.tokens = std::min(burst, b.tokens + std::chrono::duration<double>(now - b.at).count() * rate);
    b.at = now;
    if (b.tokens >= 1) {
        b.tokens -= 1;
        return 0;
    }
    return (1 - b.tokens) / rate;
}

JobInfo JobManager::info_of(const Job& j) {
    std::lock_guard<std::mutex> lock(j.m);
    JobInfo i;
    i.id = j.id;
    i.status = j.status;
    i.stage = j.stage;
    i.progress = j.progress;
    i.submitted = j.submitted;
    i.started = j.started;
    i.finished = j.finished;
    if (j.status == JobStatus::Succeeded && j.result) i.metrics = j.metrics.dump();
    i.error = j.error;
    i.expired = j.status == JobStatus::Succeeded && !j.result;
    i.owner = j.owner;
    return i;
}

std::optional<JobInfo> JobManager::info(const std::string& id) {
    auto job = find(id);
    if (!job) return std::nullopt;
    return info_of(*job);
}

std::optional<JobMesh> JobManager::mesh(const std::string& id) {
    auto job = find(id);
    if (!job) return std::nullopt;
    JobMesh out;
    out.info = info_of(*job);
    std::lock_guard<std::mutex> lock(job->m);
    out.result = job->status == JobStatus::Succeeded ? job->result : nullptr;
    out.foam = job->foam;
    return out;
}

std::optional<JobInfo> JobManager::cancel(const std::string& id) {
    if (!cancel_job(id)) return std::nullopt;
    return info(id);
}

bool JobManager::run_external(std::shared_ptr<Job> job, api::MeshRequest request) {
    take_request(*job, std::move(request));
    {
        std::lock_guard<std::mutex> lock(m_);
        if (draining_ || stop_) return false;
        job->submitted = job->submitted.time_since_epoch().count() ? job->submitted : std::chrono::system_clock::now();
        queue_.push_back(std::move(job));
        metrics_.set_queue(queue_.size(), busy_);
    }
    cv_.notify_one();
    return true;
}

size_t JobManager::idle_workers() const {
    std::lock_guard<std::mutex> lock(m_);
    const size_t taken = busy_ + queue_.size();
    const auto workers = static_cast<size_t>(config_.workers);
    return taken >= workers ? 0 : workers - taken;
}

void JobManager::wait_idle(std::chrono::milliseconds at_most) {
    std::unique_lock<std::mutex> lock(m_);
    idle_cv_.wait_for(lock, at_most, [&] { return stop_ || busy_ + queue_.size() < static_cast<size_t>(config_.workers); });
}

size_t JobManager::busy() const {
    std::lock_guard<std::mutex> lock(m_);
    return busy_;
}

bool JobManager::full() const {
    std::lock_guard<std::mutex> lock(m_);
    return queue_.size() + busy_ >= config_.queue_length + static_cast<size_t>(config_.workers);
}

void JobManager::work() {
    for (;;) {
        std::shared_ptr<Job> job;
        {
            std::unique_lock<std::mutex> lock(m_);
            cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return;  // stop_ and nothing left
            job = queue_.front();
            queue_.pop_front();
            running_.insert(job);
            ++busy_;
            metrics_.set_queue(queue_.size(), busy_);
        }
        run(job);
        {
            std::lock_guard<std::mutex> lock(m_);
            --busy_;
            running_.erase(job);
            metrics_.set_queue(queue_.size(), busy_);
        }
        cv_.notify_all();
        idle_cv_.notify_all();
        housekeeping();
    }
}

void JobManager::run(const std::shared_ptr<Job>& job) {
    const auto t0 = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> lock(job->m);
        job->status = JobStatus::Running;
        job->stage = "boundary";
        job->started = std::chrono::system_clock::now();
    }
    double limit = config_.job_timeout_s;
    if (job->request.timeout_s) limit = std::min(limit, *job->request.timeout_s);
    // The time the request took to read and parse is part of the limit.
    const auto deadline =
        t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(limit - job->parse_s));
    {
        std::lock_guard<std::mutex> lock(job->m);
        job->deadline = deadline;
    }
    std::shared_ptr<const core::MeshResult> result;
    std::optional<api::Problem> error;
    JobStatus status = JobStatus::Succeeded;
    if (job->cancel) {
        status = JobStatus::Cancelled;
    } else {
        JobObserver obs(*this, *job, deadline);
        try {
            const api::MeshRequest& req = job->request;
            result = std::make_shared<const core::MeshResult>(
                core::generate_mesh(req.geometry, req.density, req.options, &obs));
        } catch (const JobRefused& refused) {
            status = JobStatus::Failed;
            error = refused.problem;
        } catch (...) {
            std::string log;
            api::Problem p = api::problem_of(std::current_exception(), &log);
            status = JobStatus::Failed;
            if (api::is_cancellation(p)) {
                if (obs.timed_out())
                    error = api::Problem{422, "/v1/problems/timeout", "Time limit exceeded",
                                         "the mesh was not finished within " + std::to_string(limit) + " s",
                                         job->request.timeout_s ? "/options/timeout_s" : ""};
                else
                    status = JobStatus::Cancelled;
            } else {
                if (p.status == 413 && job->server_point_limit)
                    p.detail += " (the server's limit is " + std::to_string(config_.max_points) + " points)";
                if (p.status == 500) spdlog::error("job {} internal error: {}", job->id, log);
                error = std::move(p);
            }
        }
    }
    job->request = {};  // the worker is done with it; the job record may live a while
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const size_t bytes = result ? api::result_bytes(*result) : 0;
    nlohmann::ordered_json metrics = result ? nlohmann::ordered_json::parse(api::metrics_json(*result)) : nullptr;
    // The outcome, seen by readers of the job from here on.
    auto publish = [&] {
        std::lock_guard<std::mutex> lock(job->m);
        job->status = status;
        job->stage = to_string(status);
        job->progress = status == JobStatus::Succeeded ? 1.0 : job->progress;
        job->result = result;
        job->metrics = std::move(metrics);
        job->error = error;
        job->result_bytes = bytes;
        job->finished = std::chrono::system_clock::now();
    };
    if (job->on_finish) publish();
    spdlog::info("job {} {} points={} triangles={} time_ms={:.1f}{}", job->id, to_string(status),
                 result ? result->quality.points : 0, result ? result->quality.triangles : 0, secs * 1000.0,
                 error ? " problem=" + error->type : std::string());
    const size_t points = result ? result->quality.points : 0, triangles = result ? result->quality.triangles : 0;
    if (job->on_finish) {
        // A shared store's job: the store takes the outcome (and names it: a job handed back
        // to the queue has not ended); this manager keeps nothing.
        std::string outcome;
        try {
            outcome = job->on_finish(*job);
        } catch (const std::exception& e) {
            // The store keeps the job pending: its lease lapses and another replica runs it.
            spdlog::error("job {}: its end could not be handed to the store: {}", job->id, e.what());
        }
        if (outcome == "succeeded" || outcome == "failed" || outcome == "cancelled")
            metrics_.job_finished(outcome, secs, points, triangles);
        {
            std::lock_guard<std::mutex> lock(job->m);
            job->result.reset();
        }
        job->done_cv.notify_all();
        return;
    }
    metrics_.job_finished(to_string(status), secs, points, triangles);
    {
        // The store knows the finished job before anyone waiting on it wakes (a synchronous
        // request forgets its job at once), and as soon as its outcome can be read: a reader
        // who sees it finished finds it among the finished records, bounded with them (m_
        // before job->m, as housekeeping takes them).
        std::lock_guard<std::mutex> lock(m_);
        publish();
        result_bytes_ += bytes;
        finished_order_.push_back(job);
        leave_owner_share_locked(*job);
    }
    job->done_cv.notify_all();
}

void JobManager::reserve_memory(size_t bytes, const std::function<bool()>& stop) {
    const size_t budget = config_.memory_budget_bytes;
    if (bytes > budget) throw over_budget("the mesh is forecast to need about " + megabytes(bytes), budget);
    std::unique_lock<std::mutex> lock(memory_m_);
    ++memory_waiting_;
    metrics_.set_memory(memory_reserved_, memory_waiting_, budget);
    // Jobs that finish wake the waiters; the periodic wake-up is for cancellation and time.
    while (memory_reserved_ + bytes > budget) {
        if (stop()) {
            --memory_waiting_;
            metrics_.set_memory(memory_reserved_, memory_waiting_, budget);
            throw core::Cancelled();
        }
        memory_cv_.wait_for(lock, std::chrono::milliseconds(50));
    }
    --memory_waiting_;
    memory_reserved_ += bytes;
    metrics_.set_memory(memory_reserved_, memory_waiting_, budget);
}

void JobManager::grow_memory(size_t from, size_t to, double points) {
    const size_t budget = config_.memory_budget_bytes;
    if (to > budget)
        throw over_budget("the mesh grew past its forecast to " + std::to_string(static_cast<long long>(points)) +
                              " points and more, which need about " + megabytes(to),
                          budget);
    std::lock_guard<std::mutex> lock(memory_m_);
    memory_reserved_ += to - from;
    metrics_.set_memory(memory_reserved_, memory_waiting_, budget);
}

void JobManager::release_memory(size_t bytes) {
    {
        std::lock_guard<std::mutex> lock(memory_m_);
        memory_reserved_ -= bytes;
        metrics_.set_memory(memory_reserved_, memory_waiting_, config_.memory_budget_bytes);
    }
    memory_cv_.notify_all();
}

void JobManager::release_result_locked(Job& job) {
    std::lock_guard<std::mutex> jl(job.m);
    if (job.result) result_bytes_ -= job.result_bytes;
    job.result.reset();
    job.expired = true;
}

void JobManager::housekeeping() {
    const auto now = std::chrono::system_clock::now();
    const auto ttl = std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(config_.job_ttl_s));
    std::lock_guard<std::mutex> lock(m_);
    // Results over budget: released oldest first; their records stay, answering "expired".
    for (auto it = finished_order_.begin(); result_bytes_ > config_.result_memory_bytes && it != finished_order_.end(); ++it)
        release_result_locked(**it);
    // Records beyond the bound or past their time: forgotten, oldest first.
    while (!finished_order_.empty()) {
        const std::shared_ptr<Job> job = finished_order_.front();
        std::chrono::system_clock::time_point fin;
        {
            std::lock_guard<std::mutex> jl(job->m);
            fin = job->finished;
        }
        if (finished_order_.size() <= config_.max_finished_jobs && now - fin < ttl) break;
        finished_order_.pop_front();
        release_result_locked(*job);
        jobs_.erase(job->id);
    }
    metrics_.set_jobs_kept(jobs_.size());
}

void JobManager::drain(std::chrono::duration<double> grace) {
    drain_until(std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(grace));
}

void JobManager::drain_until(std::chrono::steady_clock::time_point until) {
    draining_ = true;
    {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait_until(lock, until, [&] { return queue_.empty() && busy_ == 0; });
        stop_ = true;
        for (auto& j : queue_) j->cancel = true;
        for (auto& j : running_) j->cancel = true;
        for (auto& [id, j] : jobs_) j->cancel = true;
    }
    cv_.notify_all();
    idle_cv_.notify_all();
    for (auto& t : workers_)
        if (t.joinable()) t.join();
    workers_.clear();  // a second drain (the destructor after SIGTERM) finds nothing to join
}

}  // namespace meshd::server
