// Validates the manifests in docker/k8s against the Kubernetes OpenAPI schemas, through the
// validators kubernetes-models generates from them, plus the rules meshd relies on (probe
// paths, grace period versus drain time, resources, non-root).
import { readFileSync, readdirSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { parseAllDocuments } from "yaml";
import { Deployment } from "kubernetes-models/apps/v1";
import { Service } from "kubernetes-models/v1";
import { HorizontalPodAutoscaler } from "kubernetes-models/autoscaling/v2";

const models = {
  "apps/v1/Deployment": Deployment,
  "v1/Service": Service,
  "autoscaling/v2/HorizontalPodAutoscaler": HorizontalPodAutoscaler,
};
const here = dirname(fileURLToPath(import.meta.url));
const dir = join(here, "..");
const errors = [];
const seen = {};
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
      console.log(`ok   ${file}: ${obj.kind} ${obj.metadata.name}`);
    } catch (e) {
      errors.push(`${file}: ${obj.kind} ${obj.metadata?.name}: ${e.message}`);
    }
  }
}
const dep = seen.Deployment;
if (!dep || !seen.Service || !seen.HorizontalPodAutoscaler) errors.push("expected a Deployment, a Service and a HorizontalPodAutoscaler");
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
  // the largest job allowed (16 MiB + 256 B per point, core::peak_bytes_for) within the budget.
  const mib = (q) => { const m = /^(\d+)(Mi|Gi)$/.exec(q || ""); return m ? Number(m[1]) * (m[2] === "Gi" ? 1024 : 1) : NaN; };
  const limit = mib(c.resources?.limits?.memory);
  const budget = Number(env.MESHD_MEMORY_BUDGET_MB ?? 1536), results = Number(env.MESHD_RESULT_MEMORY_MB ?? 1024);
  if (!(budget + results + 256 <= limit))
    errors.push(`MESHD_MEMORY_BUDGET_MB (${budget}) + MESHD_RESULT_MEMORY_MB (${results}) + 256 must fit the memory limit (${limit} MiB)`);
  const largest = 16 + (Number(env.MESHD_MAX_POINTS ?? 5000000) * 256) / 1048576;
  if (!(largest <= budget)) errors.push(`a job of MESHD_MAX_POINTS needs ${largest.toFixed(0)} MiB, more than MESHD_MEMORY_BUDGET_MB`);
  const drain = Number(env.MESHD_DRAIN_S ?? 30);
  if (!(pod.terminationGracePeriodSeconds >= drain + 5))
    errors.push(`terminationGracePeriodSeconds (${pod.terminationGracePeriodSeconds}) must exceed MESHD_DRAIN_S (${drain}) by 5 s`);
  if (!pod.securityContext?.runAsNonRoot) errors.push("pods must run as non-root");
  const hpa = seen.HorizontalPodAutoscaler;
  if (hpa && hpa.spec.scaleTargetRef.name !== dep.metadata.name) errors.push("the autoscaler must target the Deployment");
  if (hpa && !hpa.spec.metrics?.some((m) => m.resource?.name === "cpu")) errors.push("the autoscaler must scale on CPU");
}
// The validator itself must refuse a broken object, or the checks above mean nothing.
try {
  new Deployment({ apiVersion: "apps/v1", kind: "Deployment", metadata: { name: "broken" },
                   spec: { replicas: "two", selector: {}, template: { spec: { containers: [{ name: 1 }] } } } }).validate();
  errors.push("the schema validator accepted a broken Deployment");
} catch (e) {
  console.log("ok   a broken Deployment is refused by the schema");
}
if (errors.length) {
  for (const e of errors) console.error("FAIL " + e);
  process.exit(1);
}
console.log("manifests valid");
