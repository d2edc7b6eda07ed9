// Several meshd replicas sharing one job store: a real redis-server and real meshd processes
// on loopback ports, killed and restarted as an orchestrator would.

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "http_support.hpp"
#include "redis_process.hpp"
#include "server_process.hpp"

using json = nlohmann::ordered_json;
using meshd::test::client;
using meshd::test::eventually;
using meshd::test::naca_request;
using meshd::test::RedisProcess;
using meshd::test::ServerProcess;
using meshd::test::slow_request;
using meshd::test::wait_for_job;

namespace {

std::unique_ptr<ServerProcess> replica(const RedisProcess& redis, std::vector<std::string> args = {}) {
    args.insert(args.end(), {"--store", redis.url()});
    return std::make_unique<ServerProcess>(args);
}

std::string submit(httplib::Client& c, const std::string& body) {
    auto r = c.Post("/v1/jobs", body, "application/json");
    if (!r || r->status != 202) return "";
    return json::parse(r->body)["id"];
}

std::string status_of(httplib::Client& c, const std::string& id) {
    auto r = c.Get(("/v1/jobs/" + id).c_str());
    if (!r) return "no answer";
    if (r->status != 200) return "http-" + std::to_string(r->status);
    return json::parse(r->body)["status"];
}

bool running(httplib::Client& c, const std::string& id) { return status_of(c, id) == "running"; }

std::string mesh_of(httplib::Client& c, const std::string& id, const std::string& format) {
    auto r = c.Get(("/v1/jobs/" + id + "/mesh?format=" + format).c_str());
    return r && r->status == 200 ? r->body : "http-" + std::to_string(r ? r->status : -1);
}

std::string sync_mesh(httplib::Client& c, const std::string& body, const std::string& format) {
    auto r = c.Post(("/v1/meshes?format=" + format).c_str(), body, "application/json");
    return r && r->status == 200 ? r->body : "http-" + std::to_string(r ? r->status : -1);
}

}  // namespace

// Submitted on A; status, the mesh in every format, and a cancel answered by B.
TEST(Replicas, AnyReplicaAnswersForAnyJob) {
    RedisProcess redis;
    auto a = replica(redis), b = replica(redis);
    auto ca = client(*a), cb = client(*b);
    const std::string id = submit(ca, naca_request());
    ASSERT_FALSE(id.empty());
    const json done = wait_for_job(cb, id);
    ASSERT_EQ(done["status"], "succeeded") << done.dump();
    EXPECT_GT(done["metrics"]["triangles"].get<int>(), 1000);
    // The same bytes as a synchronous request (JSON: but for the stages' timings).
    auto untimed = [](const std::string& text) {
        json j = json::parse(text);
        j["metrics"].erase("timings_ms");
        return j;
    };
    for (const char* f : {"json", "vtk", "su2", "msh", "svg", "foam"}) {
        const std::string expected = sync_mesh(ca, naca_request(), f);
        ASSERT_EQ(expected.substr(0, 5) == "http-", false) << f;
        for (auto* c : {&ca, &cb}) {
            const std::string got = mesh_of(*c, id, f);
            if (std::string(f) == "json")
                EXPECT_EQ(untimed(got), untimed(expected));
            else
                EXPECT_TRUE(got == expected) << f;
        }
    }
    // CGNS (HDF5 stamps its objects with the time they were written): the same size.
    const std::string cgns = mesh_of(cb, id, "cgns");
    EXPECT_EQ(cgns.substr(0, 4), "\x89HDF");
    EXPECT_EQ(cgns.size(), sync_mesh(ca, naca_request(), "cgns").size());
    // A long job, cancelled through the replica that did not take it.
    const std::string slow = submit(ca, slow_request(0.0008));
    ASSERT_FALSE(slow.empty());
    ASSERT_TRUE(eventually([&] { return running(cb, slow); }));
    auto del = cb.Delete(("/v1/jobs/" + slow).c_str());
    ASSERT_TRUE(del);
    EXPECT_TRUE(del->status == 200 || del->status == 202) << del->status;
    EXPECT_EQ(wait_for_job(ca, slow)["status"], "cancelled");
    auto gone = ca.Get(("/v1/jobs/" + slow + "/mesh").c_str());
    ASSERT_TRUE(gone);
    EXPECT_EQ(gone->status, 410);
    // Unknown everywhere.
    EXPECT_EQ(status_of(cb, "00000000000000000000000000000000"), "http-404");
}

// kill -9 of the replica running a job: another replica takes it over once the lease lapses
// and finishes it, with the very bytes a synchronous request gives.
TEST(Replicas, AJobOfAKilledReplicaIsFinishedByAnother) {
    RedisProcess redis;
    const std::string body = slow_request(0.003);
    auto a = replica(redis, {"--lease-s", "0.5", "--workers", "1"});
    auto ca = client(*a);
    const std::string id = submit(ca, body);
    ASSERT_FALSE(id.empty());
    ASSERT_TRUE(eventually([&] { return running(ca, id); }));  // A has it: B does not exist yet
    auto b = replica(redis, {"--lease-s", "0.5", "--workers", "1"});
    auto cb = client(*b);
    const auto killed = std::chrono::steady_clock::now();
    a->signal(SIGKILL);
    ASSERT_NE(a->wait(std::chrono::seconds(20)), -1);
    const json done = wait_for_job(cb, id, 120);
    ASSERT_EQ(done["status"], "succeeded") << done.dump();
    std::printf("recovered in %.2f s (lease 0.5 s plus the job)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count());
    EXPECT_EQ(mesh_of(cb, id, "su2"), sync_mesh(cb, body, "su2"));
    auto page = cb.Get("/metrics");
    ASSERT_TRUE(page);
    EXPECT_NE(page->body.find("meshd_store_jobs_total{event=\"reclaimed\"} 1\n"), std::string::npos) << page->body;
}

// A replica paused past its lease (SIGSTOP: a VM paused, a machine swapping) loses its job
// to another but lives on: its run did not stop it, so it does not count towards the runs
// after which a job is failed as what stops its replicas. The job moves between two replicas
// more times than that limit and still ends succeeded.
TEST(Replicas, AJobMovedFromPausedReplicasIsNotTakenForOneThatStopsThem) {
    RedisProcess redis;
    const std::vector<std::string> args{"--lease-s", "0.5", "--workers", "1"};
    std::vector<std::unique_ptr<ServerProcess>> r;
    r.push_back(replica(redis, args));
    auto c0 = client(*r[0]);
    const std::string id = submit(c0, slow_request(0.002));  // seconds to mesh
    ASSERT_FALSE(id.empty());
    ASSERT_TRUE(eventually([&] { return running(c0, id); }));  // the first has it: the second does not exist yet
    r.push_back(replica(redis, args));
    auto takeovers = [&](ServerProcess& s) {
        const std::string log = s.log(), line = "job " + id + " taken over";
        int n = 0;
        for (size_t p = log.find(line); p != std::string::npos; p = log.find(line, p + 1)) ++n;
        return n;
    };
    // Six moves: with the first start, seven starts, more than the five runs allowed.
    int runner = 0;
    for (int move = 0; move < 6; ++move) {
        const int other = 1 - runner, before = takeovers(*r[other]);
        r[runner]->signal(SIGSTOP);
        auto c = client(*r[other]);
        ASSERT_TRUE(eventually([&] { return takeovers(*r[other]) > before || !running(c, id); }, 60)) << "move " << move;
        ASSERT_TRUE(running(c, id)) << "move " << move << ": " << status_of(c, id);
        r[runner]->signal(SIGCONT);
        runner = other;
    }
    const json end = wait_for_job(c0, id, 120);
    EXPECT_EQ(end["status"], "succeeded") << end.dump();
    for (auto& s : r) EXPECT_EQ(s->wait(std::chrono::milliseconds(1)), -1) << "a replica stopped";
}

// SIGTERM on a replica with a running job and jobs waiting: it stops taking jobs, hands the
// running one back when its grace ends, exits 0; every job ends succeeded on the other.
TEST(Replicas, ADrainingReplicaHandsItsJobsBack) {
    RedisProcess redis;
    // The running job is four times the size of the others here (about 1.2 M points, over
    // a second on the fastest machine) against a grace of 0.1 s: it cannot end in time.
    auto a = replica(redis, {"--workers", "1", "--drain-s", "0.1"});
    auto ca = client(*a);
    std::vector<std::string> ids;
    ids.push_back(submit(ca, slow_request(0.001)));
    ASSERT_TRUE(eventually([&] { return running(ca, ids[0]); }));
    for (int i = 0; i < 3; ++i) ids.push_back(submit(ca, naca_request()));
    for (const auto& id : ids) ASSERT_FALSE(id.empty());
    a->signal(SIGTERM);
    EXPECT_EQ(a->wait(std::chrono::seconds(30)), 0);
    EXPECT_TRUE(a->logged("job " + ids[0] + " handed back")) << a->log();
    // Nothing ran them meanwhile: B comes after A is gone.
    auto b = replica(redis, {"--workers", "1"});
    auto cb = client(*b);
    for (const auto& id : ids) EXPECT_EQ(wait_for_job(cb, id, 120)["status"], "succeeded") << id;
}

// Redis stopped in the middle of a run and started again from its append-only file: no
// replica dies, readiness and new submissions say 503 meanwhile, then all is as before and
// every job accepted before the stop ends succeeded.
TEST(Replicas, TheStoreGoingAwayAndComingBackLosesNothing) {
    RedisProcess redis(false, {"--appendonly", "yes", "--appendfsync", "always"});
    auto a = replica(redis, {"--workers", "1"}), b = replica(redis, {"--workers", "1"});
    auto ca = client(*a), cb = client(*b);
    std::vector<std::string> ids;
    ids.push_back(submit(ca, slow_request(0.002)));
    ASSERT_TRUE(eventually([&] { return running(ca, ids[0]); }));
    for (int i = 0; i < 4; ++i) ids.push_back(submit(i % 2 ? ca : cb, naca_request()));
    for (const auto& id : ids) ASSERT_FALSE(id.empty());
    redis.stop();
    for (auto* c : {&ca, &cb}) {
        auto ready = c->Get("/readyz");
        ASSERT_TRUE(ready);
        EXPECT_EQ(ready->status, 503);
        auto refused = c->Post("/v1/jobs", naca_request(), "application/json");
        ASSERT_TRUE(refused);
        EXPECT_EQ(refused->status, 503);
        EXPECT_FALSE(refused->get_header_value("Retry-After").empty());
        EXPECT_EQ(json::parse(refused->body)["type"], "/v1/problems/store-unavailable");
        auto status = c->Get(("/v1/jobs/" + ids[0]).c_str());
        ASSERT_TRUE(status);
        EXPECT_EQ(status->status, 503);
        // Synchronous requests need no store.
        auto sync = c->Post("/v1/meshes", naca_request(), "application/json");
        ASSERT_TRUE(sync) << httplib::to_string(sync.error());
        EXPECT_EQ(sync->status, 200);
    }
    redis.start();
    for (auto* c : {&ca, &cb}) {
        ASSERT_TRUE(eventually([&] {
            auto ready = c->Get("/readyz");
            return ready && ready->status == 200;
        }));
        ids.push_back(submit(*c, naca_request()));
        ASSERT_FALSE(ids.back().empty());
    }
    for (const auto& id : ids) EXPECT_EQ(wait_for_job(cb, id, 120)["status"], "succeeded") << id;
    for (auto* s : {a.get(), b.get()}) EXPECT_EQ(s->wait(std::chrono::milliseconds(1)), -1) << "a replica stopped";
}

// The queue bound is one for all replicas: past it, 429 from any of them.
TEST(Replicas, TheQueueBoundIsGlobal) {
    RedisProcess redis;
    auto a = replica(redis, {"--workers", "1", "--queue", "2"}), b = replica(redis, {"--workers", "1", "--queue", "2"});
    auto ca = client(*a), cb = client(*b);
    // Both workers busy with long jobs, then two wait; the fifth is refused by either replica.
    const std::string r1 = submit(ca, slow_request(0.0008)), r2 = submit(cb, slow_request(0.0008));
    ASSERT_TRUE(eventually([&] { return running(ca, r1) && running(ca, r2); }));
    const std::string w1 = submit(ca, naca_request()), w2 = submit(cb, naca_request());
    ASSERT_FALSE(w1.empty());
    ASSERT_FALSE(w2.empty());
    for (auto* c : {&ca, &cb}) {
        auto r = c->Post("/v1/jobs", naca_request(), "application/json");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 429);
        EXPECT_EQ(r->get_header_value("Retry-After"), "1");
    }
    auto m = cb.Get("/metrics");
    ASSERT_TRUE(m);
    EXPECT_NE(m->body.find("\nmeshd_queue_depth 2\n"), std::string::npos);
    // The waiting ones first: a running one cancelled first frees its worker for a waiting
    // NACA job, which can then finish (in some 20 ms) before its own cancel arrives.
    for (const auto& id : {w1, w2, r1, r2}) cb.Delete(("/v1/jobs/" + id).c_str());
    for (const auto& id : {w1, w2, r1, r2}) EXPECT_EQ(wait_for_job(ca, id)["status"], "cancelled") << id;
    EXPECT_FALSE(submit(cb, naca_request()).empty());
}

// 300 jobs over three replicas while replicas are killed (-9) and started again at random:
// every accepted job ends once, succeeded or (when the test cancelled it) cancelled, and
// each result is the mesh of its own request.
TEST(Replicas, RandomKillsLoseNoJobAndMixNoResults) {
    RedisProcess redis;
    const std::vector<std::string> args{"--lease-s", "0.5", "--workers", "1", "--queue", "400"};
    std::vector<std::unique_ptr<ServerProcess>> replicas;
    for (int i = 0; i < 3; ++i) replicas.push_back(replica(redis, args));
    // Ten requests with ten different meshes; each job is one of them.
    std::vector<std::string> bodies, expected;
    for (int k = 0; k < 10; ++k) {
        bodies.push_back(slow_request(0.012 + 0.0005 * k));  // some 8,000 points: tens of milliseconds
        auto c = client(*replicas[0]);
        expected.push_back(sync_mesh(c, bodies.back(), "su2"));
        ASSERT_EQ(expected.back().substr(0, 5) == "http-", false);
    }
    std::mt19937 rng(12345);
    struct Submitted {
        std::string id;
        int request;
        bool cancelled;
    };
    std::vector<Submitted> jobs;
    int kills = 0;
    while (jobs.size() < 300) {
        const size_t r = rng() % replicas.size();
        if (rng() % 25 == 0) {
            // Kill one and start a new one in its place (a new port, a new consumer).
            replicas[r]->signal(SIGKILL);
            replicas[r]->wait(std::chrono::seconds(20));
            replicas[r] = replica(redis, args);
            ++kills;
            continue;
        }
        auto c = client(*replicas[r]);
        const int k = static_cast<int>(rng() % bodies.size());
        const std::string id = submit(c, bodies[static_cast<size_t>(k)]);
        if (id.empty()) continue;  // the replica was just killed: a client would retry
        const bool cancel = rng() % 10 == 0;
        if (cancel) c.Delete(("/v1/jobs/" + id).c_str());
        jobs.push_back({id, k, cancel});
    }
    EXPECT_GE(kills, 5);
    auto c = client(*replicas[0]);
    std::map<std::string, std::string> final_status;
    for (const auto& j : jobs) {
        const json end = wait_for_job(c, j.id, 300);
        const std::string st = end["status"];
        final_status[j.id] = st;
        if (j.cancelled) {
            EXPECT_TRUE(st == "cancelled" || st == "succeeded") << j.id << " " << st;
        } else {
            EXPECT_EQ(st, "succeeded") << j.id << " " << end.dump();
        }
        if (st == "succeeded") {
            EXPECT_EQ(mesh_of(c, j.id, "su2"), expected[static_cast<size_t>(j.request)]) << j.id;
        }
    }
    // Ended once: the status seen from any replica later is the same.
    for (const auto& j : jobs) EXPECT_EQ(status_of(c, j.id), final_status[j.id]) << j.id;
    int reclaimed = 0;
    for (auto& r : replicas) {
        auto rc = client(*r);
        auto m = rc.Get("/metrics");
        const auto p = m ? m->body.find("meshd_store_jobs_total{event=\"reclaimed\"} ") : std::string::npos;
        if (p != std::string::npos) reclaimed += std::atoi(m->body.c_str() + p + 42);
    }
    std::printf("%d kills; the replicas alive at the end took over %d jobs\n", kills, reclaimed);
}

namespace {

int free_loopback_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    close(fd);
    return ntohs(a.sin_port);
}

// Debian's haproxy with docker/haproxy.cfg, its servers pointed at the given replicas.
class HAProxy {
public:
    HAProxy(const std::vector<std::unique_ptr<ServerProcess>>& replicas) {
        std::string cfg = meshd::test::read_file(MESHD_SOURCE_DIR "/docker/haproxy.cfg");
        port_ = free_loopback_port();
        auto replace = [&](const std::string& from, const std::string& to) {
            const auto p = cfg.find(from);
            if (p == std::string::npos) throw std::runtime_error("docker/haproxy.cfg has no \"" + from + "\"");
            cfg.replace(p, from.size(), to);
        };
        replace("bind :8080", "bind 127.0.0.1:" + std::to_string(port_));
        for (size_t i = 0; i < replicas.size(); ++i) {
            const std::string n = std::to_string(i + 1);
            replace("server meshd-" + n + " meshd-" + n + ":8080", "server meshd-" + n + " 127.0.0.1:" +
                    std::to_string(replicas[i]->port()) + " port " + std::to_string(replicas[i]->probe_port()));
        }
        path_ = ::testing::TempDir() + "/meshd_haproxy_" + std::to_string(getpid()) + ".cfg";
        std::ofstream(path_) << cfg;
        pid_ = fork();
        if (pid_ == 0) {
            const int devnull = open("/dev/null", O_WRONLY);
            dup2(devnull, 1);
            execlp("haproxy", "haproxy", "-db", "-f", path_.c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
    }
    ~HAProxy() {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
    int port() const { return port_; }

private:
    std::string path_;
    int port_ = 0;
    pid_t pid_ = -1;
};

}  // namespace

// docker/haproxy.cfg for real in front of three replicas (as compose.yaml runs them): jobs
// submitted and followed through the one address all succeed, polls landing on any replica;
// a replica that drains leaves the balancer (its /readyz on the probe port) and the
// service goes on.
TEST(Replicas, BehindTheLoadBalancerOfComposeYaml) {
    RedisProcess redis;
    std::vector<std::unique_ptr<ServerProcess>> replicas;
    for (int i = 0; i < 3; ++i) replicas.push_back(replica(redis, {"--probe-port", "0", "--workers", "1", "--drain-s", "0.1"}));
    HAProxy lb(replicas);
    httplib::Client c("127.0.0.1", lb.port());
    c.set_read_timeout(60, 0);
    // Until haproxy's first health checks pass.
    ASSERT_TRUE(eventually([&] {
        auto r = c.Get("/readyz");
        return r && r->status == 200;
    }, 60));
    std::vector<std::string> ids;
    auto submit_through_lb = [&] {
        // A client retries a 503 (a replica leaving, not yet out of the balancer).
        std::string id;
        EXPECT_TRUE(eventually([&] {
            id = submit(c, naca_request());
            return !id.empty();
        }, 60));
        ids.push_back(id);
    };
    for (int i = 0; i < 10; ++i) submit_through_lb();
    replicas[0]->signal(SIGTERM);
    EXPECT_EQ(replicas[0]->wait(std::chrono::seconds(30)), 0);
    for (int i = 0; i < 10; ++i) submit_through_lb();
    for (const auto& id : ids) {
        json end;
        ASSERT_TRUE(eventually([&] {
            auto r = c.Get(("/v1/jobs/" + id).c_str());
            if (!r || r->status != 200) return false;
            end = json::parse(r->body);
            return end["status"] != "queued" && end["status"] != "running";
        }, 120)) << id;
        EXPECT_EQ(end["status"], "succeeded") << id;
    }
    // No replica left: the balancer answers with a problem and Retry-After, as meshd would.
    for (size_t i = 1; i < replicas.size(); ++i) replicas[i]->signal(SIGTERM);
    for (size_t i = 1; i < replicas.size(); ++i) EXPECT_EQ(replicas[i]->wait(std::chrono::seconds(30)), 0);
    httplib::Response last;
    ASSERT_TRUE(eventually([&] {
        auto r = c.Get("/v1/jobs/" + ids[0]);
        if (!r || r->status != 503) return false;
        last = *r;
        return true;
    }, 60));
    EXPECT_EQ(last.get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(last.get_header_value("Retry-After"), "2");
    EXPECT_EQ(json::parse(last.body)["type"], "/v1/problems/no-replica");
}

// A Redis that refuses writes (full, under noeviction) is a store that cannot take work:
// 503 with Retry-After, never a 500; the replica stays up and serves what it can.
TEST(Replicas, AFullStoreAnswers503) {
    RedisProcess redis(false, {"--maxmemory", "4mb", "--maxmemory-policy", "noeviction"});
    auto a = replica(redis);
    auto c = client(*a);
    // A body of some 6 MB (a long spline) cannot be stored.
    json big = json::parse(naca_request());
    json through = json::array();
    for (int i = 0; i < 120000; ++i) {
        const double t = 6.283185307179586 * i / 120000;
        through.push_back({30 * std::cos(t), 30 * std::sin(t)});
    }
    through.push_back(through[0]);
    big["geometry"]["curves"]["farfield"] = {{"type", "spline"}, {"through", through}, {"tag", "farfield"}};
    big["geometry"]["points"].erase("F");
    auto r = c.Post("/v1/jobs", big.dump(), "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 503) << r->body;
    EXPECT_EQ(json::parse(r->body)["type"], "/v1/problems/store-unavailable");
    EXPECT_FALSE(r->get_header_value("Retry-After").empty());
    // Small jobs still fit.
    const std::string id = submit(c, naca_request());
    ASSERT_FALSE(id.empty());
    EXPECT_EQ(wait_for_job(c, id)["status"], "succeeded");
}
