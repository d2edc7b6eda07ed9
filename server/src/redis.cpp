#include "redis.hpp"

#include <hiredis/hiredis.h>
#include <sys/time.h>

#include <cstdlib>

namespace meshd::server::redis {

namespace {

int to_int(const std::string& text, const char* what, int lo, int hi) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < lo || v > hi)
        throw std::invalid_argument(std::string("store URL: bad ") + what + " \"" + text + "\"");
    return static_cast<int>(v);
}

Reply convert(const redisReply* r) {
    Reply out;
    switch (r->type) {
        case REDIS_REPLY_INTEGER:
            out.kind = Reply::Kind::Integer;
            out.integer = r->integer;
            break;
        case REDIS_REPLY_STRING:
            out.kind = Reply::Kind::String;
            out.str.assign(r->str, r->len);
            break;
        case REDIS_REPLY_STATUS:
            out.kind = Reply::Kind::Status;
            out.str.assign(r->str, r->len);
            break;
        case REDIS_REPLY_ERROR:
            out.kind = Reply::Kind::Error;
            out.str.assign(r->str, r->len);
            break;
        case REDIS_REPLY_ARRAY:
            out.kind = Reply::Kind::Array;
            out.elements.reserve(r->elements);
            for (size_t i = 0; i < r->elements; ++i) out.elements.push_back(convert(r->element[i]));
            break;
        default:
            out.kind = Reply::Kind::Nil;
    }
    return out;
}

timeval to_timeval(std::chrono::milliseconds ms) {
    timeval tv{};
    tv.tv_sec = static_cast<time_t>(ms.count() / 1000);
    tv.tv_usec = static_cast<suseconds_t>((ms.count() % 1000) * 1000);
    return tv;
}

}  // namespace

std::string Endpoint::describe() const {
    return (socket.empty() ? host + ":" + std::to_string(port) : "unix:" + socket) + "/" + std::to_string(db);
}

Endpoint parse_url(const std::string& url) {
    Endpoint e;
    std::string rest;
    if (url.rfind("redis://", 0) == 0) {
        rest = url.substr(8);
        // [:password@]host[:port][/db]
        const auto at = rest.rfind('@');
        if (at != std::string::npos) {
            std::string auth = rest.substr(0, at);
            rest = rest.substr(at + 1);
            const auto colon = auth.find(':');
            e.password = colon == std::string::npos ? auth : auth.substr(colon + 1);
        }
        const auto slash = rest.find('/');
        if (slash != std::string::npos) {
            if (slash + 1 < rest.size()) e.db = to_int(rest.substr(slash + 1), "database", 0, 1 << 20);
            rest = rest.substr(0, slash);
        }
        const auto colon = rest.rfind(':');
        if (colon != std::string::npos) {
            e.port = to_int(rest.substr(colon + 1), "port", 1, 65535);
            rest = rest.substr(0, colon);
        }
        if (rest.empty()) throw std::invalid_argument("store URL: no host");
        e.host = rest;
    } else if (url.rfind("unix://", 0) == 0) {
        rest = url.substr(7);
        const auto q = rest.find("?db=");
        if (q != std::string::npos) {
            e.db = to_int(rest.substr(q + 4), "database", 0, 1 << 20);
            rest = rest.substr(0, q);
        }
        if (rest.empty() || rest[0] != '/') throw std::invalid_argument("store URL: unix:// needs an absolute socket path");
        e.socket = rest;
    } else {
        throw std::invalid_argument("store URL must start with redis:// or unix://");
    }
    return e;
}

Connection::Connection(Endpoint endpoint, std::chrono::milliseconds timeout)
    : endpoint_(std::move(endpoint)), timeout_(timeout) {}

Connection::~Connection() { drop(); }

void Connection::drop() {
    if (context_) redisFree(context_);
    context_ = nullptr;
}

void Connection::open() {
    const timeval tv = to_timeval(timeout_);
    redisContext* c = endpoint_.socket.empty() ? redisConnectWithTimeout(endpoint_.host.c_str(), endpoint_.port, tv)
                                               : redisConnectUnixWithTimeout(endpoint_.socket.c_str(), tv);
    if (!c) throw Unavailable("store " + endpoint_.describe() + ": out of memory for a connection");
    if (c->err) {
        const std::string why = c->errstr;
        redisFree(c);
        throw Unavailable("store " + endpoint_.describe() + ": " + why);
    }
    redisSetTimeout(c, tv);
    context_ = c;
    auto must = [&](std::initializer_list<std::string_view> args, const char* what) {
        const Reply r = command(args);
        if (r.is_error()) {
            drop();
            throw Unavailable("store " + endpoint_.describe() + ": " + what + " refused: " + r.str);
        }
    };
    if (!endpoint_.password.empty()) must({"AUTH", endpoint_.password}, "AUTH");
    if (endpoint_.db != 0) must({"SELECT", std::to_string(endpoint_.db)}, "SELECT");
}

void Connection::fail() {
    const std::string why = context_->errstr;
    drop();
    throw Unavailable("store " + endpoint_.describe() + ": " + why);
}

Reply Connection::run(size_t argc, const char** argv, const size_t* lens) {
    if (!context_) open();
    void* raw = redisCommandArgv(context_, static_cast<int>(argc), argv, lens);
    if (!raw) fail();
    auto* reply = static_cast<redisReply*>(raw);
    Reply out = convert(reply);
    freeReplyObject(reply);
    return out;
}

namespace {

// A command's arguments as hiredis takes them: pointers and lengths (binary safe).
struct Argv {
    std::vector<const char*> ptrs;
    std::vector<size_t> lens;
    template <class Range>
    explicit Argv(const Range& args) {
        for (const auto& a : args) {
            ptrs.push_back(a.data());
            lens.push_back(a.size());
        }
    }
    int count() const { return static_cast<int>(ptrs.size()); }
};

}  // namespace

Reply Connection::command(std::initializer_list<std::string_view> args) {
    Argv argv(args);
    return run(argv.ptrs.size(), argv.ptrs.data(), argv.lens.data());
}

Reply Connection::command(const std::vector<std::string>& args) {
    Argv argv(args);
    return run(argv.ptrs.size(), argv.ptrs.data(), argv.lens.data());
}

std::vector<Reply> Connection::pipeline(const std::vector<std::vector<std::string>>& commands) {
    if (!context_) open();
    for (const auto& args : commands) {
        Argv argv(args);
        if (redisAppendCommandArgv(context_, argv.count(), argv.ptrs.data(), argv.lens.data()) != REDIS_OK) fail();
    }
    std::vector<Reply> out;
    out.reserve(commands.size());
    for (size_t i = 0; i < commands.size(); ++i) {
        void* raw = nullptr;
        if (redisGetReply(context_, &raw) != REDIS_OK || !raw) fail();
        auto* reply = static_cast<redisReply*>(raw);
        out.push_back(convert(reply));
        freeReplyObject(reply);
    }
    return out;
}

bool Connection::ping() {
    try {
        const Reply r = command({"PING"});
        return r.kind == Reply::Kind::Status && r.str == "PONG";
    } catch (const Unavailable&) {
        return false;
    }
}

}  // namespace meshd::server::redis
