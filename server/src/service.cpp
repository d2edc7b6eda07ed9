// The routes of docs/api.md.

#include "meshd/server/service.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <cmath>
#include <chrono>
#include <nlohmann/json.hpp>
#include <ostream>
#include <streambuf>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include "meshd/api/writers.hpp"
#include "meshd/server/access.hpp"
#include "peer.hpp"
#include "redis_store.hpp"
#include "web_assets.hpp"

namespace meshd::server {

namespace {

using json = nlohmann::ordered_json;
constexpr const char* kProblemType = "application/problem+json";

thread_local std::chrono::steady_clock::time_point request_start;
/// The API key of the request this thread answers (null on an open server).
thread_local const ApiKey* request_key = nullptr;

std::string request_owner() { return request_key ? request_key->id : std::string(); }

void send_problem(httplib::Response& res, const api::Problem& p) {
    res.status = p.status;
    res.set_content(p.to_json(), kProblemType);
}

api::Problem problem(int status, const std::string& kind, const std::string& title, const std::string& detail,
                     const std::string& pointer = "") {
    return api::Problem{status, "/v1/problems/" + kind, title, detail, pointer};
}

std::string rfc3339(std::chrono::system_clock::time_point t) {
    if (t.time_since_epoch().count() == 0) return "";
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
    const std::time_t secs = static_cast<std::time_t>(ms / 1000);
    std::tm tm{};
    gmtime_r(&secs, &tm);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                  tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms % 1000));
    return buf;
}

std::string route_of(const std::string& path) {
    if (path == "/v1/meshes" || path == "/v1/jobs" || path == "/healthz" || path == "/livez" || path == "/readyz" ||
        path == "/metrics" || path == "/v1/openapi.json" || path == "/")
        return path;
    if (path.rfind("/ui/", 0) == 0) return "/ui/{file}";
    if (path.rfind("/v1/jobs/", 0) == 0) {
        const std::string rest = path.substr(9);
        if (rest.find('/') == std::string::npos) return "/v1/jobs/{id}";
        if (rest.size() > 5 && rest.compare(rest.size() - 5, 5, "/mesh") == 0 && rest.find('/') == rest.size() - 5)
            return "/v1/jobs/{id}/mesh";
    }
    return "other";
}

// Streams what a writer puts in an ostream into the HTTP response, in 64 KiB chunks.
class SinkBuf : public std::streambuf {
public:
    SinkBuf(httplib::DataSink& sink, std::chrono::steady_clock::time_point until)
        : sink_(sink), until_(until), buf_(1 << 16) {
        setp(buf_.data(), buf_.data() + buf_.size());
    }
    ~SinkBuf() override { sync(); }
    bool ok() const { return ok_; }
    /// Whether it stopped at the time limit (else, when not ok, the client went away).
    bool late() const { return late_; }

protected:
    int overflow(int c) override {
        if (sync() != 0) return traits_type::eof();
        if (c != traits_type::eof()) {
            *pptr() = static_cast<char>(c);
            pbump(1);
        }
        return c == traits_type::eof() ? 0 : c;
    }
    int sync() override {
        const auto n = static_cast<size_t>(pptr() - pbase());
        if (n > 0 && ok_) {
            late_ = std::chrono::steady_clock::now() > until_;
            ok_ = !late_ && sink_.write(pbase(), n);
        }
        setp(buf_.data(), buf_.data() + buf_.size());
        return ok_ ? 0 : -1;
    }

private:
    httplib::DataSink& sink_;
    std::chrono::steady_clock::time_point until_;
    std::vector<char> buf_;
    bool ok_ = true;
    bool late_ = false;
};

// Collects what a writer puts in an ostream in a string, written in place (the string is the
// put area, doubled when full), for answers sent whole.
class StringBuf : public std::streambuf {
public:
    explicit StringBuf(size_t expected) {
        s_.resize(std::max<size_t>(expected, 4096));
        setp(s_.data(), s_.data() + s_.size());
    }
    std::string take() {
        s_.resize(static_cast<size_t>(pptr() - pbase()));
        setp(nullptr, nullptr);
        return std::move(s_);
    }

protected:
    int overflow(int c) override {
        const auto used = static_cast<std::ptrdiff_t>(pptr() - pbase());
        s_.resize(2 * s_.size());
        setp(s_.data(), s_.data() + s_.size());
        pbump(static_cast<int>(used));  // below the whole-answer limit: far below 2^31
        if (c == traits_type::eof()) return 0;
        *pptr() = static_cast<char>(c);
        pbump(1);
        return c;
    }

private:
    std::string s_;
};

// Meshes up to this many triangles are answered whole, with a Content-Length, rather than
// streamed: cpp-httplib copies each chunk of a streamed answer into a string of its own with
// the chunk's header, which cost the load run's 5,000-triangle answers a few percent of the
// server's time. Larger ones stream, so that no answer needs its whole text in memory.
constexpr size_t kWholeAnswerTriangles = 100'000;
// A guess at the answer's bytes per triangle, for the string's first size (JSON's points and
// triangles take about 37 per triangle; a short guess costs one doubling).
constexpr size_t kAnswerBytesPerTriangle = 48;

// cpp-httplib answers a client that accepts Brotli (every browser) with Brotli at its
// slowest quality: 10.6 s for a 5.7 MB mesh that gzip sends in 1.1 s. Such a client gets
// gzip. (The request object is httplib's own, not const: its headers may be edited here.)
void gzip_only(httplib::Request& req) {
    auto it = req.headers.find("Accept-Encoding");
    if (it == req.headers.end() || it->second.find("br") == std::string::npos) return;
    it->second = it->second.find("gzip") != std::string::npos ? "gzip" : "identity";
}

// `?sizes=true` with format=json: rho at each point too (write_json).
bool sizes_asked(const httplib::Request& req) { return req.has_param("sizes") && req.get_param_value("sizes") == "true"; }

// The mesh in format f (JSON with rho at each point when `sizes`).
void write_answer(std::ostream& os, const core::MeshResult& result, api::Format f, const api::FoamOptions& foam,
                  bool sizes) {
    if (f == api::Format::Json && sizes)
        api::write_json(result, os, true);
    else
        api::write_mesh(f, result, os, foam);
}

// Sends the mesh: whole when small, else streamed; past `until` a streamed answer's connection
// is dropped (the answer is incomplete: a client that reads too slowly cannot hold a thread
// and the mesh beyond the time limit; a whole answer is bounded by the socket's write timeout).
void send_mesh(httplib::Response& res, std::shared_ptr<const core::MeshResult> result, api::Format f,
               api::FoamOptions foam, std::chrono::steady_clock::time_point until, bool sizes) {
    res.status = 200;
    if (f == api::Format::Foam) res.set_header("Content-Disposition", "attachment; filename=\"polyMesh.tar\"");
    if (f == api::Format::Cgns) res.set_header("Content-Disposition", "attachment; filename=\"mesh.cgns\"");
    if (result->mesh.triangles.size() <= kWholeAnswerTriangles) {
        StringBuf buf(kAnswerBytesPerTriangle * (result->mesh.triangles.size() + result->mesh.quads.size()));
        {
            std::ostream os(&buf);
            write_answer(os, *result, f, foam, sizes);
        }
        res.body = buf.take();  // in place: set_content would copy it
        res.set_header("Content-Type", api::content_type(f));
        return;
    }
    res.set_chunked_content_provider(api::content_type(f), [result, f, foam = std::move(foam), until, sizes](size_t, httplib::DataSink& sink) {
        bool ok = true, late = false;
        {
            SinkBuf buf(sink, until);
            std::ostream os(&buf);
            write_answer(os, *result, f, foam, sizes);
            os.flush();
            ok = buf.ok();
            late = buf.late();
        }
        if (!ok) {
            // A client that goes away mid-answer (every load generator at its end) is no
            // fault of the server's: only the time limit is worth a warning.
            if (late) spdlog::warn("answer not finished within the time limit: connection dropped");
            else spdlog::info("the client went away before the answer was complete");
            return false;
        }
        sink.done();
        return true;
    });
}

std::optional<api::Format> format_of(const httplib::Request& req, httplib::Response& res) {
    const std::string name = req.has_param("format") ? req.get_param_value("format") : "json";
    auto f = api::parse_format(name);
    if (!f)
        send_problem(res, problem(400, "unknown-format", "Unknown format",
                                  "format \"" + name + "\" is not one of " + api::format_list()));
    return f;
}

// The body of a POST, read as it arrives and refused (413) past `limit`. A plain handler gets
// a chunked body whole, past cpp-httplib's payload limit (which it checks against
// Content-Length); read through the content reader, chunked bodies are held to it too.
// A body still arriving at `until` is refused (408): a client that trickles it cannot hold a
// thread beyond the server's time limit.
// Past the limit the rest of the body is read and dropped, up to kDrainBytes more and within
// the time limit, before the 413: a connection closed with unread data in it is reset, and a
// client still sending (cpp-httplib's, curl's) then loses the answer or gets a broken pipe.
std::optional<std::string> read_body(const httplib::ContentReader& reader, size_t limit,
                                     std::chrono::steady_clock::time_point until, httplib::Response& res) {
    constexpr size_t kDrainBytes = size_t{16} << 20;
    std::string body;
    bool too_large = false, too_slow = false;
    size_t dropped = 0;
    const bool ok = reader([&](const char* data, size_t n) {
        if (std::chrono::steady_clock::now() > until) {
            too_slow = !too_large;
            return false;
        }
        if (too_large || body.size() + n > limit) {
            too_large = true;
            dropped += n;
            return dropped <= kDrainBytes;
        }
        body.append(data, n);
        return true;
    });
    // The rest of an unread body must not be taken for the next request.
    if (too_slow || too_large || !ok) res.set_header("Connection", "close");
    if (too_slow) {
        send_problem(res, problem(408, "request-timeout", "Request timeout",
                                  "the body did not arrive within the server's time limit"));
        return std::nullopt;
    }
    // A Content-Length over the limit fails the read with cpp-httplib's own 413.
    if (too_large || (!ok && res.status == 413)) {
        send_problem(res, problem(413, "body-too-large", "Request too large", "the body exceeds the server's limit"));
        return std::nullopt;
    }
    if (!ok) {
        send_problem(res, problem(400, "bad-request", "Bad request", "the body could not be read"));
        return std::nullopt;
    }
    return body;
}

bool json_body(const httplib::Request& req, httplib::Response& res) {
    std::string ct = req.get_header_value("Content-Type");
    for (char& c : ct) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool ok = ct.rfind("application/json", 0) == 0 ||
                    (ct.find("+json") != std::string::npos && ct.rfind("application/", 0) == 0);
    if (!ok)
        send_problem(res, problem(415, "unsupported-media-type", "Unsupported media type",
                                  "send the request as application/json (got \"" + ct + "\")"));
    return ok;
}

json job_json(const JobInfo& j) {
    json o;
    o["id"] = j.id;
    o["status"] = to_string(j.status);
    o["progress"] = j.progress;
    o["stage"] = j.stage;
    o["submitted_at"] = rfc3339(j.submitted);
    if (j.status != JobStatus::Queued && j.started.time_since_epoch().count()) o["started_at"] = rfc3339(j.started);
    if (is_final(j.status)) o["finished_at"] = rfc3339(j.finished);
    if (j.status == JobStatus::Succeeded && !j.expired && !j.metrics.empty()) o["metrics"] = json::parse(j.metrics);
    if (j.status == JobStatus::Succeeded && j.expired) o["expired"] = true;
    if (j.error) o["error"] = json::parse(j.error->to_json());
    return o;
}

api::Problem second_order_problem(const std::string& why) {
    return problem(422, "format-cannot-hold-order", "Format cannot hold this mesh", why, "/options/order");
}

void store_unavailable(httplib::Response& res, const StoreUnavailable& e) {
    spdlog::warn("job store unavailable: {}", e.what());
    res.set_header("Retry-After", "2");
    send_problem(res, problem(503, "store-unavailable", "Job store unavailable",
                              "the job store cannot be reached now; retry later"));
}

}  // namespace

Service::Service(Config config) : config_(std::move(config)) {
    if (!config_.api_keys_file.empty()) access_ = Access::load(config_.api_keys_file);
    jobs_ = std::make_unique<JobManager>(config_, metrics_);
    store_ = jobs_.get();
    if (config_.store != "memory") {
        redis_ = std::make_unique<RedisStore>(config_, *jobs_, metrics_);
        store_ = redis_.get();
    }
    http_ = std::make_unique<httplib::Server>();
    install();
    if (config_.probe_port >= 0) {
        probe_ = std::make_unique<httplib::Server>();
        probe_->new_task_queue = [] { return new httplib::ThreadPool(2); };
        probe_->set_read_timeout(5, 0);
        probe_->set_write_timeout(5, 0);
        probe_->set_logger([](const httplib::Request& req, const httplib::Response& res) {
            spdlog::debug("probe {} {} {}", req.method, req.path, res.status);
        });
        install_probes(*probe_, false);
    }
}

Service::~Service() {
    stop();
    if (probe_thread_.joinable()) probe_thread_.join();
    // The store stops taking jobs before the workers go, and outlives them: their last jobs
    // end through it.
    if (redis_) redis_->stop_claiming();
    jobs_.reset();
    redis_.reset();
}

int Service::bind() {
    if (config_.probe_port >= 0) {
        probe_port_ = config_.probe_port == 0 ? probe_->bind_to_any_port(config_.host)
                      : probe_->bind_to_port(config_.host, config_.probe_port) ? config_.probe_port : -1;
        if (probe_port_ < 0) return -1;
    }
    if (config_.port == 0) return http_->bind_to_any_port(config_.host);
    return http_->bind_to_port(config_.host, config_.port) ? config_.port : -1;
}

bool Service::listen() {
    if (redis_) redis_->start();
    if (probe_port_ >= 0) probe_thread_ = std::thread([this] { probe_->listen_after_bind(); });
    return http_->listen_after_bind();
}
bool Service::running() const { return http_->is_running(); }

void Service::drain() {
    if (draining_.exchange(true)) return;
    spdlog::info("draining: readiness off, no new jobs, waiting up to {} s for running jobs", config_.drain_s);
    // The grace counts from the signal: stopping the store's claimer first may take as long
    // as its blocking read. A shared store's jobs not finished within the grace are handed
    // back to its queue.
    const auto until = std::chrono::steady_clock::now() +
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(config_.drain_s));
    if (redis_) redis_->stop_claiming();
    jobs_->drain_until(until);
    if (redis_) redis_->stop();
    spdlog::info("drained; stopping");
    http_->stop();
    if (probe_) probe_->stop();
}

void Service::stop() {
    if (http_) http_->stop();
    if (probe_) probe_->stop();
}

// /healthz, /livez, /readyz and /metrics: on the main server (`document`: listed in the
// OpenAPI document) and on the probe server, whose threads meshing and slow clients cannot
// hold.
void Service::install_probes(httplib::Server& s, bool document) {
    auto add = [&](const char* method, const char* path) {
        if (document) routes_.push_back({method, path});
    };
    auto health = [](const httplib::Request&, httplib::Response& res) {
        res.set_content(R"({"status":"ok"})", "application/json");
    };
    add("get", "/healthz");
    s.Get("/healthz", health);
    add("get", "/livez");
    s.Get("/livez", health);

    // Whether this replica takes traffic: not while it drains. A full queue is not a reason
    // (the 429 with Retry-After is the answer then; taking every replica out of the Service
    // at once under load would turn that into connection errors).
    add("get", "/readyz");
    s.Get("/readyz", [this](const httplib::Request&, httplib::Response& res) {
        if (jobs_->draining() || draining_) {
            res.set_header("Retry-After", "5");
            return send_problem(res, problem(503, "draining", "Not ready", "the server is draining"));
        }
        if (!store_->reachable()) {
            res.set_header("Retry-After", "2");
            return send_problem(res, problem(503, "store-unavailable", "Not ready", "the job store cannot be reached"));
        }
        res.set_content(R"({"status":"ready"})", "application/json");
    });

    add("get", "/metrics");
    s.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
        metrics_.set_queue(store_->queued(), jobs_->busy());
        try {
            metrics_.set_jobs_kept(store_->kept());
        } catch (const StoreUnavailable&) {
            // the figure from the last time the store answered stays
        }
        res.set_content(metrics_.render(), "text/plain; version=0.0.4; charset=utf-8");
    });
}

void Service::install() {
    httplib::Server& s = *http_;
    const int threads = config_.http_threads;
    s.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<size_t>(threads)); };
    s.set_payload_max_length(config_.max_body_bytes);
    s.set_read_timeout(30, 0);
    s.set_write_timeout(15, 0);  // a client that cannot take 64 KiB in 15 s holds a thread no longer
    s.set_keep_alive_max_count(1000);

    auto add = [&](const char* method, const char* path) { routes_.push_back({method, path}); };

    s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        request_start = std::chrono::steady_clock::now();
        request_key = nullptr;
        gzip_only(const_cast<httplib::Request&>(req));
        if (access_.open() || req.path.rfind("/v1/", 0) != 0) return httplib::Server::HandlerResponse::Unhandled;
        // API keys: every /v1 request names one (the probes and / stay open).
        const std::string auth = req.get_header_value("Authorization");
        const bool bearer = auth.size() > 7 && (auth.compare(0, 7, "Bearer ") == 0 || auth.compare(0, 7, "bearer ") == 0);
        if (!bearer) {
            res.set_header("WWW-Authenticate", "Bearer realm=\"meshd\"");
            send_problem(res, problem(401, "unauthorized", "Unauthorized",
                                      "send an API key as \"Authorization: Bearer <key>\""));
            return httplib::Server::HandlerResponse::Handled;
        }
        request_key = access_.find(auth.substr(7));
        if (!request_key) {
            send_problem(res, problem(403, "forbidden", "Forbidden", "the API key is not one of this service's"));
            return httplib::Server::HandlerResponse::Handled;
        }
        if (request_key->rate_per_s > 0) {
            double wait = 0;
            try {
                wait = store_->take_token(request_key->id, request_key->rate_per_s, request_key->burst);
            } catch (const StoreUnavailable&) {
                wait = 0;  // the rate is not enforced while the store is away; the job routes say 503
            }
            if (wait > 0) {
                res.set_header("Retry-After", std::to_string(static_cast<long>(std::ceil(wait))));
                send_problem(res, problem(429, "rate-limited", "Too many requests",
                                          "this API key's request rate (" + std::to_string(request_key->rate_per_s) +
                                              " per second) is used up; retry later"));
                return httplib::Server::HandlerResponse::Handled;
            }
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });
    s.set_logger([this](const httplib::Request& req, const httplib::Response& res) {
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - request_start).count();
        const std::string route = route_of(req.path);
        metrics_.request(route, res.status, secs);
        spdlog::info("{} {} {} {:.1f}ms", req.method, req.path, res.status, secs * 1000.0);
    });
    s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        switch (res.status) {
            case 404: send_problem(res, problem(404, "not-found", "Not found", "no route for " + req.method + " " + req.path)); break;
            case 405: send_problem(res, problem(405, "method-not-allowed", "Method not allowed", req.method + " " + req.path)); break;
            case 413: send_problem(res, problem(413, "body-too-large", "Request too large", "the body exceeds the server's limit")); break;
            case 400: send_problem(res, problem(400, "bad-request", "Bad request", "the HTTP request is malformed")); break;
            default: send_problem(res, problem(res.status, "http-" + std::to_string(res.status), "HTTP error", "status " + std::to_string(res.status)));
        }
    });
    s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown";
        try {
            if (ep) std::rethrow_exception(ep);
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        spdlog::error("unhandled exception in a handler: {}", what);
        send_problem(res, problem(500, "internal", "Internal error", "meshd failed on this request (a bug): " + what));
    });

    // The request of a POST, parsed, with the seconds that took (they count in its time
    // limit), or the problem sent.
    struct Parsed {
        api::MeshRequest request;
        double seconds;
        std::string body;
    };
    auto parse = [this](const httplib::Request& req, httplib::Response& res,
                        const httplib::ContentReader& reader) -> std::optional<Parsed> {
        if (!json_body(req, res)) return std::nullopt;
        const auto limit = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(config_.job_timeout_s));
        const std::optional<std::string> body = read_body(reader, config_.max_body_bytes, request_start + limit, res);
        if (!body) return std::nullopt;
        try {
            api::MeshRequest mr = api::parse_request(*body);
            return Parsed{std::move(mr), std::chrono::duration<double>(std::chrono::steady_clock::now() - request_start).count(),
                          std::move(*body)};
        } catch (const api::RequestError& e) {
            send_problem(res, e.problem());
            return std::nullopt;
        }
    };

    auto refuse_busy = [this](httplib::Response& res) {
        if (jobs_->draining() || draining_) {
            res.set_header("Retry-After", "5");
            send_problem(res, problem(503, "draining", "Shutting down", "the server is draining and takes no new jobs"));
        } else {
            res.set_header("Retry-After", "1");
            send_problem(res, problem(429, "queue-full", "Too many jobs", "the job queue is full; retry later"));
        }
    };

    // POST /v1/meshes: mesh synchronously (through the job queue, so the pool bounds the work).
    add("post", "/v1/meshes");
    s.Post("/v1/meshes", [this, parse, refuse_busy](const httplib::Request& req, httplib::Response& res,
                                                     const httplib::ContentReader& reader) {
        const auto f = format_of(req, res);
        if (!f) return;
        auto parsed = parse(req, res, reader);
        if (!parsed) return;
        if (parsed->request.options.order == 2)
            if (auto why = api::second_order_refusal(*f)) return send_problem(res, second_order_problem(*why));
        if (draining_) return refuse_busy(res);
        auto job = jobs_->submit(std::move(parsed->request), parsed->seconds);
        if (!job) return refuse_busy(res);
        // Wait for the job, and cancel it if the client goes away meanwhile. The connection's
        // socket is looked for only once the job has outlasted the first wait: the search
        // asks every descriptor of the process its addresses (at the load run's 64
        // connections, 1.2% of the server's profile in the kernel alone), and most requests
        // are answered first (load run: 349 -> 370 requests/s on average).
        int socket = -1;
        bool socket_sought = false, client_gone = false;
        std::unique_lock<std::mutex> lock(job->m);
        while (!job->done_cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return job->finished_locked(); })) {
            if (!socket_sought) {
                socket_sought = true;
                socket = connection_socket(req);
            }
            if (client_gone || socket < 0 || !peer_closed(socket)) continue;
            client_gone = true;
            lock.unlock();
            spdlog::info("job {}: the client closed the connection; cancelling", job->id);
            jobs_->cancel_job(job->id);
            lock.lock();
        }
        const JobStatus status = job->status;
        auto result = job->result;  // the answer holds the mesh while it streams
        const std::optional<api::Problem> error = job->error;
        const auto deadline = job->deadline;
        api::FoamOptions foam = job->foam;
        lock.unlock();
        jobs_->forget(job);  // nobody asks for a synchronous job again
        if (client_gone)
            send_problem(res, problem(499, "client-closed-request", "Client closed request",
                                      "the client closed the connection before the answer; the job was cancelled"));
        else if (status == JobStatus::Succeeded)
            send_mesh(res, std::move(result), *f, std::move(foam), deadline, sizes_asked(req));
        else if (status == JobStatus::Failed)
            send_problem(res, *error);
        else
            send_problem(res, problem(503, "cancelled", "Cancelled", "the job was cancelled (the server is shutting down)"));
    });

    // POST /v1/jobs: queue, in the job store.
    add("post", "/v1/jobs");
    s.Post("/v1/jobs", [this, parse, refuse_busy](const httplib::Request& req, httplib::Response& res,
                                                   const httplib::ContentReader& reader) {
        auto parsed = parse(req, res, reader);
        if (!parsed) return;
        if (draining_) return refuse_busy(res);
        Submission sub;
        try {
            sub = store_->submit(parsed->body, std::move(parsed->request), parsed->seconds, request_owner(),
                                 request_key ? request_key->queue_share : 0);
        } catch (const StoreUnavailable& e) {
            return store_unavailable(res, e);
        }
        if (sub.refusal == Submission::Refusal::OwnerShare) {
            res.set_header("Retry-After", "1");
            return send_problem(res, problem(429, "key-queue-share", "Too many jobs for this key",
                                             "this API key has " + std::to_string(request_key->queue_share) +
                                                 " jobs queued or running, its share of the queue; retry later"));
        }
        if (sub.refusal != Submission::Refusal::None) return refuse_busy(res);
        res.status = 202;
        res.set_header("Location", "/v1/jobs/" + sub.id);
        res.set_content(json{{"id", sub.id}, {"status", "queued"}}.dump(), "application/json");
    });

    auto unknown_job = [](httplib::Response& res, const std::string& id) {
        send_problem(res, problem(404, "unknown-job", "Unknown job", "no job \"" + id + "\" (never made, or expired)"));
    };

    add("get", "/v1/jobs/{id}");
    s.Get(R"(/v1/jobs/([0-9a-f]+))", [this, unknown_job](const httplib::Request& req, httplib::Response& res) {
        std::optional<JobInfo> job;
        try {
            job = store_->info(req.matches[1]);
        } catch (const StoreUnavailable& e) {
            return store_unavailable(res, e);
        }
        // Another key's job is no job for this one (not even its existence is told).
        if (!job || job->owner != request_owner()) return unknown_job(res, req.matches[1]);
        if (!is_final(job->status)) res.set_header("Retry-After", "1");
        res.set_content(job_json(*job).dump(), "application/json");
    });

    add("get", "/v1/jobs/{id}/mesh");
    s.Get(R"(/v1/jobs/([0-9a-f]+)/mesh)", [this, unknown_job](const httplib::Request& req, httplib::Response& res) {
        const auto f = format_of(req, res);
        if (!f) return;
        std::optional<JobMesh> job;
        try {
            job = store_->mesh(req.matches[1]);
        } catch (const StoreUnavailable& e) {
            return store_unavailable(res, e);
        }
        if (!job || job->info.owner != request_owner()) return unknown_job(res, req.matches[1]);
        switch (job->info.status) {
            case JobStatus::Queued:
            case JobStatus::Running:
                res.set_header("Retry-After", "1");
                return send_problem(res, problem(409, "not-finished", "Not finished", "the job is " + std::string(to_string(job->info.status))));
            case JobStatus::Cancelled:
                return send_problem(res, problem(410, "cancelled", "Gone", "the job was cancelled"));
            case JobStatus::Failed:
                return send_problem(res, *job->info.error);
            case JobStatus::Succeeded:
                break;
        }
        if (!job->result) return send_problem(res, problem(410, "expired", "Gone", "the mesh has expired; submit the request again"));
        if (job->result->mesh.order() == 2)
            if (auto why = api::second_order_refusal(*f)) return send_problem(res, second_order_problem(*why));
        send_mesh(res, std::move(job->result), *f, std::move(job->foam),
                  std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                         std::chrono::duration<double>(config_.job_timeout_s)),
                  sizes_asked(req));
    });

    add("delete", "/v1/jobs/{id}");
    s.Delete(R"(/v1/jobs/([0-9a-f]+))", [this, unknown_job](const httplib::Request& req, httplib::Response& res) {
        std::optional<JobInfo> job;
        try {
            job = store_->info(req.matches[1]);
            if (job && job->owner == request_owner()) job = store_->cancel(req.matches[1]);
        } catch (const StoreUnavailable& e) {
            return store_unavailable(res, e);
        }
        if (!job || job->owner != request_owner()) return unknown_job(res, req.matches[1]);
        res.status = job->status == JobStatus::Running ? 202 : 200;
        res.set_content(job_json(*job).dump(), "application/json");
    });

    install_probes(s, true);

    add("get", "/v1/openapi.json");
    s.Get("/v1/openapi.json", [doc = openapi()](const httplib::Request&, httplib::Response& res) {
        res.set_content(doc, "application/json");
    });

    if (config_.ui) install_page(s, add);
}

// GET / and /ui/...: the web page (web/) and the examples it offers, from the binary. The
// page talks only to this server: its policy lets it load nothing from anywhere else.
void Service::install_page(httplib::Server& s, const std::function<void(const char*, const char*)>& add) {
    auto send = [](httplib::Response& res, const WebAsset& a) {
        res.set_header("Content-Security-Policy",
                       "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
                       "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'");
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_header("Cache-Control", "no-cache");
        res.set_content(reinterpret_cast<const char*>(a.data), a.size, a.content_type);
    };
    // "/" is the page itself; anything else under /ui/ not built in is a 404.
    auto serve = [send](const httplib::Request& req, httplib::Response& res) {
        const std::string path = req.path == "/" ? "/ui/index.html" : req.path;
        for (std::size_t i = 0; i < kWebAssetCount; ++i)
            if (path == kWebAssets[i].path) return send(res, kWebAssets[i]);
        res.status = 404;
    };
    add("get", "/");
    s.Get("/", serve);
    s.Get(R"(/ui/[A-Za-z0-9_./-]+)", serve);
}

}  // namespace meshd::server
