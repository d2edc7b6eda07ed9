#pragma once
/// The HTTP service of docs/api.md over cpp-httplib: routes, problems, streaming responses,
/// metrics, logging, readiness and draining. Holds no geometry: requests go to api/, work to
/// the JobManager.

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "meshd/server/config.hpp"
#include "meshd/server/jobs.hpp"
#include "meshd/server/metrics.hpp"

namespace httplib {
class Server;
}

namespace meshd::server {

struct Route {
    std::string method;
    std::string path;  ///< OpenAPI form: /v1/jobs/{id}
};

class Service {
public:
    explicit Service(Config config);
    ~Service();

    /// Binds (port 0: any free port) and returns the port; -1 on failure.
    int bind();
    /// Serves until stop(); blocks.
    bool listen();
    bool running() const;
    /// Readiness off, no new jobs, running jobs finish up to the drain grace, then the HTTP
    /// server stops. Safe to call from any thread once.
    void drain();
    void stop();

    /// Every route this service answers, as documented in /v1/openapi.json.
    const std::vector<Route>& routes() const { return routes_; }
    std::string openapi() const;

private:
    void install();

    Config config_;
    Metrics metrics_;
    std::unique_ptr<JobManager> jobs_;
    std::unique_ptr<httplib::Server> http_;
    std::vector<Route> routes_;
    std::atomic<bool> draining_{false};
};

}  // namespace meshd::server
