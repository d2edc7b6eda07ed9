#pragma once
// Starts a real redis-server (Debian's, installed by scripts/setup.sh) for a test: on a unix
// socket in a fresh directory, or on a free loopback port; stopped (SIGKILL) at the end.

#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <netinet/in.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace meshd::test {

class RedisProcess {
public:
    /// `tcp`: listen on a free loopback port; else on a unix socket. `extra`: more
    /// redis-server arguments (e.g. {"--requirepass", "secret"}).
    explicit RedisProcess(bool tcp = false, std::vector<std::string> extra = {}) : extra_(std::move(extra)) {
        char tmpl[] = "/tmp/meshd-redis-XXXXXX";
        if (!mkdtemp(tmpl)) throw std::runtime_error("mkdtemp");
        dir_ = tmpl;
        socket_ = dir_ + "/redis.sock";
        if (tcp) port_ = free_port();
        start();
    }
    ~RedisProcess() {
        stop();
        std::system(("rm -rf " + dir_).c_str());
    }

    const std::string& socket_path() const { return socket_; }
    int port() const { return port_; }
    std::string url() const { return port_ ? "redis://127.0.0.1:" + std::to_string(port_) : "unix://" + socket_; }

    void stop() {
        if (pid_ > 0) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
            pid_ = -1;
        }
    }
    /// Starts it again with the same address (and the same data directory).
    void start() {
        std::vector<std::string> args{"redis-server", "--port", std::to_string(port_), "--bind", "127.0.0.1",
                                      "--unixsocket", socket_, "--dir", dir_, "--save", "", "--appendonly", "no",
                                      "--daemonize", "no", "--logfile", dir_ + "/redis.log"};
        args.insert(args.end(), extra_.begin(), extra_.end());
        pid_ = fork();
        if (pid_ == 0) {
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            execvp("redis-server", argv.data());
            _exit(127);
        }
        // Ready when its socket accepts a connection.
        for (int i = 0; i < 500; ++i) {
            if (accepts()) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        throw std::runtime_error("redis-server did not start (is it installed? scripts/setup.sh)");
    }

private:
    bool accepts() const {
        const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::snprintf(a.sun_path, sizeof a.sun_path, "%s", socket_.c_str());
        const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
        close(fd);
        return ok;
    }
    static int free_port() {
        const int fd = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
        socklen_t len = sizeof a;
        getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
        close(fd);
        return ntohs(a.sin_port);
    }

    std::vector<std::string> extra_;
    std::string dir_, socket_;
    int port_ = 0;
    pid_t pid_ = -1;
};

}  // namespace meshd::test
