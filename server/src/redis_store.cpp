#include "redis_store.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "meshd/api/stored_result.hpp"

namespace meshd::server {

namespace {

using Clock = std::chrono::steady_clock;

/// Redis answered a command with an error.
class StoreRefused : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
using json = nlohmann::json;

constexpr const char* kGroup = "workers";
const std::string kPrefix = "{meshd}:";
/// A job whose replica stopped this many times is failed instead of run again: it is
/// probably what stops them. A run whose replica lost the job's lease but lived on (its
/// heartbeat came back to find the job moved) is not counted.
constexpr int kMaxRuns = 5;
/// Results are stored in chunks of this size (a Redis string holds at most 512 MB; one
/// chunk per command keeps every command and reply small).
constexpr size_t kChunk = size_t{1} << 20;
/// How long a finished job's outcome is retried while the store is away; past it the job
/// is left to its lease (another replica runs it again).
constexpr std::chrono::seconds kOutcomeRetry{120};
/// A stored result the finishing script has not taken yet expires after this (ms) at the
/// soonest: the script sets the job's TTL on it.
constexpr long long kUntakenResultMs = 60'000;

// Every script takes the job's key as KEYS[1] and the key prefix as ARGV[1]; the other keys
// are named from the prefix (they share its hash tag, so a Cluster keeps them in one slot).
// kLib is their common start: the budget of kept results and the bound on finished records.
const std::string kLib = R"lua(
local P = ARGV[1]
local function drop_result(id)
  local b = tonumber(redis.call('HGET', P .. 'result_sizes', id) or '0')
  redis.call('HDEL', P .. 'result_sizes', id)
  redis.call('ZREM', P .. 'results', id)
  redis.call('DEL', P .. 'result:' .. id)
  return redis.call('DECRBY', P .. 'result_bytes', b)
end
-- Finished records past their time leave (their hashes expire by themselves), and the
-- oldest beyond the bound are forgotten; their results leave the budget.
local function trim(now, ttl, max)
  for _, old in ipairs(redis.call('ZRANGEBYSCORE', P .. 'finished', '-inf', now - ttl)) do
    redis.call('ZREM', P .. 'finished', old)
    drop_result(old)
  end
  while redis.call('ZCARD', P .. 'finished') > max do
    local oldest = redis.call('ZRANGE', P .. 'finished', 0, 0)[1]
    redis.call('ZREM', P .. 'finished', oldest)
    drop_result(oldest)
    redis.call('DEL', P .. 'job:' .. oldest)
  end
end
-- A job has just ended.
local function ended(id, now, ttl, max)
  redis.call('DECR', P .. 'active')
  local owner = redis.call('HGET', P .. 'job:' .. id, 'owner')
  if owner and owner ~= '' then
    if redis.call('HINCRBY', P .. 'owners', owner, -1) <= 0 then redis.call('HDEL', P .. 'owners', owner) end
  end
  redis.call('ZADD', P .. 'finished', now, id)
  trim(now, ttl, max)
end
)lua";

// A token bucket (KEYS[1]: the owner's). ARGV: prefix, rate per s, burst.
// -> 0 go on | the milliseconds until a token is there
const std::string kToken = R"lua(
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + tonumber(t[2]) / 1000
local rate, burst = tonumber(ARGV[2]), tonumber(ARGV[3])
local b = redis.call('HMGET', KEYS[1], 'tokens', 'at')
local tokens = tonumber(b[1]) or burst
local at = tonumber(b[2]) or now
tokens = math.min(burst, tokens + math.max(0, now - at) * rate / 1000)
local wait = 0
if tokens >= 1 then tokens = tokens - 1 else wait = math.ceil((1 - tokens) * 1000 / rate) end
redis.call('HSET', KEYS[1], 'tokens', tostring(tokens), 'at', tostring(now))
redis.call('PEXPIRE', KEYS[1], math.ceil(burst * 1000 / rate) + 1000)
return wait
)lua";

// ARGV: prefix, now, ttl ms, max finished. -> the job records kept
const std::string kKept = kLib + R"lua(
trim(tonumber(ARGV[2]), tonumber(ARGV[3]), tonumber(ARGV[4]))
return redis.call('ZCARD', P .. 'finished') + math.max(0, tonumber(redis.call('GET', P .. 'active') or '0'))
)lua";

// ARGV: prefix, id, bound, now, body, foam, owner, owner's share.
// -> 1 queued | 0 queue full | -1 id taken | -2 the owner's share is taken
const std::string kSubmit = kLib + R"lua(
if redis.call('EXISTS', KEYS[1]) == 1 then return -1 end
if tonumber(redis.call('GET', P .. 'queued') or '0') >= tonumber(ARGV[3]) then return 0 end
local share = tonumber(ARGV[8])
if ARGV[7] ~= '' then
  if share > 0 and tonumber(redis.call('HGET', P .. 'owners', ARGV[7]) or '0') >= share then return -2 end
  redis.call('HINCRBY', P .. 'owners', ARGV[7], 1)
end
local entry = redis.call('XADD', P .. 'queue', '*', 'id', ARGV[2])
redis.call('HSET', KEYS[1], 'status', 'queued', 'stage', 'queued', 'progress', '0', 'submitted', ARGV[4],
  'request', ARGV[5], 'foam', ARGV[6], 'owner', ARGV[7], 'entry', entry, 'runs', '0')
redis.call('INCR', P .. 'queued')
redis.call('INCR', P .. 'active')
return 1
)lua";

// ARGV: prefix, consumer, now, max runs, entry.
// -> {'run', request, runs} | {'poison', runs} | {'final'} | {'gone'} | {'stale'}
const std::string kStart = R"lua(
local P = ARGV[1]
local f = redis.call('HMGET', KEYS[1], 'status', 'runs', 'request', 'entry')
if not f[1] then return {'gone'} end
if f[1] ~= 'queued' and f[1] ~= 'running' then return {'final'} end
if f[4] ~= ARGV[5] then return {'stale'} end
if f[1] == 'queued' then redis.call('DECR', P .. 'queued') end
local runs = tonumber(f[2]) + 1
redis.call('HSET', KEYS[1], 'status', 'running', 'stage', 'starting', 'progress', '0', 'runner', ARGV[2],
  'runs', tostring(runs), 'started', ARGV[3])
if runs > tonumber(ARGV[4]) then return {'poison', tostring(runs - 1)} end
return {'run', f[3], tostring(runs)}
)lua";

// ARGV: prefix, consumer, entry, stage, progress. -> ok | cancel | moved | final
// A job taken over while its runner lived on (paused or starved past its lease) gives back
// the run it counted: that run did not stop its replica. The replica sends this once per job
// after 'moved'.
const std::string kHeartbeat = R"lua(
local P = ARGV[1]
local f = redis.call('HMGET', KEYS[1], 'status', 'runner', 'cancel')
if f[1] ~= 'running' then return 'final' end
if f[2] ~= ARGV[2] then
  redis.call('HINCRBY', KEYS[1], 'runs', -1)
  return 'moved'
end
redis.call('HSET', KEYS[1], 'stage', ARGV[4], 'progress', ARGV[5])
local p = redis.call('XPENDING', P .. 'queue', 'workers', ARGV[3], ARGV[3], 1)
if p[1] and p[1][2] == ARGV[2] then redis.call('XCLAIM', P .. 'queue', 'workers', ARGV[2], 0, ARGV[3], 'JUSTID') end
if f[3] == '1' then return 'cancel' end
return 'ok'
)lua";

// ARGV: prefix, id, status, now, ttl ms, metrics, error, bytes, budget, entry, max finished.
// -> 1 written | 0 the job had already ended (or is gone) | -1 no complete result stored
const std::string kFinish = kLib + R"lua(
local s = redis.call('HGET', KEYS[1], 'status')
local rk = P .. 'result:' .. ARGV[2]
if s ~= 'queued' and s ~= 'running' then
  redis.call('XACK', P .. 'queue', 'workers', ARGV[10])
  redis.call('XDEL', P .. 'queue', ARGV[10])
  return 0
end
if ARGV[3] == 'succeeded' and redis.call('HEXISTS', rk, 'n') == 0 then return -1 end
redis.call('XACK', P .. 'queue', 'workers', ARGV[10])
redis.call('XDEL', P .. 'queue', ARGV[10])
if s == 'queued' then redis.call('DECR', P .. 'queued') end
local now, ttl = tonumber(ARGV[4]), tonumber(ARGV[5])
redis.call('HSET', KEYS[1], 'status', ARGV[3], 'stage', ARGV[3], 'finished', ARGV[4])
redis.call('HDEL', KEYS[1], 'request')
if ARGV[7] ~= '' then redis.call('HSET', KEYS[1], 'error', ARGV[7]) end
redis.call('PEXPIRE', KEYS[1], ttl)
ended(ARGV[2], now, ttl, tonumber(ARGV[11]))
if ARGV[3] ~= 'succeeded' or redis.call('EXISTS', KEYS[1]) == 0 then return 1 end
redis.call('HSET', KEYS[1], 'progress', '1', 'metrics', ARGV[6])
redis.call('ZADD', P .. 'results', now, ARGV[2])
redis.call('HSET', P .. 'result_sizes', ARGV[2], ARGV[8])
redis.call('PEXPIRE', rk, ttl)
local total = redis.call('INCRBY', P .. 'result_bytes', tonumber(ARGV[8]))
while total > tonumber(ARGV[9]) do
  local oldest = redis.call('ZRANGE', P .. 'results', 0, 0)[1]
  if not oldest then break end
  total = drop_result(oldest)
  local job = P .. 'job:' .. oldest
  if redis.call('EXISTS', job) == 1 then redis.call('HSET', job, 'expired', '1') end
end
return 1
)lua";

// ARGV: prefix, now, ttl ms, max finished. -> 0 unknown | 1
const std::string kCancel = kLib + R"lua(
local f = redis.call('HMGET', KEYS[1], 'status', 'entry')
if not f[1] then return 0 end
if f[1] == 'queued' then
  redis.call('DECR', P .. 'queued')
  redis.call('HSET', KEYS[1], 'status', 'cancelled', 'stage', 'cancelled', 'finished', ARGV[2], 'cancel', '1')
  redis.call('HDEL', KEYS[1], 'request')
  -- Its entry stays until a replica reads it (and drops it, the job having ended): an entry
  -- deleted before the group has read it would make the group's lag unknown (XINFO GROUPS),
  -- which the autoscaler reads.
  redis.call('PEXPIRE', KEYS[1], ARGV[3])
  ended(string.sub(KEYS[1], #P + 5), tonumber(ARGV[2]), tonumber(ARGV[3]), tonumber(ARGV[4]))
elseif f[1] == 'running' then
  redis.call('HSET', KEYS[1], 'cancel', '1')
end
return 1
)lua";

// ARGV: prefix, consumer, entry, idle ms. -> 1 handed back | 0 not this replica's
const std::string kHandBack = R"lua(
local P = ARGV[1]
local f = redis.call('HMGET', KEYS[1], 'status', 'runner')
if f[1] ~= 'running' or f[2] ~= ARGV[2] then return 0 end
redis.call('HSET', KEYS[1], 'status', 'queued', 'stage', 'queued', 'progress', '0')
redis.call('HINCRBY', KEYS[1], 'runs', -1)
redis.call('INCR', P .. 'queued')
local p = redis.call('XPENDING', P .. 'queue', 'workers', ARGV[3], ARGV[3], 1)
if p[1] and p[1][2] == ARGV[2] then
  redis.call('XCLAIM', P .. 'queue', 'workers', ARGV[2], 0, ARGV[3], 'IDLE', ARGV[4], 'JUSTID')
end
return 1
)lua";

long long now_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::chrono::system_clock::time_point from_ms(const std::string& s) {
    if (s.empty()) return {};
    return std::chrono::system_clock::time_point(std::chrono::milliseconds(std::atoll(s.c_str())));
}

std::string foam_json(const api::FoamOptions& f) {
    json o = json::object();
    o["patch_types"] = f.patch_types;
    if (f.slab_thickness) o["slab_thickness"] = *f.slab_thickness;
    return o.dump();
}

// The two below read what this store wrote; what they cannot read (a damaged store) gives
// the defaults rather than failing the request.
api::FoamOptions foam_of(const std::string& s) {
    api::FoamOptions f;
    const json o = json::parse(s, nullptr, false);
    if (!o.is_object()) return f;
    if (o.contains("patch_types") && o["patch_types"].is_object())
        for (const auto& [tag, type] : o["patch_types"].items())
            if (type.is_string()) f.patch_types[tag] = type.get<std::string>();
    if (o.contains("slab_thickness") && o["slab_thickness"].is_number()) f.slab_thickness = o["slab_thickness"].get<double>();
    return f;
}

api::Problem problem_of_json(const std::string& s) {
    json o = json::parse(s, nullptr, false);
    if (!o.is_object()) o = json::object();
    api::Problem p;
    p.status = o.value("status", 500);
    p.type = o.value("type", "");
    p.title = o.value("title", "");
    p.detail = o.value("detail", "");
    p.pointer = o.value("pointer", "");
    return p;
}

std::string str(const redis::Reply& r) { return r.kind == redis::Reply::Kind::String || r.kind == redis::Reply::Kind::Status ? r.str : ""; }

std::string hostname() {
    char buf[256] = {0};
    if (gethostname(buf, sizeof buf - 1) != 0) return "meshd";
    return buf;
}

}  // namespace

class RedisStore::Pool {
public:
    Pool(redis::Endpoint e, std::chrono::milliseconds timeout) : endpoint_(std::move(e)), timeout_(timeout) {}
    std::unique_ptr<redis::Connection> take() {
        {
            std::lock_guard<std::mutex> lock(m_);
            if (!free_.empty()) {
                auto c = std::move(free_.back());
                free_.pop_back();
                return c;
            }
        }
        return std::make_unique<redis::Connection>(endpoint_, timeout_);
    }
    void give(std::unique_ptr<redis::Connection> c) {
        std::lock_guard<std::mutex> lock(m_);
        if (free_.size() < 32) free_.push_back(std::move(c));
    }

private:
    redis::Endpoint endpoint_;
    std::chrono::milliseconds timeout_;
    std::mutex m_;
    std::vector<std::unique_ptr<redis::Connection>> free_;
};

RedisStore::RedisStore(const Config& config, JobManager& runner, Metrics& metrics)
    : config_(config), runner_(runner), metrics_(metrics), endpoint_(redis::parse_url(config.store)) {
    if (!config.store_password.empty()) endpoint_.password = config.store_password;
    // Unique per process: a restarted replica is a new consumer, and the jobs its previous
    // life held are taken over like any lapsed lease.
    consumer_ = hostname() + "-" + std::to_string(getpid()) + "-" + JobManager::new_id().substr(0, 8);
    pool_ = std::make_unique<Pool>(endpoint_, std::chrono::milliseconds(2000));
}

RedisStore::~RedisStore() {
    stop_claiming();
    stop();
}

long long RedisStore::lease_ms() const { return std::max<long long>(1, std::llround(config_.lease_s * 1000)); }

// 0 (a TTL under half a millisecond) makes PEXPIRE delete the record and the result as the
// job ends, as the memory store forgets them; 1 ms left both readable within that
// millisecond, and a poll that saw the job end could still fetch its mesh.
std::string RedisStore::ttl_ms() const {
    return std::to_string(std::max<long long>(0, std::llround(config_.job_ttl_s * 1000)));
}

std::string RedisStore::key(const std::string& kind, const std::string& id) const {
    return id.empty() ? kPrefix + kind : kPrefix + kind + ":" + id;
}

redis::Reply RedisStore::eval(redis::Connection& c, const std::string& script, const std::string& id,
                              const std::vector<std::string>& args) {
    return eval_on(c, script, key("job", id), args);
}

redis::Reply RedisStore::eval_on(redis::Connection& c, const std::string& script, const std::string& first_key,
                                 const std::vector<std::string>& args) {
    std::vector<std::string> argv{"EVAL", script, "1", first_key, kPrefix};
    argv.insert(argv.end(), args.begin(), args.end());
    redis::Reply r = c.command(argv);
    if (r.is_error()) throw StoreRefused("store script failed: " + r.str);
    return r;
}

template <class F>
auto RedisStore::with_store(const char* op, F&& f) {
    auto c = pool_->take();
    const auto t0 = Clock::now();
    try {
        auto out = f(*c);
        metrics_.store_op(op, std::chrono::duration<double>(Clock::now() - t0).count(), true);
        pool_->give(std::move(c));
        return out;
    } catch (const redis::Unavailable& e) {
        metrics_.store_op(op, std::chrono::duration<double>(Clock::now() - t0).count(), false);
        throw StoreUnavailable(e.what());
    } catch (const StoreRefused& e) {
        // Redis answered with an error (out of memory under noeviction, a read-only
        // replica after a failover): the store cannot take this now.
        metrics_.store_op(op, std::chrono::duration<double>(Clock::now() - t0).count(), false);
        spdlog::error("job store refused {}: {}", op, e.what());
        throw StoreUnavailable(e.what());
    }
}

void RedisStore::ensure_group(redis::Connection& c) {
    {
        std::lock_guard<std::mutex> lock(m_);
        if (group_ready_) return;
    }
    const redis::Reply r = c.command({"XGROUP", "CREATE", key("queue"), kGroup, "0", "MKSTREAM"});
    if (r.is_error() && r.str.rfind("BUSYGROUP", 0) != 0) throw std::runtime_error("store: cannot create the consumer group: " + r.str);
    std::lock_guard<std::mutex> lock(m_);
    group_ready_ = true;
}

void RedisStore::start() {
    claimer_ = std::thread([this] { claim_loop(); });
    heartbeat_ = std::thread([this] { heartbeat_loop(); });
    writer_ = std::thread([this] { writer_loop(); });
    spdlog::info("shared job store {}, this replica its consumer {} (lease {} s)", endpoint_.describe(), consumer_, config_.lease_s);
}

void RedisStore::stop_claiming() {
    claiming_ = false;
    cv_.notify_all();
    if (claimer_.joinable()) claimer_.join();
}

void RedisStore::stop() {
    {
        // Outcomes not yet written get a few seconds more to reach the store (the drain has
        // had its time already; an orchestrator's grace is the drain plus about 5 s). What
        // is left is run again elsewhere once its lease lapses.
        std::lock_guard<std::mutex> lock(m_);
        writer_stop_ = true;
        writer_deadline_ = Clock::now() + std::chrono::seconds(4);
    }
    cv_.notify_all();
    if (writer_.joinable()) writer_.join();
    stopping_ = true;
    cv_.notify_all();
    if (claimer_.joinable()) claimer_.join();
    if (heartbeat_.joinable()) heartbeat_.join();
}

void RedisStore::pause(std::chrono::milliseconds d) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait_for(lock, d, [&] { return stopping_.load() || !claiming_.load(); });
}

// ---- submitting and reading (HTTP threads) ----

Submission RedisStore::submit(const std::string& body, api::MeshRequest request, double, const std::string& owner,
                              size_t owner_share) {
    if (!claiming_) return {Submission::Refusal::Draining, ""};
    const std::string foam = foam_json(request.foam);
    return with_store("submit", [&](redis::Connection& c) {
        for (;;) {
            const std::string id = JobManager::new_id();
            const redis::Reply r =
                eval(c, kSubmit, id, {id, std::to_string(config_.queue_length), std::to_string(now_ms()), body, foam, owner,
                                      std::to_string(owner_share)});
            if (r.integer == -1) continue;  // an id already taken (2^-128): draw again
            if (r.integer == -2) return Submission{Submission::Refusal::OwnerShare, ""};
            if (r.integer == 0) return Submission{Submission::Refusal::QueueFull, ""};
            return Submission{Submission::Refusal::None, id};
        }
    });
}

namespace {

const std::vector<std::string> kInfoFields{"status", "stage", "progress", "submitted", "started", "finished",
                                           "metrics", "error", "expired", "owner", "foam"};

std::optional<JobInfo> info_from(const std::string& id, const redis::Reply& r, std::string* foam = nullptr) {
    if (r.elements.size() != kInfoFields.size() || r.elements[0].is_nil()) return std::nullopt;
    auto field = [&](size_t i) { return str(r.elements[i]); };
    JobInfo j;
    j.id = id;
    const auto status = parse_status(field(0));
    if (!status) return std::nullopt;
    j.status = *status;
    j.stage = field(1);
    j.progress = field(2).empty() ? 0.0 : std::atof(field(2).c_str());
    j.submitted = from_ms(field(3));
    j.started = from_ms(field(4));
    j.finished = from_ms(field(5));
    j.metrics = field(6);
    if (!field(7).empty()) j.error = problem_of_json(field(7));
    j.expired = field(8) == "1";
    j.owner = field(9);
    if (foam) *foam = field(10);
    return j;
}

}  // namespace

std::vector<std::string> RedisStore::info_command(const std::string& id) const {
    std::vector<std::string> cmd{"HMGET", key("job", id)};
    cmd.insert(cmd.end(), kInfoFields.begin(), kInfoFields.end());
    return cmd;
}

std::optional<JobInfo> RedisStore::info(const std::string& id) {
    return with_store("status", [&](redis::Connection& c) { return info_from(id, c.command(info_command(id))); });
}

std::optional<JobMesh> RedisStore::mesh(const std::string& id) {
    return with_store("mesh", [&](redis::Connection& c) -> std::optional<JobMesh> {
        std::string foam;
        auto i = info_from(id, c.command(info_command(id)), &foam);
        if (!i) return std::nullopt;
        JobMesh out;
        out.info = *i;
        out.foam = foam_of(foam);
        if (i->status != JobStatus::Succeeded || i->expired) return out;
        const std::string rk = key("result", id);
        const redis::Reply n = c.command({"HGET", rk, "n"});
        if (n.is_nil()) {
            out.info.expired = true;  // evicted between the two reads
            return out;
        }
        std::string bytes;
        const long chunks = std::atol(n.str.c_str());
        for (long k = 0; k < chunks; ++k) {
            const redis::Reply part = c.command({"HGET", rk, std::to_string(k)});
            if (part.is_nil()) {
                out.info.expired = true;
                return out;
            }
            bytes += part.str;
        }
        try {
            out.result = std::make_shared<const core::MeshResult>(api::decode_result(bytes));
        } catch (const api::StoredResultError& e) {
            // Not what this replica wrote (a store shared with another version, or damaged):
            // the client gets "expired" and can submit again.
            spdlog::error("job {}: its stored result cannot be read ({}); answered as expired", id, e.what());
            out.info.expired = true;
        }
        return out;
    });
}

std::optional<JobInfo> RedisStore::cancel(const std::string& id) {
    const redis::Reply r = with_store("cancel", [&](redis::Connection& c) {
        return eval(c, kCancel, id, {std::to_string(now_ms()), ttl_ms(), std::to_string(config_.max_finished_jobs)});
    });
    if (r.integer == 0) return std::nullopt;
    return info(id);
}

double RedisStore::take_token(const std::string& owner, double rate, double burst) {
    const redis::Reply r = with_store("rate", [&](redis::Connection& c) {
        return eval_on(c, kToken, key("rate", owner), {std::to_string(rate), std::to_string(burst)});
    });
    return static_cast<double>(r.integer) / 1000.0;
}

bool RedisStore::reachable() {
    auto c = pool_->take();
    const bool ok = c->ping();
    metrics_.set_store_up(ok);
    if (ok) pool_->give(std::move(c));
    return ok;
}

size_t RedisStore::queued() {
    try {
        return with_store("queued", [&](redis::Connection& c) {
            const redis::Reply r = c.command({"GET", key("queued")});
            return r.is_nil() ? size_t{0} : static_cast<size_t>(std::max(0LL, std::atoll(r.str.c_str())));
        });
    } catch (const StoreUnavailable&) {
        return 0;
    }
}

size_t RedisStore::kept() {
    return with_store("kept", [&](redis::Connection& c) {
        // KEYS[1] is only there for the Cluster's routing: any key of the tag will do.
        const redis::Reply r = eval_on(c, kKept, key("finished"), {std::to_string(now_ms()), ttl_ms(), std::to_string(config_.max_finished_jobs)});
        return static_cast<size_t>(std::max(0LL, r.integer));
    });
}

// ---- claiming (the claimer thread) ----

void RedisStore::claim_loop() {
    redis::Connection c(endpoint_, std::chrono::milliseconds(std::max<long long>(2000, lease_ms())));
    auto backoff = std::chrono::milliseconds(100);
    auto next_sweep = Clock::now();
    while (claiming_ && !stopping_) {
        // Claim only for a worker that is free now: what waits stays in the shared queue,
        // where any replica can take it.
        runner_.wait_idle(std::chrono::milliseconds(200));
        if (!claiming_ || stopping_ || runner_.idle_workers() == 0) continue;
        try {
            ensure_group(c);
            if (Clock::now() >= next_sweep) {
                forget_dead_consumers(c);
                next_sweep = Clock::now() + std::chrono::minutes(1);
            }
            claim_one(c);
            backoff = std::chrono::milliseconds(100);
            metrics_.set_store_up(true);
        } catch (const redis::Unavailable& e) {
            metrics_.store_op("claim", 0.0, false);
            metrics_.set_store_up(false);
            spdlog::warn("job store: {}; retrying in {} ms", e.what(), backoff.count());
            {
                std::lock_guard<std::mutex> lock(m_);
                group_ready_ = false;  // a Redis that restarted empty has no group
            }
            pause(backoff);
            backoff = std::min(backoff * 2, std::chrono::milliseconds(2000));
        } catch (const std::exception& e) {
            spdlog::error("job store: {}", e.what());
            {
                std::lock_guard<std::mutex> lock(m_);
                group_ready_ = false;
            }
            pause(std::chrono::milliseconds(1000));
        }
    }
}

void RedisStore::forget_dead_consumers(redis::Connection& c) {
    // Every replica that ever ran left a consumer in the group; those holding nothing and
    // silent for long are dropped (a live one that was only quiet is made again by its next
    // read, with nothing lost: it held nothing).
    const long long quiet_ms = std::max<long long>(600'000, 10 * lease_ms());
    const redis::Reply r = c.command({"XINFO", "CONSUMERS", key("queue"), kGroup});
    if (r.kind != redis::Reply::Kind::Array) return;
    for (const redis::Reply& consumer : r.elements) {
        std::string name;
        long long pending = -1, idle = 0;
        for (size_t i = 0; i + 1 < consumer.elements.size(); i += 2) {
            const std::string& field = consumer.elements[i].str;
            const redis::Reply& v = consumer.elements[i + 1];
            if (field == "name") name = v.str;
            else if (field == "pending") pending = v.integer;
            else if (field == "idle") idle = v.integer;
        }
        if (name.empty() || name == consumer_ || pending != 0 || idle < quiet_ms) continue;
        c.command({"XGROUP", "DELCONSUMER", key("queue"), kGroup, name});
        spdlog::info("job store: dropped the consumer {} (nothing pending, silent {} s)", name, idle / 1000);
    }
}

bool RedisStore::claim_one(redis::Connection& c) {
    const std::string lease = std::to_string(lease_ms());
    // First an entry whose replica stopped renewing its lease (or handed it back).
    // The scan goes on from where the last one ended (each looks at a few entries), so
    // that every pending entry is looked at in turn.
    const redis::Reply ac =
        c.command({"XAUTOCLAIM", key("queue"), kGroup, consumer_, lease, autoclaim_cursor_, "COUNT", "1"});
    if (ac.is_error()) throw std::runtime_error("XAUTOCLAIM: " + ac.str);
    if (!ac.elements.empty()) autoclaim_cursor_ = ac.elements[0].str.empty() ? "0-0" : ac.elements[0].str;
    if (ac.elements.size() >= 2) {
        for (const redis::Reply& e : ac.elements[1].elements) {
            if (e.elements.size() < 2 || e.elements[1].elements.size() < 2) continue;
            start_entry(c, e.elements[0].str, e.elements[1].elements[1].str, true);
            return true;
        }
    }
    // Then a new one, waiting for it a little.
    const redis::Reply r =
        c.command({"XREADGROUP", "GROUP", kGroup, consumer_, "COUNT", "1", "BLOCK", "500", "STREAMS", key("queue"), ">"});
    if (r.is_error()) throw std::runtime_error("XREADGROUP: " + r.str);
    if (r.is_nil() || r.elements.empty()) return false;
    for (const redis::Reply& stream : r.elements) {
        if (stream.elements.size() < 2) continue;
        for (const redis::Reply& e : stream.elements[1].elements) {
            if (e.elements.size() < 2 || e.elements[1].elements.size() < 2) continue;
            start_entry(c, e.elements[0].str, e.elements[1].elements[1].str, false);
            return true;
        }
    }
    return false;
}

void RedisStore::start_entry(redis::Connection& c, const std::string& entry, const std::string& id, bool reclaimed) {
    const redis::Reply r = eval(c, kStart, id, {consumer_, std::to_string(now_ms()), std::to_string(kMaxRuns), entry});
    const std::string what = r.elements.empty() ? "" : r.elements[0].str;
    if (what != "run" && what != "poison") {
        // Ended (cancelled while queued), forgotten, or an entry that is not the job's own.
        c.pipeline({{"XACK", key("queue"), kGroup, entry}, {"XDEL", key("queue"), entry}});
        return;
    }
    metrics_.store_event(reclaimed ? "reclaimed" : "claimed");
    if (reclaimed) spdlog::info("job {} taken over (its lease lapsed or it was handed back)", id);
    auto job = std::make_shared<Job>();
    job->id = id;
    job->stage = "starting";
    job->on_finish = [this](Job& j) { return finish(j); };
    {
        std::lock_guard<std::mutex> lock(m_);
        inflight_[id] = InFlight{job, entry};
    }
    std::optional<api::Problem> refused;
    api::MeshRequest request;
    if (what == "poison") {
        refused = api::Problem{500, "/v1/problems/lost-job", "Job lost",
                               "the job was started " + r.elements[1].str + " times and its replica stopped each time", ""};
    } else {
        const auto t0 = Clock::now();
        try {
            request = api::parse_request(r.elements[1].str);
        } catch (const api::RequestError& e) {
            refused = e.problem();  // a replica of another version: its parser disagrees
        }
        job->parse_s = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    if (refused) {
        {
            std::lock_guard<std::mutex> lock(job->m);
            job->status = JobStatus::Failed;
            job->error = refused;
        }
        finish(*job);
        return;
    }
    if (!runner_.run_external(job, std::move(request))) {
        // Draining since the claim: give it back at once.
        hand_back(c, id, entry);
        std::lock_guard<std::mutex> lock(m_);
        inflight_.erase(id);
    }
}

void RedisStore::hand_back(redis::Connection& c, const std::string& id, const std::string& entry) {
    // Idle as if its lease had lapsed a day ago: the next XAUTOCLAIM anywhere takes it.
    eval(c, kHandBack, id, {consumer_, entry, "86400000"});
    metrics_.store_event("handed_back");
    spdlog::info("job {} handed back to the queue", id);
}

// ---- the heartbeat: leases, progress, cancellation ----

void RedisStore::heartbeat_loop() {
    redis::Connection c(endpoint_, std::chrono::milliseconds(2000));
    // Several beats per lease, and at least three a second for cancellation.
    const auto period = std::chrono::milliseconds(std::clamp<long long>(lease_ms() / 4, 20, 300));
    while (!stopping_) {
        std::vector<std::pair<std::string, InFlight>> jobs;
        {
            std::lock_guard<std::mutex> lock(m_);
            // A moved job was told once (its run given back); its worker is stopping it.
            for (const auto& j : inflight_)
                if (!j.second.moved) jobs.push_back(j);
        }
        if (!jobs.empty()) {
            std::vector<std::vector<std::string>> cmds;
            for (const auto& [id, f] : jobs) {
                std::string stage, progress;
                {
                    std::lock_guard<std::mutex> lock(f.job->m);
                    stage = f.job->stage;
                    progress = std::to_string(f.job->progress);
                }
                cmds.push_back({"EVAL", kHeartbeat, "1", key("job", id), kPrefix, consumer_, f.entry, stage, progress});
            }
            try {
                const auto t0 = Clock::now();
                const std::vector<redis::Reply> replies = c.pipeline(cmds);
                metrics_.store_op("heartbeat", std::chrono::duration<double>(Clock::now() - t0).count(), true);
                std::lock_guard<std::mutex> lock(m_);
                for (size_t i = 0; i < jobs.size(); ++i) {
                    const std::string& what = replies[i].str;
                    auto it = inflight_.find(jobs[i].first);
                    if (it == inflight_.end() || what == "ok" || replies[i].is_error()) continue;
                    if (what == "cancel") it->second.user_cancelled = true;
                    else it->second.moved = true;  // taken over, or ended elsewhere
                    it->second.job->cancel = true;
                }
            } catch (const redis::Unavailable& e) {
                metrics_.store_op("heartbeat", 0.0, false);
                spdlog::warn("job store heartbeat: {}", e.what());
            }
        }
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait_for(lock, period, [&] { return stopping_.load(); });
    }
}

// ---- the end of a claimed job (a worker thread) ----

std::string RedisStore::finish(Job& job) {
    InFlight f;
    {
        std::lock_guard<std::mutex> lock(m_);
        auto it = inflight_.find(job.id);
        if (it == inflight_.end()) return "lost";
        f = it->second;
    }
    JobStatus status;
    std::shared_ptr<const core::MeshResult> result;
    std::optional<api::Problem> error;
    {
        std::lock_guard<std::mutex> lock(job.m);
        status = job.status;
        result = job.result;
        error = job.error;
    }
    std::string outcome = to_string(status);
    auto forget = [&] {
        std::lock_guard<std::mutex> lock(m_);
        inflight_.erase(job.id);
    };
    if (f.moved) {
        forget();
        return "moved";
    }
    std::string bytes, metrics, problem;
    if (status == JobStatus::Cancelled && !f.user_cancelled) {
        // Stopped by this replica's drain: another replica runs it.
        try {
            with_store("hand back", [&](redis::Connection& c) {
                hand_back(c, job.id, f.entry);
                return 0;
            });
        } catch (const StoreUnavailable& e) {
            spdlog::warn("job {}: could not hand it back ({}); its lease will lapse", job.id, e.what());
        }
        forget();
        return "handed back";
    }
    if (result) {
        bytes = api::encode_result(*result);
        metrics = api::metrics_json(*result);
        if (bytes.size() > config_.result_memory_bytes) {
            status = JobStatus::Failed;
            outcome = "failed";
            error = api::Problem{507, "/v1/problems/result-too-large", "Result too large for the store",
                                 "the mesh takes " + std::to_string(bytes.size() >> 20) + " MiB stored, more than the store's result budget of " +
                                     std::to_string(config_.result_memory_bytes >> 20) + " MiB (--result-memory-mb): ask for fewer points",
                                 "/density"};
            bytes.clear();
        }
    }
    if (error) problem = error->to_json();
    // Written by the writer thread: this worker is free for the next job even while the
    // store is away. The job stays in flight (its lease renewed) until it is written.
    {
        std::lock_guard<std::mutex> lock(m_);
        outcomes_.push_back(Outcome{job.id, f.entry, status, std::move(bytes), std::move(metrics), std::move(problem),
                                    Clock::now() + kOutcomeRetry});
    }
    cv_.notify_all();
    return outcome;
}

void RedisStore::writer_loop() {
    redis::Connection c(endpoint_, std::chrono::milliseconds(5000));
    auto backoff = std::chrono::milliseconds(100);
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
        cv_.wait(lock, [&] { return !outcomes_.empty() || writer_stop_; });
        if (outcomes_.empty()) return;
        if (writer_stop_ && Clock::now() > writer_deadline_) {
            for (const Outcome& o : outcomes_)
                spdlog::error("job {}: its outcome was not stored before the replica stopped; another replica will run it again", o.id);
            outcomes_.clear();
            return;
        }
        Outcome o = outcomes_.front();
        lock.unlock();
        bool done = false;
        const auto t0 = Clock::now();
        try {
            write_outcome(c, o.id, o.entry, o.status, o.bytes, o.metrics, o.problem);
            metrics_.store_op("finish", std::chrono::duration<double>(Clock::now() - t0).count(), true);
            metrics_.set_store_up(true);
            backoff = std::chrono::milliseconds(100);
            done = true;
        } catch (const std::exception& e) {
            // Unreachable, or refused (a result not stored whole under memory pressure).
            metrics_.store_op("finish", 0.0, false);
            metrics_.set_store_up(dynamic_cast<const redis::Unavailable*>(&e) == nullptr);
            if (Clock::now() + backoff > o.until) {
                spdlog::error("job {}: its outcome could not be stored within {} s ({}); another replica will run it again",
                              o.id, kOutcomeRetry.count(), e.what());
                done = true;
            } else {
                spdlog::warn("job {}: storing its outcome: {}; retrying in {} ms", o.id, e.what(), backoff.count());
            }
        }
        lock.lock();
        if (done) {
            outcomes_.pop_front();
            inflight_.erase(o.id);
        } else {
            cv_.wait_for(lock, backoff, [&] { return writer_stop_ && Clock::now() > writer_deadline_; });
            backoff = std::min(backoff * 2, std::chrono::milliseconds(2000));
        }
    }
}

void RedisStore::write_outcome(redis::Connection& c, const std::string& id, const std::string& entry, JobStatus status,
                               const std::string& bytes, const std::string& metrics, const std::string& error) {
    const std::string rk = key("result", id);
    const std::string ttl = ttl_ms();
    if (status == JobStatus::Succeeded) {
        // The chunks, then "n": a result is complete once "n" is there. It expires by itself
        // if the script below does not take it (the job ended elsewhere meanwhile), but not
        // before the script has had time to take it and set the TTL itself (a TTL of 0 or a
        // few milliseconds would drop it first).
        // One chunk per round trip: hiredis moves the unsent rest of its output buffer after
        // every partial write, so a pipeline of all the chunks cost time quadratic in them.
        auto must = [](const redis::Reply& r) {
            if (r.is_error()) throw std::runtime_error("storing a result: " + r.str);
        };
        must(c.command({"DEL", rk}));
        size_t k = 0;
        for (size_t at = 0; at < bytes.size() || k == 0; at += kChunk, ++k)
            must(c.command({"HSET", rk, std::to_string(k), std::string_view(bytes).substr(at, kChunk)}));
        must(c.command({"HSET", rk, "n", std::to_string(k)}));
        must(c.command({"PEXPIRE", rk, std::to_string(std::max<long long>(std::stoll(ttl), kUntakenResultMs))}));
    }
    const redis::Reply r =
        eval(c, kFinish, id,
             {id, to_string(status), std::to_string(now_ms()), ttl, metrics, error, std::to_string(bytes.size()),
              std::to_string(config_.result_memory_bytes), entry, std::to_string(config_.max_finished_jobs)});
    if (r.integer == -1) throw std::runtime_error("job " + id + ": its result was not stored whole");
    if (r.integer == 0) spdlog::info("job {} had already ended elsewhere; this run's outcome is dropped", id);
}

}  // namespace meshd::server
