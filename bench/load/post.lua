-- wrk script: POST the request file named by MESHD_LOAD_REQUEST. The status counts come
-- from the server's /metrics afterwards (wrk's per-thread counters do not reach done()).
local f = assert(io.open(os.getenv("MESHD_LOAD_REQUEST"), "rb"))
wrk.method = "POST"
wrk.body = f:read("*a")
f:close()
wrk.headers["Content-Type"] = "application/json"

function done(summary, latency, requests)
  io.write(string.format("requests/s: %.1f\n", summary.requests / (summary.duration / 1e6)))
  io.write(string.format("latency p50: %.1f ms, p99: %.1f ms\n", latency:percentile(50) / 1000, latency:percentile(99) / 1000))
end
