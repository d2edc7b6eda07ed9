#pragma once
// A small synchronous Redis client over hiredis (Debian's libhiredis 0.14): one connection,
// binary-safe commands, replies as values, reconnection after a failure. The job store's
// Redis implementation is built on it; nothing here knows about jobs.
//
// Endpoints: redis://[:password@]host[:port][/db] or unix:///path/to/socket[?db=N]. A
// password given in the URL or by the caller is sent with AUTH on every (re)connection and
// never appears in what describe() returns or in error texts.

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

struct redisContext;

namespace meshd::server::redis {

struct Endpoint {
    std::string host;       ///< empty for a unix socket
    int port = 6379;
    std::string socket;     ///< path of a unix socket, or empty
    int db = 0;
    std::string password;   ///< empty: no AUTH

    /// host:port/db or unix:path/db, without the password.
    std::string describe() const;
};

/// Parses a Redis URL; throws std::invalid_argument naming what is wrong (without the password).
Endpoint parse_url(const std::string& url);

struct Reply {
    enum class Kind { Nil, Integer, String, Status, Array, Error };
    Kind kind = Kind::Nil;
    long long integer = 0;
    std::string str;  ///< String, Status and Error
    std::vector<Reply> elements;

    bool is_nil() const { return kind == Kind::Nil; }
    bool is_error() const { return kind == Kind::Error; }
};

/// The store could not be reached, or the connection failed during a command.
class Unavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Connection {
public:
    /// Connects lazily: the first command (or ping()) opens the connection.
    Connection(Endpoint endpoint, std::chrono::milliseconds timeout);
    ~Connection();
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    /// Runs one command. Redis's own errors come back as Kind::Error replies; a connection
    /// that cannot be opened or fails throws Unavailable and is reopened by the next command.
    Reply command(std::initializer_list<std::string_view> args);
    Reply command(const std::vector<std::string>& args);
    /// Several commands in one round trip, replies in order (a failed connection throws).
    std::vector<Reply> pipeline(const std::vector<std::vector<std::string>>& commands);
    /// True when PING answers.
    bool ping();
    bool connected() const { return context_ != nullptr; }
    const Endpoint& endpoint() const { return endpoint_; }

private:
    void open();
    void drop();
    Reply run(size_t argc, const char** argv, const size_t* lens);
    /// The connection failed: dropped (the next command reopens it), Unavailable thrown.
    [[noreturn]] void fail();

    Endpoint endpoint_;
    std::chrono::milliseconds timeout_;
    redisContext* context_ = nullptr;
};

}  // namespace meshd::server::redis
