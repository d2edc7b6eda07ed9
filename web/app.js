// The page: the request editor with the examples, meshing (synchronously when small, as a job
// with progress and cancel when large), the view, the quality panel and the downloads. It
// talks only to the server that served it.

import { MeshView } from './view.js';
import { fromJson, fromVtk } from './meshdata.js';
import { place, lineOf } from './jsonpos.js';

// Meshes forecast above this many points go to a job (the server refuses the synchronous
// request with 413 before any work when its forecast exceeds the request's max_points).
const SYNC_POINTS = 150000;
const POLL_MS = 250;
const FORMATS = [
  ['json', 'JSON', 'mesh.json'], ['vtk', 'legacy VTK (binary)', 'mesh.vtk'], ['su2', 'SU2', 'mesh.su2'],
  ['msh', 'Gmsh MSH 4.1', 'mesh.msh'], ['svg', 'SVG picture', 'mesh.svg'],
  ['foam', 'OpenFOAM polyMesh (tar)', 'polyMesh.tar'], ['cgns', 'CGNS/HDF5', 'mesh.cgns'],
];
const EXAMPLE_TITLES = {
  naca0012: 'NACA 0012 in a far field',
  fig9: 'Paper, Fig. 9',
  fig10: 'Paper, Fig. 10',
  fig11: 'Paper, Fig. 11',
  plate_with_holes: 'Plate with holes',
  channel_wake: 'Channel, cylinder and wake line',
  high_lift_layers: 'High-lift wing with boundary layers',
};

const $ = (id) => document.getElementById(id);
const editor = $('editor'), gutter = $('gutter'), marks = $('marks');
const state = {
  source: null,     // what the shown mesh came from: {kind: 'sync', body} or {kind: 'job', id}
  job: null,        // the running job's id
  abort: null,      // AbortController of a synchronous request
  problems: [],     // [{problem, place}] shown in the editor
  metrics: null,
  busy: false,
};

const view = new MeshView($('canvas'), { onHover: showHover });
window.meshdPage = { view, state };  // for the browser tests and the curious

// --- server ----------------------------------------------------------------------------

function headers(extra = {}) {
  const key = $('api-key').value.trim();
  return key ? { ...extra, Authorization: `Bearer ${key}` } : extra;
}

async function call(method, path, body, signal) {
  const init = { method, headers: headers(body !== undefined ? { 'Content-Type': 'application/json' } : {}), signal };
  if (body !== undefined) init.body = body;
  return fetch(path, init);
}

async function problemOf(res) {
  const text = await res.text();
  try {
    const p = JSON.parse(text);
    if (p && typeof p === 'object' && 'status' in p) return p;
  } catch (_) { /* not JSON */ }
  return { status: res.status, title: `HTTP ${res.status}`, detail: text.slice(0, 300) };
}

// --- editor ----------------------------------------------------------------------------

function setText(text) {
  editor.value = text;
  clearProblems();
  onEdit();
}

function onEdit() {
  const lines = editor.value.split('\n').length;
  const bad = new Set(state.problems.map((p) => p.line).filter((l) => l !== undefined));
  gutter.replaceChildren(...Array.from({ length: lines }, (_, i) => {
    const s = document.createElement('span');
    s.textContent = `${i + 1}\n`;
    if (bad.has(i)) s.className = 'bad';
    return s;
  }));
  syncScroll();
  checkJson();
}

function syncScroll() {
  gutter.scrollTop = editor.scrollTop;
  placeMarks();
}

function checkJson() {
  const status = $('json-status');
  try {
    JSON.parse(editor.value);
    status.textContent = 'JSON is well formed.';
    status.classList.remove('bad');
    return true;
  } catch (e) {
    status.textContent = `JSON: ${e.message}`;
    status.classList.add('bad');
    return false;
  }
}

const lineHeight = () => parseFloat(getComputedStyle(editor).lineHeight) || 18;

// The problems' notes, each just under the line of its field, scrolled with the text.
function placeMarks() {
  const h = lineHeight(), top = parseFloat(getComputedStyle(editor).paddingTop) || 0;
  for (const m of marks.children) {
    const line = Number(m.dataset.line);
    m.style.top = `${top + (line + 1) * h - editor.scrollTop + 2}px`;
  }
}

function clearProblems() {
  state.problems = [];
  $('problems').replaceChildren();
  marks.replaceChildren();
}

// Shows a problem object (RFC 9457) from the server: in the list, and at its field.
function showProblem(p) {
  const text = editor.value;
  let where = null;
  if (p.pointer !== undefined) {
    try {
      JSON.parse(text);
      where = place(text, p.pointer);
    } catch (_) { /* the text changed into something else */ }
  }
  const entry = { problem: p, place: where, line: where ? lineOf(text, where.keyStart) : undefined };
  state.problems.push(entry);
  const li = document.createElement('li');
  li.className = 'problem';
  li.dataset.pointer = p.pointer ?? '';
  const title = document.createElement('div');
  title.className = 'title';
  title.textContent = `${p.status ?? ''} ${p.title ?? 'Problem'}`.trim();
  const detail = document.createElement('div');
  detail.className = 'detail';
  detail.textContent = p.detail ?? '';
  li.append(title, detail);
  if (p.pointer) {
    const go = document.createElement('button');
    go.type = 'button';
    go.textContent = p.pointer;
    go.setAttribute('aria-label', `Go to ${p.pointer} in the request`);
    go.addEventListener('click', () => selectPlace(entry));
    li.append(go);
  }
  $('problems').append(li);
  if (where) {
    const m = document.createElement('div');
    m.className = 'mark';
    m.dataset.line = String(entry.line);
    m.dataset.pointer = p.pointer;
    m.textContent = `${p.detail ?? p.title}`;
    marks.append(m);
  }
  onEdit();
  if (where) revealLine(entry.line);
}

function revealLine(line) {
  const h = lineHeight();
  const y = line * h;
  if (y < editor.scrollTop || y > editor.scrollTop + editor.clientHeight - 3 * h) editor.scrollTop = Math.max(0, y - 2 * h);
  syncScroll();
}

function selectPlace(entry) {
  if (!entry.place) return;
  editor.focus();
  editor.setSelectionRange(entry.place.keyStart, entry.place.end);
  revealLine(entry.line);
}

// --- meshing ---------------------------------------------------------------------------

function setBusy(busy, cancellable) {
  state.busy = busy;
  $('mesh').disabled = busy;
  $('cancel').disabled = !(busy && cancellable);
  document.body.setAttribute('aria-busy', busy ? 'true' : 'false');
}

function jobStatus(text, progress) {
  $('job').hidden = false;
  $('job-status').textContent = text;
  if (progress === undefined) $('progress').removeAttribute('value');
  else $('progress').value = progress;
}

async function meshIt() {
  if (state.busy) return;
  clearProblems();
  if (!checkJson()) {
    showProblem({ title: 'Not JSON', detail: $('json-status').textContent, status: 400 });
    return;
  }
  const body = editor.value;
  const request = JSON.parse(body);
  try {
    if (!$('as-job').checked && await meshSync(body, request)) return;
    await meshJob(body);
  } catch (e) {
    if (e.name !== 'AbortError') showProblem({ title: 'No answer', detail: String(e.message || e) });
    setBusy(false);
  }
}

// Synchronously, with max_points lowered to SYNC_POINTS: true when this settled it (a mesh or
// a problem), false when the mesh is too large for it (then a job).
async function meshSync(body, request) {
  const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
  const options = isObject(request) ? request.options : undefined;
  const own = isObject(options) ? options.max_points : undefined;
  // A request of another shape goes as it is: the server names what is wrong with it.
  const lowered = isObject(request) && (options === undefined || isObject(options)) && !(typeof own === 'number' && own <= SYNC_POINTS);
  const capped = lowered ? JSON.stringify({ ...request, options: { ...options, max_points: SYNC_POINTS } }) : body;
  state.abort = new AbortController();
  setBusy(true, true);
  jobStatus('meshing…');
  const started = performance.now();
  const res = await call('POST', '/v1/meshes?sizes=true', capped, state.abort.signal);
  if (res.ok) {
    const answer = await res.json();
    state.abort = null;
    show(fromJson(answer.mesh), answer.metrics, { kind: 'sync', body });
    jobStatus(`done in ${Math.round(performance.now() - started)} ms`, 1);
    setBusy(false);
    return true;
  }
  const p = await problemOf(res);
  state.abort = null;
  if (lowered && res.status === 413 && /too-many-points$/.test(p.type || '')) return false;
  showProblem(p);
  jobStatus('failed', 0);
  setBusy(false);
  return true;
}

async function meshJob(body) {
  setBusy(true, true);
  jobStatus('submitting…');
  const res = await call('POST', '/v1/jobs', body);
  if (res.status !== 202) {
    showProblem(await problemOf(res));
    jobStatus('refused', 0);
    setBusy(false);
    return;
  }
  const { id } = await res.json();
  state.job = id;
  $('job').dataset.job = id;
  for (;;) {
    const st = await call('GET', `/v1/jobs/${id}`);
    if (!st.ok) {
      showProblem(await problemOf(st));
      break;
    }
    const job = await st.json();
    $('job').dataset.status = job.status;
    if (job.status === 'queued') jobStatus('queued', 0);
    else if (job.status === 'running') jobStatus(`running: ${job.stage ?? ''} ${Math.round(100 * (job.progress ?? 0))}%`, job.progress ?? 0);
    else if (job.status === 'succeeded') {
      // A job's mesh is large: binary VTK (no JSON to compress and parse); its metrics are
      // in the job's status.
      jobStatus('fetching the mesh…', 1);
      const m = await call('GET', `/v1/jobs/${id}/mesh?format=vtk`);
      if (m.ok) {
        show(fromVtk(await m.arrayBuffer()), job.metrics, { kind: 'job', id });
        jobStatus(`done (job ${id})`, 1);
      } else showProblem(await problemOf(m));
      break;
    } else if (job.status === 'failed') {
      showProblem(job.error || { title: 'Failed' });
      jobStatus('failed', 0);
      break;
    } else if (job.status === 'cancelled') {
      jobStatus('cancelled', 0);
      break;
    }
    await new Promise((r) => setTimeout(r, POLL_MS));
  }
  state.job = null;
  setBusy(false);
}

async function cancel() {
  if (state.abort) {
    state.abort.abort();
    state.abort = null;
    jobStatus('cancelled', 0);
    setBusy(false);
  } else if (state.job) {
    $('cancel').disabled = true;
    jobStatus('cancelling…');
    const res = await call('DELETE', `/v1/jobs/${state.job}`);
    if (!res.ok) showProblem(await problemOf(res));
  }
}

// --- results ---------------------------------------------------------------------------

// mesh: the page's form (meshdata.js); metrics: the API's.
function show(mesh, metrics, source) {
  state.source = source;
  state.metrics = metrics;
  view.setMesh(mesh);
  $('empty').hidden = true;
  const m = metrics;
  $('canvas').setAttribute('aria-label',
    `The mesh: ${m.points} points, ${m.triangles} triangles${m.quads ? `, ${m.quads} quads` : ''}; ` +
    `boundaries ${mesh.boundaries.map((b) => b.tag).join(', ')}`);
  showLegend();
  showScale();
  showHistogram(m);
  showMetrics(m);
  $('download').disabled = false;
  $('download-status').textContent = '';
}

function hex(c) {
  return '#' + c.map((v) => Math.round(v * 255).toString(16).padStart(2, '0')).join('');
}

function showLegend() {
  $('legend').replaceChildren(...view.tags.map(({ tag, edges, colour }) => {
    const li = document.createElement('li');
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = hex(colour);
    li.append(sw, `${tag} (${edges} edges)`);
    li.dataset.tag = tag;
    return li;
  }));
}

function showScale() {
  const mode = $('colour').value;
  const box = $('scale');
  if (mode === 'plain') return box.replaceChildren();
  const bar = document.createElement('span');
  bar.className = `bar ${mode}`;
  const [lo, hi] = mode === 'quality' ? ['0.5 or less', '1'] : ['half of rho', 'twice rho'];
  const label = (text) => Object.assign(document.createElement('span'), { textContent: text });
  box.replaceChildren(label(mode === 'quality' ? 'radius ratio (quads: scaled Jacobian):' : 'edge length:'), label(lo), bar, label(hi));
  if (mode === 'size' && !(view.mesh && view.mesh.sizes)) box.append(' (no sizes in this answer)');
}

function showHistogram(m) {
  const svg = $('histogram');
  const NS = 'http://www.w3.org/2000/svg';
  const h = m.quality?.histogram || [];
  const max = Math.max(1, ...h);
  const parts = [];
  h.forEach((count, i) => {
    const r = document.createElementNS(NS, 'rect');
    const height = count ? Math.max(1, 90 * count / max) : 0;
    r.setAttribute('x', 10 + 20 * i + 1);
    r.setAttribute('y', 100 - height);
    r.setAttribute('width', 18);
    r.setAttribute('height', height);
    const t = document.createElementNS(NS, 'title');
    t.textContent = `${(i / 10).toFixed(1)}-${((i + 1) / 10).toFixed(1)}: ${count}`;
    r.append(t);
    parts.push(r);
  });
  for (let i = 0; i <= 10; i += 2) {
    const t = document.createElementNS(NS, 'text');
    t.setAttribute('x', 10 + 20 * i);
    t.setAttribute('y', 112);
    t.setAttribute('text-anchor', 'middle');
    t.textContent = (i / 10).toFixed(1);
    parts.push(t);
  }
  svg.replaceChildren(...parts);
  svg.setAttribute('aria-label', 'Quality histogram: ' + h.map((c, i) => `${(i / 10).toFixed(1)} to ${((i + 1) / 10).toFixed(1)}: ${c}`).join('; '));
}

const fmt = (v, digits = 3) => {
  if (typeof v === 'string') return v;
  return typeof v === 'number' ? (Number.isInteger(v) ? v.toLocaleString('en') : v.toPrecision(digits)) : '–';
};

function showMetrics(m) {
  const rows = [
    ['Points', m.points], ['boundary', m.boundary_points], ['interior', m.interior_points],
    ['Triangles', m.triangles],
  ];
  if (m.quads) rows.push(['Quads', m.quads]);
  rows.push(
    ['Angles (deg)'], ['min', m.angle_deg?.min], ['mean', m.angle_deg?.mean], ['max', m.angle_deg?.max],
    ['Radius ratio'], ['min', m.quality?.min], ['mean', m.quality?.mean],
    ['Size against rho'], ['mean ratio', m.size_ratio?.mean], ['within √2', m.size_ratio?.within_sqrt2],
  );
  const bl = m.boundary_layers;
  if (bl) {
    rows.push(['Boundary layers']);
    for (const w of bl) {
      rows.push(['columns', w.columns], ['layers', `${w.layers.min}–${w.layers.max}`],
                ['first height', `${fmt(w.first_height.min)}–${fmt(w.first_height.max)}`],
                ['aspect ratio max', w.aspect_ratio_max], ['scaled Jacobian min', w.scaled_jacobian_min],
                ['skew max', w.skew_max], ['columns cut back', w.cut_back.columns]);
    }
  }
  const t = m.timings_ms || {};
  rows.push(['Time (ms)'], ['boundary', t.boundary], ['interior', t.interior], ['triangulation', t.triangulation],
            ['smoothing', t.smoothing], ['total', t.total]);
  // A row of one cell is a group's heading.
  $('metrics').tBodies[0].replaceChildren(...rows.map((row) => {
    const [name, value] = row;
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    th.scope = 'row';
    th.textContent = name;
    tr.append(th);
    if (row.length === 1) {
      tr.className = 'group';
      th.colSpan = 2;
    } else {
      const td = document.createElement('td');
      td.textContent = fmt(value);
      tr.append(td);
    }
    return tr;
  }));
}

function showHover(d) {
  const out = $('hover');
  if (!d) {
    out.textContent = '';
    return;
  }
  const a = d.angles.map((x) => x.toFixed(1)).join(', ');
  const q = d.kind === 'triangle' ? `radius ratio ${d.quality.toFixed(3)}` : `scaled Jacobian ${d.quality.toFixed(3)}`;
  const s = Number.isFinite(d.size) ? `, size/rho ${d.size.toFixed(2)}` : '';
  out.textContent = `${d.kind} ${d.index}: angles ${a} deg; ${q}${s}`;
}

// --- downloads -------------------------------------------------------------------------

async function download() {
  const [fmtName, , file] = FORMATS.find((f) => f[0] === $('format').value);
  const src = state.source;
  if (!src) return;
  const status = $('download-status');
  status.textContent = `preparing ${file}…`;
  status.classList.remove('bad');
  const res = src.kind === 'sync'
    ? await call('POST', `/v1/meshes?format=${fmtName}`, src.body)
    : await call('GET', `/v1/jobs/${src.id}/mesh?format=${fmtName}`);
  if (!res.ok) {
    const p = await problemOf(res);
    status.textContent = `${p.title}: ${p.detail ?? ''}`;
    status.classList.add('bad');
    return;
  }
  const blob = await res.blob();
  window.meshdPage.lastDownload = { format: fmtName, file, blob };
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = file;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 60000);
  status.textContent = `${file}: ${blob.size.toLocaleString('en')} bytes`;
}

// --- wiring ----------------------------------------------------------------------------

async function loadExamples() {
  const sel = $('example');
  const res = await fetch('/ui/examples/index.json');
  const names = await res.json();
  const first = ['naca0012', 'fig9', 'fig10', 'fig11', 'plate_with_holes', 'channel_wake'];
  names.sort((a, b) => (first.indexOf(a) + 1 || 99) - (first.indexOf(b) + 1 || 99));
  sel.replaceChildren(...names.map((n) => new Option(EXAMPLE_TITLES[n] || n, n)));
  sel.addEventListener('change', () => loadExample(sel.value));
  await loadExample(names[0]);
}

async function loadExample(name) {
  const res = await fetch(`/ui/examples/${name}.json`);
  setText(await res.text());
}

function init() {
  $('format').replaceChildren(...FORMATS.map(([v, label]) => new Option(label, v)));
  editor.addEventListener('input', () => {
    if (state.problems.length) clearProblems();
    onEdit();
  });
  editor.addEventListener('scroll', syncScroll);
  editor.addEventListener('keydown', (e) => {
    if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) {
      e.preventDefault();
      meshIt();
    }
  });
  $('mesh').addEventListener('click', meshIt);
  $('cancel').addEventListener('click', cancel);
  $('fit').addEventListener('click', () => view.fit());
  $('colour').addEventListener('change', () => {
    view.setMode($('colour').value);
    showScale();
  });
  $('edges').addEventListener('change', () => view.setEdges($('edges').checked));
  $('download').addEventListener('click', download);
  const key = $('api-key');
  key.value = sessionStorage.getItem('meshd-api-key') || '';
  key.addEventListener('change', () => sessionStorage.setItem('meshd-api-key', key.value));
  loadExamples().then(() => { window.meshdPage.ready = true; });
}

init();
