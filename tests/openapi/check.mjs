// The OpenAPI document against a real OpenAPI 3.0 validator, and its request schema against
// the request parser:
//   - the document (meshd --openapi) is valid OpenAPI 3.0.3;
//   - the schema's own example and every request in examples/ pass the schema, and the
//     parser accepts them (meshd-cli meshes each);
//   - every case of the bad-request catalogue that the parser refuses as malformed (400)
//     fails the schema, and every other case (a valid shape the core refuses, 422 or 413)
//     passes it: the two agree on what a well-formed request is. The catalogue's statuses
//     are the parser's own answers (tests/api and tests/server check them).
// Usage: node check.mjs MESHD MESHD_CLI SOURCE_DIR
import { execFileSync, spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { Validator } from "@seriousme/openapi-schema-validator";
import Ajv from "ajv-draft-04";

const [meshd, cli, source] = process.argv.slice(2);
let failures = 0;
const fail = (what) => {
  failures++;
  console.error("FAIL " + what);
};

const doc = JSON.parse(execFileSync(meshd, ["--openapi"], { encoding: "utf8" }));
const result = await new Validator().validate(doc);
if (!result.valid) fail("the document is not valid OpenAPI 3.0.3: " + JSON.stringify(result.errors).slice(0, 2000));
if (doc.openapi !== "3.0.3") fail("openapi is " + doc.openapi);

// OpenAPI 3.0 schema objects are JSON Schema draft 4 with a few more keywords (example,
// nullable, ...), which a non-strict draft-04 validator skips.
const ajv = new Ajv({ strict: false, allErrors: true });
ajv.addSchema(doc, "openapi.json");
const validRequest = ajv.getSchema("openapi.json#/components/schemas/MeshRequest");
const schemaSays = (text) => {
  let body;
  try {
    body = JSON.parse(text);
  } catch {
    return { valid: false, why: "not JSON" };
  }
  const valid = validRequest(body);
  return { valid, why: valid ? "" : ajv.errorsText(validRequest.errors) };
};

// Examples: the schema's own and the repository's.
const examples = [["components/schemas/MeshRequest/example", JSON.stringify(doc.components.schemas.MeshRequest.example)]];
const exampleDir = path.join(source, "examples");
for (const f of fs.readdirSync(exampleDir).filter((f) => f.endsWith(".json")).sort())
  examples.push(["examples/" + f, fs.readFileSync(path.join(exampleDir, f), "utf8")]);
if (examples.length < 2) fail("no examples found in " + exampleDir);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "meshd-openapi-"));
for (const [name, text] of examples) {
  const s = schemaSays(text);
  if (!s.valid) fail(`${name}: the schema refuses it: ${s.why}`);
  const file = path.join(tmp, "request.json");
  fs.writeFileSync(file, text);
  const run = spawnSync(cli, [file, "-o", path.join(tmp, "mesh.json"), "--quiet"], { encoding: "utf8" });
  if (run.status !== 0) fail(`${name}: the parser refuses it (exit ${run.status}): ${run.stderr}`);
}
fs.rmSync(tmp, { recursive: true, force: true });

// The catalogue. What a schema cannot say, with the reason:
const schemaCannotSay = new Map([
  ["a point named twice", "JSON.parse keeps the last of two equal names; the parser refuses them"],
  ["a curve member named twice", "as above"],
  ["an option named twice", "as above"],
  ["a number beyond a double", "JSON.parse reads 1e400 as Infinity, a number to the schema; the parser refuses it"],
  ["a curve named with a control character and no tag", "OpenAPI 3.0 schemas cannot constrain property names"],
]);
const catalogue = JSON.parse(fs.readFileSync(path.join(source, "tests/data/bad_requests.json"), "utf8"));
let compared = 0;
for (const c of catalogue.cases) {
  const text = c.raw !== undefined ? c.raw : JSON.stringify(c.body);
  const s = schemaSays(text);
  const malformed = c.status === 400;
  if (schemaCannotSay.has(c.name)) {
    if (!malformed || !s.valid) fail(`${c.name}: listed as beyond the schema, but it is not (${s.why})`);
    continue;
  }
  compared++;
  if (malformed && s.valid) fail(`${c.name}: the parser answers 400 at "${c.pointer}", the schema accepts it`);
  if (!malformed && !s.valid) fail(`${c.name}: the parser accepts its shape (${c.status}), the schema refuses it: ${s.why}`);
}
console.log(`openapi: document valid; ${examples.length} examples; ${compared} catalogue cases agree` +
            (failures ? `; ${failures} failures` : ""));
process.exit(failures ? 1 : 0);
