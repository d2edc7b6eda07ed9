#pragma once
/// The HTTP service of docs/api.md over cpp-httplib: routes, problems, streaming responses,
/// metrics, logging, readiness and draining. Holds no geometry: requests go to api/, work to
/// the JobManager, asynchronous jobs to the job store (store.hpp).

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "meshd/server/access.hpp"
#include "meshd/server/config.hpp"
#include "meshd/server/jobs.hpp"
#include "meshd/server/metrics.hpp"

namespace httplib {
class Server;
}

namespace meshd::server {

class RedisStore;

struct Route {
    std::string method;
    std::string path;  ///< OpenAPI form: /v1/jobs/{id}
};

class Service {
public:
    explicit Service(Config config);
    ~Service();

    /// Binds (port 0: any free port) and returns the port; -1 on failure. Binds the probe
    /// listener too when the config asks for one.
    int bind();
    /// The probe listener's port once bound; -1 without one.
    int probe_port() const { return probe_port_; }
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
    void install_probes(httplib::Server& s, bool document);
    void install_page(httplib::Server& s, const std::function<void(const char*, const char*)>& add);

    Config config_;
    Access access_;
    Metrics metrics_;
    /// Jobs run here (sync requests, and the async ones of the store); the store of async
    /// jobs is either jobs_ itself or redis_ (--store).
    std::unique_ptr<JobManager> jobs_;
    std::unique_ptr<RedisStore> redis_;
    JobStore* store_ = nullptr;
    std::unique_ptr<httplib::Server> http_;
    std::unique_ptr<httplib::Server> probe_;
    std::thread probe_thread_;
    int probe_port_ = -1;
    std::vector<Route> routes_;
    std::atomic<bool> draining_{false};
};

}  // namespace meshd::server
