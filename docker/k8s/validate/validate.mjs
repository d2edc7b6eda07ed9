// Validates the manifests in docker/k8s against the Kubernetes OpenAPI schemas, through the
// validators kubernetes-models generates from them (KEDA's through @kubernetes-models/keda),
// plus the rules meshd relies on (probe paths, grace period versus drain time, resources,
// non-root, the shared store, the autoscaler on its queue, who may reach whom).
import { readFileSync, readdirSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { parseAllDocuments } from "yaml";
import { Deployment, StatefulSet } from "kubernetes-models/apps/v1";
import { Secret, Service } from "kubernetes-models/v1";
import { NetworkPolicy } from "kubernetes-models/networking.k8s.io/v1";
import { ScaledObject, TriggerAuthentication } from "@kubernetes-models/keda/keda.sh/v1alpha1";

const models = {
  "apps/v1/Deployment": Deployment,
  "apps/v1/StatefulSet": StatefulSet,
  "v1/Service": Service,
  "v1/Secret": Secret,
  "networking.k8s.io/v1/NetworkPolicy": NetworkPolicy,
  "keda.sh/v1alpha1/ScaledObject": ScaledObject,
  "keda.sh/v1alpha1/TriggerAuthentication": TriggerAuthentication,
};
const here = dirname(fileURLToPath(import.meta.url));
const dir = join(here, "..");
const errors = [];
const seen = {};
const all = [];
for (const file of readdirSync(dir).filter((f) => f.endsWith(".yaml"))) {
  for (const doc of parseAllDocuments(readFileSync(join(dir, file), "utf8"))) {
    if (doc.errors.length) errors.push(`${file}: ${doc.errors.join("; ")}`);
    const obj = doc.toJS();
    if (!obj) continue;
    const key = `${obj.apiVersion}/${obj.kind}`;
    const Model = models[key];
    if (!Model) {
      errors.push(`${file}: no schema for ${key}`);
      continue;
    }
    try {
      new Model(obj).validate();
      seen[obj.kind] = obj;
      all.push(obj);
      console.log(`ok   ${file}: ${obj.kind} ${obj.metadata.name}`);
    } catch (e) {
      errors.push(`${file}: ${obj.kind} ${obj.metadata?.name}: ${e.message}`);
    }
  }
}
const named = (kind, name) => all.find((o) => o.kind === kind && o.metadata.name === name);
const dep = named("Deployment", "meshd");
if (!dep || !named("Service", "meshd") || !seen.ScaledObject) errors.push("expected the meshd Deployment, its Service and a ScaledObject");
if (dep) {
  const pod = dep.spec.template.spec;
  const c = pod.containers[0];
  const env = Object.fromEntries((c.env || []).map((e) => [e.name, e.value]));
  if (c.livenessProbe?.httpGet?.path !== "/livez") errors.push("liveness probe must be /livez");
  if (c.readinessProbe?.httpGet?.path !== "/readyz") errors.push("readiness probe must be /readyz");
  if (!c.startupProbe) errors.push("a startup probe is needed");
  if (!c.resources?.requests || !c.resources?.limits) errors.push("resource requests and limits are needed");
  // Probes on the probe listener: synchronous meshes and slow clients cannot hold its threads.
  const probePort = (c.ports || []).find((p) => String(p.containerPort) === String(env.MESHD_PROBE_PORT));
  if (!probePort) errors.push("MESHD_PROBE_PORT must be one of the container's ports");
  for (const [name, probe] of [["liveness", c.livenessProbe], ["readiness", c.readinessProbe], ["startup", c.startupProbe]])
    if (probePort && probe?.httpGet?.port !== probePort.name && probe?.httpGet?.port !== probePort.containerPort)
      errors.push(`the ${name} probe must use the probe port`);
  // Memory: the running jobs' budget, the kept results and 256 MiB for the rest under the limit;
  // the largest job allowed (32 MiB + 256 B per point, core::peak_bytes_for) within the budget.
  const mib = (q) => { const m = /^(\d+)(Mi|Gi)$/.exec(q || ""); return m ? Number(m[1]) * (m[2] === "Gi" ? 1024 : 1) : NaN; };
  const limit = mib(c.resources?.limits?.memory);
  const budget = Number(env.MESHD_MEMORY_BUDGET_MB ?? 1536), results = Number(env.MESHD_RESULT_MEMORY_MB ?? 1024);
  if (!(budget + results + 256 <= limit))
    errors.push(`MESHD_MEMORY_BUDGET_MB (${budget}) + MESHD_RESULT_MEMORY_MB (${results}) + 256 must fit the memory limit (${limit} MiB)`);
  const largest = 32 + (Number(env.MESHD_MAX_POINTS ?? 5000000) * 256) / 1048576;
  if (!(largest <= budget)) errors.push(`a job of MESHD_MAX_POINTS needs ${largest.toFixed(0)} MiB, more than MESHD_MEMORY_BUDGET_MB`);
  const drain = Number(env.MESHD_DRAIN_S ?? 30);
  if (!(pod.terminationGracePeriodSeconds >= drain + 5))
    errors.push(`terminationGracePeriodSeconds (${pod.terminationGracePeriodSeconds}) must exceed MESHD_DRAIN_S (${drain}) by 5 s`);
  if (!pod.securityContext?.runAsNonRoot) errors.push("pods must run as non-root");
  // A read-only root needs a writable /tmp (format=cgns writes its file there first).
  if (c.securityContext?.readOnlyRootFilesystem) {
    const tmp = (c.volumeMounts || []).find((m) => m.mountPath === "/tmp");
    const vol = tmp && (pod.volumes || []).find((v) => v.name === tmp.name);
    if (!vol?.emptyDir) errors.push("with a read-only root, /tmp must be an emptyDir");
  }
  // The shared store: its URL names the Redis Service, its password comes from a Secret.
  const store = /^redis:\/\/([^:/]+):(\d+)/.exec(env.MESHD_STORE || "");
  const redisService = store && named("Service", store[1]);
  if (!store || !redisService) errors.push("MESHD_STORE must be redis://<the Redis Service>:<port>/<db>");
  const redisSet = named("StatefulSet", "meshd-redis");
  if (!redisSet) errors.push("expected the meshd-redis StatefulSet");
  const secretRef = (c.env || []).find((e) => e.name === "MESHD_STORE_PASSWORD")?.valueFrom?.secretKeyRef;
  if (!secretRef || !named("Secret", secretRef.name)) errors.push("MESHD_STORE_PASSWORD must come from a Secret defined here");
  if (/@/.test(env.MESHD_STORE || "")) errors.push("no password in MESHD_STORE: it is logged; use MESHD_STORE_PASSWORD");
  if (redisSet) {
    const r = redisSet.spec.template.spec;
    const args = (r.containers[0].args || []).join(" ");
    if (!/--appendonly yes/.test(args)) errors.push("Redis must keep its append-only file (--appendonly yes)");
    if (!/--requirepass \$\(REDIS_PASSWORD\)/.test(args)) errors.push("Redis must require the password of the Secret");
    if (!/--maxmemory-policy noeviction/.test(args)) errors.push("Redis must not evict keys (meshd evicts results itself)");
    if (!redisSet.spec.volumeClaimTemplates?.length) errors.push("Redis needs a persistent volume");
    const port = redisService?.spec.ports?.[0]?.port;
    if (store && String(port) !== store[2]) errors.push(`MESHD_STORE's port ${store[2]} is not the Redis Service's (${port})`);
    const sel = redisService?.spec.selector || {};
    if (Object.entries(sel).some(([k, v]) => r.metadata?.labels?.[k] !== v && redisSet.spec.template.metadata.labels[k] !== v))
      errors.push("the Redis Service must select the Redis pods");
  }
  // API keys from a Secret, mounted where MESHD_API_KEYS says.
  if (env.MESHD_API_KEYS) {
    const mount = (c.volumeMounts || []).find((m) => env.MESHD_API_KEYS.startsWith(m.mountPath + "/"));
    const vol = mount && (pod.volumes || []).find((v) => v.name === mount.name);
    if (!vol?.secret || !named("Secret", vol.secret.secretName)) errors.push("MESHD_API_KEYS must be a file of a Secret defined here");
  }
  // Scaling on the queue: the stream and group meshd uses (redis_store.hpp), the lag (Redis 7).
  const so = seen.ScaledObject;
  if (so) {
    if (so.spec.scaleTargetRef.name !== dep.metadata.name) errors.push("the ScaledObject must target the Deployment");
    const t = so.spec.triggers.find((x) => x.type === "redis-streams");
    if (!t) errors.push("the ScaledObject must scale on the redis-streams trigger");
    else {
      if (t.metadata.stream !== "{meshd}:queue" || t.metadata.consumerGroup !== "workers")
        errors.push("the redis-streams trigger must read the stream {meshd}:queue and its group workers");
      if (!t.metadata.lagCount) errors.push("the redis-streams trigger must scale on lagCount (jobs waiting, not running)");
      if (store && t.metadata.address !== `${store[1]}:${store[2]}`) errors.push("the trigger must reach the same Redis as MESHD_STORE");
      const auth = named("TriggerAuthentication", t.authenticationRef?.name);
      if (!auth || auth.spec.secretTargetRef?.[0]?.name !== secretRef?.name) errors.push("the trigger must authenticate with the Redis Secret");
    }
    if (!so.spec.triggers.some((x) => x.type === "cpu")) errors.push("the ScaledObject must scale on CPU too (synchronous load)");
    if (!(so.spec.minReplicaCount >= 1)) errors.push("keep at least one replica");
  }
  // Network: meshd's HTTP port only from the clients' namespace; Redis only from meshd (and KEDA).
  const policyFor = (name) => all.find((o) => o.kind === "NetworkPolicy" && o.spec.podSelector.matchLabels?.["app.kubernetes.io/name"] === name);
  const meshdPolicy = policyFor("meshd"), redisPolicy = policyFor("meshd-redis");
  if (!meshdPolicy || !redisPolicy) errors.push("NetworkPolicies for meshd and for Redis are needed");
  if (meshdPolicy && !meshdPolicy.spec.ingress.some((i) => i.from?.some((f) => f.namespaceSelector) && i.ports?.some((p) => p.port === 8080)))
    errors.push("meshd's HTTP port must be open to the clients' namespace only");
  if (meshdPolicy && meshdPolicy.spec.ingress.some((i) => !i.from && i.ports?.some((p) => p.port === 8080)))
    errors.push("meshd's HTTP port must not be open to everyone");
  if (redisPolicy) {
    const froms = redisPolicy.spec.ingress.flatMap((i) => i.from || [{}]);
    if (froms.some((f) => !f.podSelector && !f.namespaceSelector)) errors.push("Redis must not be open to everyone");
    if (!froms.some((f) => f.podSelector?.matchLabels?.["app.kubernetes.io/name"] === "meshd" && !f.namespaceSelector))
      errors.push("Redis must admit the meshd pods");
  }
}
// docker/compose.yaml: three replicas on one Redis (append-only) behind docker/haproxy.cfg.
{
  const compose = parseAllDocuments(readFileSync(join(dir, "..", "compose.yaml"), "utf8"))[0];
  if (compose.errors.length) errors.push(`compose.yaml: ${compose.errors.join("; ")}`);
  const services = compose.toJS({ maxAliasCount: -1 }).services || {};
  const cfg = readFileSync(join(dir, "..", "haproxy.cfg"), "utf8");
  const replicas = Object.keys(services).filter((n) => /^meshd-\d+$/.test(n));
  if (replicas.length < 2) errors.push("compose.yaml: several meshd replicas are expected");
  const redisArgs = (services.redis?.command || []).join(" ");
  if (!/--appendonly yes/.test(redisArgs)) errors.push("compose.yaml: Redis must keep its append-only file");
  if (!services.redis?.volumes?.some((v) => /:\/data$/.test(v))) errors.push("compose.yaml: Redis's /data must be a volume");
  for (const name of replicas) {
    const env = services[name].environment || {};
    const m = /^redis:\/\/([^:/]+):6379/.exec(env.MESHD_STORE || "");
    if (!m || !services[m[1]]) errors.push(`compose.yaml: ${name}'s MESHD_STORE must name the Redis service`);
    if (!env.MESHD_STORE_PASSWORD) errors.push(`compose.yaml: ${name} needs MESHD_STORE_PASSWORD`);
    if (!new RegExp(`^\\s*server ${name} ${name}:8080\\s*$`, "m").test(cfg)) errors.push(`haproxy.cfg: no server line for ${name}`);
    const probe = env.MESHD_PROBE_PORT;
    if (!new RegExp(`default-server check port ${probe}\\b`).test(cfg)) errors.push(`haproxy.cfg: health checks must use the probe port ${probe}`);
  }
  if (!/option httpchk GET \/readyz/.test(cfg)) errors.push("haproxy.cfg: health checks must ask /readyz");
  if (!services.lb?.volumes?.some((v) => v.startsWith("./haproxy.cfg:"))) errors.push("compose.yaml: the balancer must load haproxy.cfg");
  if (!errors.length) console.log(`ok   compose.yaml: ${replicas.length} replicas, Redis, HAProxy`);
}
// The validator itself must refuse a broken object, or the checks above mean nothing.
try {
  new Deployment({ apiVersion: "apps/v1", kind: "Deployment", metadata: { name: "broken" },
                   spec: { replicas: "two", selector: {}, template: { spec: { containers: [{ name: 1 }] } } } }).validate();
  errors.push("the schema validator accepted a broken Deployment");
} catch (e) {
  console.log("ok   a broken Deployment is refused by the schema");
}
try {
  new ScaledObject({ apiVersion: "keda.sh/v1alpha1", kind: "ScaledObject", metadata: { name: "broken" },
                     spec: { scaleTargetRef: {}, triggers: [{ metadata: {} }] } }).validate();
  errors.push("the KEDA validator accepted a broken ScaledObject");
} catch (e) {
  console.log("ok   a broken ScaledObject is refused by KEDA's schema");
}
if (errors.length) {
  for (const e of errors) console.error("FAIL " + e);
  process.exit(1);
}
console.log("manifests valid");
