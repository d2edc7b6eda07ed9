#pragma once
// Starts the real `meshd` binary on a free loopback port and stops it: the integration
// tests talk HTTP to it like any client.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace meshd::test {

// cpp-httplib's client sends without MSG_NOSIGNAL: a write to a server that has closed its
// side would kill the test process with SIGPIPE instead of failing the request (meshd itself
// ignores SIGPIPE, server/src/main.cpp).
inline const bool kSigpipeIgnored = [] {
    signal(SIGPIPE, SIG_IGN);
    return true;
}();

class ServerProcess {
public:
    explicit ServerProcess(std::vector<std::string> args) {
        int out[2];
        if (pipe(out) != 0) throw std::runtime_error("pipe");
        pid_ = fork();
        if (pid_ == 0) {
            dup2(out[1], 1);
            dup2(out[1], 2);
            close(out[0]);
            std::vector<std::string> all{MESHD_SERVER_BINARY, "--host", "127.0.0.1", "--port", "0"};
            all.insert(all.end(), args.begin(), args.end());
            std::vector<char*> argv;
            for (auto& a : all) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(argv[0], argv.data());
            _exit(127);
        }
        close(out[1]);
        out_ = out[0];
        // Wait for "listening on 127.0.0.1:PORT".
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (port_ == 0 && std::chrono::steady_clock::now() < until) {
            char buf[4096];
            const ssize_t n = read(out_, buf, sizeof buf);
            if (n <= 0) break;
            log_.append(buf, static_cast<size_t>(n));
            const auto p = log_.find("listening on 127.0.0.1:");
            if (p != std::string::npos) {
                const auto e = log_.find(' ', p + 23);
                if (e != std::string::npos) port_ = std::stoi(log_.substr(p + 23, e - p - 23));
            }
        }
        if (port_ == 0) throw std::runtime_error("meshd did not start: " + log_);
        // Keep draining its output so that it never blocks on a full pipe.
        reader_ = std::thread([this] {
            char buf[4096];
            for (;;) {
                const ssize_t n = read(out_, buf, sizeof buf);
                std::lock_guard<std::mutex> lock(m_);
                if (n <= 0) {
                    output_ended_ = true;
                    read_cv_.notify_all();
                    break;
                }
                log_.append(buf, static_cast<size_t>(n));
                read_cv_.notify_all();
            }
        });
    }

    ~ServerProcess() {
        if (pid_ > 0 && !exited_) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        if (reader_.joinable()) reader_.join();
        if (out_ >= 0) close(out_);
    }

    int port() const { return port_; }

    /// The probe listener's port (started with --probe-port 0), from its log line; 0 when
    /// there is none.
    int probe_port() {
        for (int i = 0; i < 1000; ++i) {
            {
                std::lock_guard<std::mutex> lock(m_);
                const auto p = log_.find("probes on 127.0.0.1:");
                if (p != std::string::npos) {
                    const auto e = log_.find(' ', p + 20);
                    if (e != std::string::npos) return std::stoi(log_.substr(p + 20, e - p - 20));
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return 0;
    }
    void signal(int sig) { kill(pid_, sig); }

    /// Waits for the process to end; its exit status, or -1 on timeout.
    int wait(std::chrono::duration<double> timeout) {
        const auto until = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < until) {
            int status = 0;
            const pid_t r = waitpid(pid_, &status, WNOHANG);
            if (r == pid_) {
                exited_ = true;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return -1;
    }

    /// What the server has printed so far, as far as the reading thread has got: a line just
    /// written may arrive a moment later (wait for it with logged()).
    std::string log() {
        std::lock_guard<std::mutex> lock(m_);
        return log_;
    }

    /// Waits until the server's output holds `text`: true then; false when its output ends, or
    /// the timeout passes, without it.
    bool logged(const std::string& text, std::chrono::duration<double> timeout = std::chrono::seconds(60)) {
        std::unique_lock<std::mutex> lock(m_);
        read_cv_.wait_for(lock, timeout, [&] { return output_ended_ || log_.find(text) != std::string::npos; });
        return log_.find(text) != std::string::npos;
    }

    /// Everything the server printed, once its output has ended (it has exited), or what has
    /// arrived when the timeout passes.
    std::string whole_log(std::chrono::duration<double> timeout = std::chrono::seconds(60)) {
        std::unique_lock<std::mutex> lock(m_);
        read_cv_.wait_for(lock, timeout, [&] { return output_ended_; });
        return log_;
    }

private:
    pid_t pid_ = -1;
    int out_ = -1;
    int port_ = 0;
    bool exited_ = false;
    std::string log_;
    bool output_ended_ = false;
    std::mutex m_;
    std::condition_variable read_cv_;
    std::thread reader_;
};

}  // namespace meshd::test
