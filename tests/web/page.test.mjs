// The web page in a real browser: headless Chromium (Debian's chromium package) driven by
// puppeteer-core, against a real meshd. Every request the page makes to anywhere but that
// server is blocked (and counted), so all of this also shows the page works with no network.
//
// usage: node --test tests/web/page.test.mjs   (MESHD=path/to/meshd, CHROMIUM=/usr/bin/chromium)

import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { ROOT, example, launchChromium, meshAndWait as meshIn, openPage, pickExample as pickIn, startMeshd } from './harness.mjs';

const WHITE = [255, 255, 255];

// Points outside each example's domain (inside an airfoil or a hole, or across a symmetry
// line), from the example files' geometry: a NACA section at 30% chord on its chord line
// (inside every 4- and 5-digit section), the centre of a circular hole. The box is the view
// that shows the point with room around it.
const OUTSIDE = {
  naca0012: [[0.3, 0, [-0.1, -0.3, 1.1, 0.3]]],
  fig9: [[0.3, 0, [-0.1, -0.3, 1.1, 0.3]]],
  fig10: [[0.3, 0.02, [-0.1, -0.3, 1.1, 0.3]], [2.0, -1.0, null]],
  fig11: [[24, 0, [-5, -30, 115, 30]], [82 + 9 * Math.cos(Math.PI / 6), -12 - 9 * Math.sin(Math.PI / 6), [75, -30, 115, 0]]],
  plate_with_holes: [[1, 1, null], [2.5, 0.6, null], [3.2, 1.4, null]],
  channel_wake: [[1.5, 0.5, [1, 0.1, 2, 0.9]]],
  high_lift_layers: [[0.3, 0.02, [-0.1, -0.3, 1.1, 0.3]]],
};

let server, origin, browser, page;
const consoleErrors = [];
const blocked = [];
const pickExample = (name) => pickIn(page, name);
const meshAndWait = () => meshIn(page);

async function api(pathname, body, format = 'json') {
  const res = await fetch(`${origin}${pathname}${pathname.includes('?') ? '&' : '?'}format=${format}`, {
    method: body === undefined ? 'GET' : 'POST',
    headers: body === undefined ? {} : { 'Content-Type': 'application/json' },
    body,
  });
  return { status: res.status, bytes: Buffer.from(await res.arrayBuffer()) };
}

// Puts a request in the editor and tells the page it changed (an input event, as typing does).
async function setRequest(text) {
  await page.evaluate((t) => {
    const e = document.getElementById('editor');
    e.value = t;
    e.dispatchEvent(new Event('input'));
  }, text);
}

// Centroid of cell `i` of an API mesh (triangles, then quads).
function centroid(mesh, corners) {
  const ps = corners.map((v) => mesh.points[v]);
  return [ps.reduce((s, p) => s + p[0], 0) / ps.length, ps.reduce((s, p) => s + p[1], 0) / ps.length];
}

// Screen pixel of a world point in the current view, and the colour there.
async function colourAt(x, y) {
  return page.evaluate((x, y) => {
    const v = window.meshdPage.view;
    const [px, py] = v.toScreen(x, y);
    return { px, py, rgb: v.pixel(px, py) };
  }, x, y);
}

before(async () => {
  ({ proc: server, origin } = await startMeshd(['--workers', '2', '--memory-budget-mb', '6000', '--max-points', '8000000']));
  browser = await launchChromium();
  page = await openPage(browser, origin, async (p) => {
    await p.setRequestInterception(true);
    p.on('request', (r) => {
      if (r.url().startsWith(origin + '/') || r.url().startsWith('blob:') || r.url().startsWith('data:')) r.continue();
      else {
        blocked.push(r.url());
        r.abort();
      }
    });
    // The browser's own note on every 4xx answer (the problem tests ask for them) is not an
    // error of the page.
    p.on('console', (m) => {
      if (m.type() === 'error' && !/^Failed to load resource: the server responded with a status of 4\d\d/.test(m.text())) consoleErrors.push(m.text());
    });
    p.on('pageerror', (e) => consoleErrors.push(String(e)));
  });
});

after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

test('the page loads: the examples are offered, the first is in the editor', async () => {
  const options = await page.$$eval('#example option', (os) => os.map((o) => o.value));
  const files = fs.readdirSync(path.join(ROOT, 'examples')).filter((f) => f.endsWith('.json')).map((f) => f.replace(/\.json$/, ''));
  assert.deepEqual([...options].sort(), [...files].sort());
  for (const wanted of ['naca0012', 'fig9', 'fig10', 'fig11', 'plate_with_holes', 'channel_wake']) assert.ok(options.includes(wanted), wanted);
  const text = await page.$eval('#editor', (e) => e.value);
  assert.deepEqual(JSON.parse(text), JSON.parse(example(options[0])));
  // Every control has a name a screen reader can say.
  const unnamed = await page.$$eval('button, select, input, textarea, canvas', (els) => els.filter((e) => {
    const labelled = e.getAttribute('aria-label') || e.getAttribute('aria-labelledby') || (e.id && document.querySelector(`label[for="${e.id}"]`)) || e.closest('label');
    return !labelled && !(e.tagName === 'BUTTON' && e.textContent.trim());
  }).map((e) => e.id || e.outerHTML.slice(0, 60)));
  assert.deepEqual(unnamed, []);
});

test('the format list is the API\'s', async () => {
  const doc = JSON.parse((await api('/v1/openapi.json')).bytes.toString());
  const enumerated = doc.paths['/v1/meshes'].post.parameters.find((p) => p.name === 'format').schema.enum;
  const offered = await page.$$eval('#format option', (os) => os.map((o) => o.value));
  assert.deepEqual([...offered].sort(), [...enumerated].sort());
});

for (const name of Object.keys(OUTSIDE)) {
  test(`example ${name} meshes and the view shows it, with nothing drawn outside the domain`, async () => {
    await pickExample(name);
    await meshAndWait();
    const problems = await page.$$eval('#problems li', (ls) => ls.map((l) => l.textContent));
    assert.deepEqual(problems, []);
    // The same request through the API, read here: the page shows that mesh.
    const answer = JSON.parse((await api('/v1/meshes', example(name))).bytes.toString());
    const shown = await page.evaluate(() => ({
      points: window.meshdPage.view.mesh.nPoints, triangles: window.meshdPage.view.mesh.nTriangles,
      quads: window.meshdPage.view.mesh.nQuads,
      table: Object.fromEntries([...document.querySelectorAll('#metrics tr')].map((r) => [r.cells[0].textContent, r.cells[1]?.textContent])),
      legend: [...document.querySelectorAll('#legend li')].map((l) => l.dataset.tag),
    }));
    assert.equal(shown.points, answer.mesh.points.length);
    assert.equal(shown.triangles, answer.mesh.triangles.length);
    assert.equal(shown.quads, (answer.mesh.quads || []).length);
    assert.equal(shown.table.Triangles, answer.metrics.triangles.toLocaleString('en'));
    assert.deepEqual(shown.legend, Object.keys(answer.mesh.boundaries));
    for (const w of answer.metrics.boundary_layers || []) {
      assert.equal(shown.table.layers, `${w.layers.min}–${w.layers.max}`);
      assert.equal(shown.table.columns, w.columns.toLocaleString('en'));
    }
    // Inside: the centroids of the largest cells (several pixels across once fitted) are drawn.
    await page.evaluate(() => window.meshdPage.view.fit());
    const cells = [...answer.mesh.triangles.map((t) => t.slice(0, 3)), ...(answer.mesh.quads || [])];
    const area = (c) => {
      const p = c.map((v) => answer.mesh.points[v]);
      return Math.abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
    };
    const largest = cells.map((c, i) => [area(c), i]).sort((a, b) => b[0] - a[0]).slice(0, 12);
    for (const [, i] of largest) {
      const [x, y] = centroid(answer.mesh, cells[i]);
      const { rgb } = await colourAt(x, y);
      assert.notDeepEqual(rgb, WHITE, `${name}: nothing drawn at the centroid (${x}, ${y}) of cell ${i}`);
    }
    // Outside: background.
    for (const [x, y, box] of OUTSIDE[name]) {
      await page.evaluate((b) => (b ? window.meshdPage.view.show(...b) : window.meshdPage.view.fit()), box);
      const { rgb } = await colourAt(x, y);
      assert.deepEqual(rgb, WHITE, `${name}: drawn at (${x}, ${y}), outside the domain`);
    }
  });
}

test('hovering a cell shows its angles and quality, computed here from the API\'s mesh', async () => {
  await pickExample('high_lift_layers');
  await meshAndWait();
  const answer = JSON.parse((await api('/v1/meshes', example('high_lift_layers'))).bytes.toString());
  assert.ok(answer.mesh.quads.length > 0);
  const angle = (p, c, n) => {
    const ax = p[0] - c[0], ay = p[1] - c[1], bx = n[0] - c[0], by = n[1] - c[1];
    return Math.acos((ax * bx + ay * by) / Math.hypot(ax, ay) / Math.hypot(bx, by)) * 180 / Math.PI;
  };
  const cases = [['triangle', answer.mesh.triangles.length >> 1, answer.mesh.triangles[answer.mesh.triangles.length >> 1]],
                 ['quad', answer.mesh.quads.length >> 1, answer.mesh.quads[answer.mesh.quads.length >> 1]]];
  for (const [kind, index, corners] of cases) {
    const ps = corners.slice(0, kind === 'quad' ? 4 : 3).map((v) => answer.mesh.points[v]);
    const [x, y] = centroid(answer.mesh, corners.slice(0, ps.length));
    // Zoom until the cell is 200 pixels across, centred, then point at its centroid.
    const extent = Math.max(...ps.map((p) => Math.hypot(p[0] - x, p[1] - y)));
    await page.evaluate((x, y, r) => window.meshdPage.view.show(x - 4 * r, y - 4 * r, x + 4 * r, y + 4 * r), x, y, extent);
    const box = await (await page.$('#canvas')).boundingBox();
    const [px, py] = await page.evaluate((x, y) => window.meshdPage.view.toScreen(x, y), x, y);
    await page.mouse.move(box.x + px, box.y + py);
    await page.waitForFunction((k) => document.getElementById('hover').textContent.startsWith(k), {}, kind);
    const text = await page.$eval('#hover', (e) => e.textContent);
    assert.match(text, new RegExp(`^${kind} ${index}:`));
    const expected = ps.map((c, k) => angle(ps[(k + ps.length - 1) % ps.length], c, ps[(k + 1) % ps.length]).toFixed(1));
    assert.ok(text.includes(`angles ${expected.join(', ')} deg`), `${text} / ${expected}`);
  }
});

test('a request with an error shows the problem next to the field its pointer names', async () => {
  await pickExample('naca0012');
  const cases = [
    // 422 from the geometry: the NACA code.
    ['"0012"', '"00x2"', '/geometry/curves/wing/code', '"code"'],
    // 400 from the parser: an option that does not exist.
    ['"smoothing_iterations": 5', '"smoothing_iterations": 5, "smoothness": 3', '/options/smoothness', '"smoothness"'],
  ];
  for (const [from, to, pointer, key] of cases) {
    const text = example('naca0012').replace(from, to);
    await setRequest(text);
    await page.click('#mesh');
    await page.waitForSelector(`#marks .mark[data-pointer="${pointer}"]`, { timeout: 30000 });
    const line = text.split('\n').findIndex((l) => l.includes(key));
    const got = await page.evaluate((p) => {
      const mark = document.querySelector(`#marks .mark[data-pointer="${p}"]`);
      const bad = [...document.querySelectorAll('#gutter .bad')].map((s) => Number(s.textContent) - 1);
      const listed = [...document.querySelectorAll('#problems li')].map((l) => l.dataset.pointer);
      return { line: Number(mark.dataset.line), bad, listed, top: mark.getBoundingClientRect().top };
    }, pointer);
    assert.equal(got.line, line);
    assert.deepEqual(got.bad, [line]);
    assert.deepEqual(got.listed, [pointer]);
    // Drawn just under that line of the text, as the browser laid out the line numbers.
    const lineBox = await page.evaluate((l) => document.querySelectorAll('#gutter span')[l].getBoundingClientRect().bottom, line);
    assert.ok(Math.abs(got.top - lineBox) < 6, `mark at ${got.top}, line ends at ${lineBox}`);
    // The problem's link selects the field in the editor.
    await page.click(`#problems li[data-pointer="${pointer}"] button`);
    const selected = await page.$eval('#editor', (e) => e.value.slice(e.selectionStart, e.selectionEnd));
    assert.ok(selected.startsWith(key), selected);
  }
  // Editing clears the marks.
  await page.type('#editor', ' ');
  assert.equal(await page.$$eval('#marks .mark', (m) => m.length), 0);
});

test('a large mesh runs as a job: its stage and progress show, and Cancel stops it', async () => {
  // The example's sizes 25 times smaller: some 2.5 million points, far above the page's
  // synchronous limit, so the server refuses the synchronous request before any work and the
  // page queues a job.
  const request = JSON.parse(example('naca0012'));
  request.density.size = `0.04 * (${request.density.size})`;
  await setRequest(JSON.stringify(request, null, 2));
  await page.click('#mesh');
  await page.waitForFunction(() => {
    const job = document.getElementById('job');
    return job.dataset.status === 'running' && document.getElementById('progress').value > 0;
  }, { timeout: 60000, polling: 50 });
  const id = await page.$eval('#job', (e) => e.dataset.job);
  assert.match(await page.$eval('#job-status', (e) => e.textContent), /^running: (boundary|interior|triangulation|smoothing|quality) \d+%$/);
  assert.equal(await page.$eval('#cancel', (e) => e.disabled), false);
  await page.click('#cancel');
  await page.waitForFunction(() => document.getElementById('job').dataset.status === 'cancelled', { timeout: 60000 });
  const status = JSON.parse((await api(`/v1/jobs/${id}`)).bytes.toString());
  assert.equal(status.status, 'cancelled');
  assert.equal(await page.$eval('#mesh', (e) => e.disabled), false);
});

async function downloads(label) {
  const sizes = {};
  for (const format of await page.$$eval('#format option', (os) => os.map((o) => o.value))) {
    await page.evaluate(() => { window.meshdPage.lastDownload = null; });
    await page.select('#format', format);
    await page.click('#download');
    await page.waitForFunction((f) => window.meshdPage.lastDownload?.format === f, { timeout: 60000 }, format);
    const got = Buffer.from(await page.evaluate(async () => {
      const b = new Uint8Array(await window.meshdPage.lastDownload.blob.arrayBuffer());
      let s = '';
      for (let i = 0; i < b.length; i += 0x8000) s += String.fromCharCode(...b.subarray(i, i + 0x8000));
      return btoa(s);
    }), 'base64');
    const want = await label(format);
    assert.equal(want.status, 200);
    if (format === 'cgns') {
      // HDF5 stamps each object with the second it was written, and checksums its headers:
      // the same length, and differences only in short runs (a 4-byte time, a 4-byte checksum,
      // at most the two side by side), under 1% of the bytes.
      assert.equal(got.length, want.bytes.length);
      let run = 0, longest = 0, differ = 0;
      for (let i = 0; i < got.length; i++) {
        run = got[i] !== want.bytes[i] ? run + 1 : 0;
        differ += run > 0;
        longest = Math.max(longest, run);
      }
      assert.ok(longest <= 8 && differ < got.length / 100, `${differ} bytes differ, in runs up to ${longest}`);
    } else if (format === 'json') {
      // The mesh byte for byte; the metrics but for the time each run took.
      const [gotMesh, gotMetrics] = got.toString().split(',"metrics":');
      const [wantMesh, wantMetrics] = want.bytes.toString().split(',"metrics":');
      assert.ok(gotMesh === wantMesh, 'json: the meshes differ');
      const untimed = (t) => {
        const m = JSON.parse(t.replace(/}\s*$/, ''));
        delete m.timings_ms;
        return m;
      };
      assert.deepEqual(untimed(gotMetrics), untimed(wantMetrics));
    } else {
      assert.ok(got.equals(want.bytes), `${format}: ${got.length} bytes, the API gives ${want.bytes.length}`);
    }
    sizes[format] = got.length;
  }
  return sizes;
}

test('each download gives the bytes the API gives (a synchronous mesh)', async () => {
  const text = example('plate_with_holes');
  await setRequest(text);
  await meshAndWait();
  assert.equal(await page.evaluate(() => window.meshdPage.state.source.kind), 'sync');
  await downloads((format) => api('/v1/meshes', text, format));
});

test('each download gives the bytes the API gives (a job)', async () => {
  const text = example('channel_wake');
  await setRequest(text);
  await page.click('#as-job');
  try {
    await meshAndWait();
  } finally {
    await page.click('#as-job');
  }
  const source = await page.evaluate(() => window.meshdPage.state.source);
  assert.equal(source.kind, 'job');
  await downloads((format) => api(`/v1/jobs/${source.id}/mesh`, undefined, format));
});

// The page's mesh as plain arrays, to compare with the API's JSON.
const pageMesh = () => page.evaluate(() => {
  const m = window.meshdPage.view.mesh;
  const pairs = (a, n) => Array.from({ length: a.length / n }, (_, i) => Array.from(a.subarray(n * i, n * i + n)));
  return {
    points: pairs(m.points, 2), triangles: pairs(m.triangles, 3), quads: pairs(m.quads, 4),
    boundaries: Object.fromEntries(m.boundaries.map((b) => [b.tag, pairs(b.edges, 2)])),
    sizes: m.sizes && Array.from(m.sizes),
  };
});

for (const name of ['channel_wake', 'high_lift_layers']) {
  test(`a job's mesh comes to the page as binary VTK: the same mesh as the API's JSON (${name})`, async () => {
    await setRequest(example(name));
    await page.click('#as-job');
    const vtk = [];
    const seen = (r) => { if (/\/v1\/jobs\/[^/]+\/mesh\?format=vtk$/.test(r.url())) vtk.push(r.url()); };
    page.on('request', seen);
    try {
      await meshAndWait();
    } finally {
      page.off('request', seen);
      await page.click('#as-job');
    }
    const source = await page.evaluate(() => window.meshdPage.state.source);
    assert.equal(source.kind, 'job');
    assert.equal(vtk.length, 1);
    const answer = JSON.parse((await api(`/v1/jobs/${source.id}/mesh?sizes=true`, undefined)).bytes.toString());
    const got = await pageMesh();
    // Coordinates are doubles in both: equal to the last bit.
    assert.deepEqual(got.points, answer.mesh.points);
    assert.deepEqual(got.triangles, answer.mesh.triangles);
    assert.deepEqual(got.quads, answer.mesh.quads || []);
    assert.deepEqual(got.boundaries, answer.mesh.boundaries);
    assert.deepEqual(got.sizes, answer.mesh.sizes);
    if (name === 'high_lift_layers') assert.ok(got.quads.length > 0);
    // The metrics table is the job's.
    const status = JSON.parse((await api(`/v1/jobs/${source.id}`)).bytes.toString());
    const table = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('#metrics tr')].map((r) => [r.cells[0].textContent, r.cells[1]?.textContent])));
    assert.equal(table.Triangles, status.metrics.triangles.toLocaleString('en'));
    assert.equal(table.Points, status.metrics.points.toLocaleString('en'));
  });
}

test('a large mesh moves as a picture while the view moves, and is drawn again once it stands still', async () => {
  await pickExample('naca0012');
  await meshAndWait();
  // Every mesh counts as large here; a pan of whole pixels inside the picture's margin.
  const DX = 40, DY = 24;
  const r = await page.evaluate((DX, DY) => {
    const v = window.meshdPage.view, gl = v.gl, c = v.canvas;
    const read = () => {
      const a = new Uint8Array(c.width * c.height * 4);
      gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, a);
      return a;
    };
    const dpr = c.width / v.size()[0], dx = Math.round(DX * dpr), dy = Math.round(DY * dpr);
    // Pixels of `b` equal to those of `a` moved by (dx, -dy) (GL rows go up), over the overlap;
    // "equal" within 16 levels: software WebGL's interpolation moves a drawn edge's shading by
    // a few levels when the whole drawing moves by a pixel (a lost or moved cell costs far more).
    const same = (a, b) => {
      let equal = 0, all = 0;
      for (let y = 0; y < c.height - dy; y++) {
        for (let x = 0; x < c.width - dx; x++) {
          const i = 4 * ((y + dy) * c.width + x), j = 4 * (y * c.width + x + dx);
          let ok = true;
          for (let k = 0; k < 3; k++) ok = ok && Math.abs(a[i + k] - b[j + k]) <= 16;
          equal += ok;
          all++;
        }
      }
      return equal / all;
    };
    const white = (a, x0, x1) => {
      let n = 0;
      for (let y = 0; y < c.height; y++) for (let x = x0; x < x1; x++) n += a[4 * (y * c.width + x)] === 255 && a[4 * (y * c.width + x) + 1] === 255 && a[4 * (y * c.width + x) + 2] === 255;
      return n;
    };
    const keep = v.cacheAbove;
    v.cacheAbove = 0;
    try {
      // Near the wing, where cells cover the whole canvas.
      v.show(-0.2, -0.3, 1.2, 0.3);
      v.refresh();
      const A = read(), s0 = { ...v.stats };
      v.panBy(DX, DY);
      v.drawNow();
      const B = read(), s1 = { ...v.stats };
      v.refresh();
      const C = read(), s2 = { ...v.stats };
      return {
        moved: s1.moved - s0.moved, drawnWhileMoving: s1.drawn - s0.drawn, drawnAfter: s2.drawn - s1.drawn,
        pictureMoved: same(A, B), settledLikeMoved: same(A, C),
        revealedWhite: white(B, 0, dx), revealed: dx * c.height,
        fullWhite: white(C, 0, dx),
      };
    } finally {
      v.cacheAbove = keep;
    }
  }, DX, DY);
  // The move drew no cells: the picture, moved by exactly the pan.
  assert.equal(r.moved, 1);
  assert.equal(r.drawnWhileMoving, 0);
  assert.ok(r.pictureMoved > 0.995, `moved picture: ${r.pictureMoved} of the pixels agree`);
  // The strip the pan uncovered came from the picture's margin: what a full drawing shows there.
  assert.equal(r.revealedWhite, r.fullWhite, `${r.revealedWhite} white pixels in the uncovered strip of ${r.revealed}`);
  // Drawn again, the cells agree with the moved picture.
  assert.equal(r.drawnAfter, 1);
  assert.ok(r.settledLikeMoved > 0.995, `settled: ${r.settledLikeMoved}`);
  // Left alone after a move, the view draws the cells again by itself.
  const [before, keep] = await page.evaluate(() => {
    const v = window.meshdPage.view, keep = v.cacheAbove;
    v.cacheAbove = 0;
    v.panBy(5, 5);
    v.drawNow();
    return [v.stats.drawn, keep];
  });
  try {
    await page.waitForFunction((n) => window.meshdPage.view.stats.drawn > n, { timeout: 30000, polling: 20 }, before);
  } finally {
    await page.evaluate((k) => { window.meshdPage.view.cacheAbove = k; }, keep);
  }
});

test('colour modes and the keyboard', async () => {
  await pickExample('plate_with_holes');
  await meshAndWait();
  const answer = JSON.parse((await api('/v1/meshes?sizes=true', example('plate_with_holes'))).bytes.toString());
  // rho at each point came with the answer: the page's size colouring has what it needs.
  assert.equal(answer.mesh.sizes.length, answer.mesh.points.length);
  assert.ok(answer.mesh.sizes.every((s) => s > 0));
  await page.evaluate(() => window.meshdPage.view.fit());
  const t = answer.mesh.triangles[0];
  const [x, y] = centroid(answer.mesh, t);
  const colours = {};
  for (const mode of ['quality', 'size', 'plain']) {
    await page.select('#colour', mode);
    colours[mode] = (await colourAt(x, y)).rgb;
  }
  assert.notDeepEqual(colours.quality, colours.size);
  assert.notDeepEqual(colours.size, colours.plain);
  // Keyboard: + zooms in by 1.25 about the centre, 0 fits again.
  await page.focus('#canvas');
  const before = await page.evaluate(() => window.meshdPage.view.view.scale);
  await page.keyboard.press('+');
  const zoomed = await page.evaluate(() => window.meshdPage.view.view.scale);
  assert.ok(Math.abs(zoomed / before - 1.25) < 1e-9);
  await page.keyboard.press('0');
  assert.ok(Math.abs(await page.evaluate(() => window.meshdPage.view.view.scale) / before - 1) < 1e-9);
  // Ctrl+Enter in the editor meshes.
  await page.evaluate(() => { window.meshdPage.state.source = null; });
  await page.focus('#editor');
  await page.keyboard.down('Control');
  await page.keyboard.press('Enter');
  await page.keyboard.up('Control');
  await page.waitForFunction(() => window.meshdPage.state.source);
});

test('a server started with --ui off serves no page, and the API still', async () => {
  const other = await startMeshd(['--ui', 'off']);
  try {
    assert.equal((await fetch(`${other.origin}/`)).status, 404);
    assert.equal((await fetch(`${other.origin}/ui/app.js`)).status, 404);
    assert.equal((await fetch(`${other.origin}/healthz`)).status, 200);
  } finally {
    other.proc.kill('SIGTERM');
  }
});

test('no console errors, and no request left the server', () => {
  assert.deepEqual(consoleErrors, []);
  assert.deepEqual(blocked, []);
});
