// meshd: the HTTP server. Configuration by flags and environment (meshd --help); logs to
// stdout; SIGTERM or SIGINT drains (readiness off, running jobs finish within --drain-s)
// and exits 0.

#include <malloc.h>
#include <signal.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <thread>

#include "meshd/server/access.hpp"
#include "meshd/server/config.hpp"
#include "meshd/server/service.hpp"
#include "redis.hpp"

namespace {

std::atomic<int> g_signal{0};

void on_signal(int sig) { g_signal = sig; }

// %* in a pattern: the message as a JSON string literal, so that --log-json lines parse.
class JsonMessage : public spdlog::custom_flag_formatter {
public:
    void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
        const std::string text(msg.payload.data(), msg.payload.size());
        const std::string quoted = nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        dest.append(quoted.data(), quoted.data() + quoted.size());
    }
    std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<JsonMessage>(); }
};

}  // namespace

int main(int argc, char** argv) {
    using namespace meshd::server;
    // A job's arrays are allocated and freed whole. glibc would map the large ones afresh
    // for every job and return freed memory at once, so each job paid a page fault per 4 KiB
    // it touched; kept up to these sizes, the next job reuses the pages.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    Config config;
    if (argc == 2 && std::strcmp(argv[1], "--openapi") == 0) {
        // The document of the routes a default server answers, for client generators.
        std::puts(Service(Config{}).openapi().c_str());
        return 0;
    }
    if (argc == 2 && std::strcmp(argv[1], "--hash-key") == 0) {
        // The digest an --api-keys file holds for a key (the key itself is never stored).
        std::string key;
        if (!std::getline(std::cin, key) || key.empty()) {
            std::fprintf(stderr, "meshd --hash-key: give the key on standard input\n");
            return 2;
        }
        std::puts(sha256_hex(key).c_str());
        return 0;
    }
    try {
        bool help = false;
        config = parse_config(std::vector<std::string>(argv + 1, argv + argc), help);
        if (help) {
            std::fputs(help_text().c_str(), stdout);
            return 0;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "meshd: %s\n", e.what());
        return 2;
    }
    auto logger = spdlog::stdout_logger_mt("meshd");
    spdlog::set_default_logger(logger);
    spdlog::set_level(spdlog::level::from_str(config.log_level));
    if (config.log_json) {
        auto f = std::make_unique<spdlog::pattern_formatter>(spdlog::pattern_time_type::utc);
        f->add_flag<JsonMessage>('*').set_pattern(R"({"time":"%Y-%m-%dT%H:%M:%S.%eZ","level":"%l","msg":%*})");
        spdlog::set_formatter(std::move(f));
    } else
        spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%eZ %l %v", spdlog::pattern_time_type::utc);
    spdlog::flush_on(spdlog::level::info);

    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGINT, &sa, nullptr);
    signal(SIGPIPE, SIG_IGN);

    std::unique_ptr<Service> owned;
    try {
        owned = std::make_unique<Service>(config);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    Service& service = *owned;
    const int port = service.bind();
    if (port < 0) {
        spdlog::error("cannot bind {}:{}", config.host, config.port);
        return 1;
    }
    spdlog::info("meshd listening on {}:{} with {} workers, queue {}, job store {}", config.host, port, config.workers,
                 config.queue_length, config.store == "memory" ? std::string("memory") : meshd::server::redis::parse_url(config.store).describe());
    if (service.probe_port() >= 0) spdlog::info("probes on {}:{} (/healthz, /livez, /readyz, /metrics)", config.host, service.probe_port());
    std::thread watcher([&] {
        while (g_signal == 0 && !(service.running() == false && g_signal != 0)) std::this_thread::sleep_for(std::chrono::milliseconds(50));
        spdlog::info("signal {} received", g_signal.load());
        service.drain();
    });
    const bool ok = service.listen();
    if (g_signal == 0) g_signal = -1;  // the server stopped on its own: let the watcher end
    watcher.join();
    spdlog::info("meshd stopped");
    return ok || g_signal > 0 ? 0 : 1;
}
