// How the page's view copes with large meshes: headless Chromium (software WebGL, SwiftShader:
// a real GPU draws far faster; the JavaScript figures hold for any machine like this one)
// against a meshd started here. For each size: the page's time from the finished job to the
// mesh in its buffers (binary VTK download, parse, GPU buffers), the time to draw the cells
// (the first frame, and each frame once the view stands still), of one frame while panning and
// zooming (the cached picture moved), each drawn and read back, and of building the picking
// grid on the first hover.
//
// usage: node bench/web/view_bench.mjs [scale ...]   scale multiplies the NACA 0012 example's
// sizes (default 0.1 0.05 0.03: about 0.8, 3.2 and 9 x 10^5 triangles)

import fs from 'node:fs';
import path from 'node:path';
import { ROOT, launchChromium, openPage, startMeshd } from '../../tests/web/harness.mjs';

const scales = process.argv.slice(2).map(Number);
if (!scales.length) scales.push(0.1, 0.05, 0.03);

const { proc: server, origin } = await startMeshd(['--memory-budget-mb', '8000', '--result-memory-mb', '4000']);
const browser = await launchChromium(['--js-flags=--max-old-space-size=8192']);
const rows = [];
try {
  const page = await openPage(browser, origin);
  const base = JSON.parse(fs.readFileSync(path.join(ROOT, 'examples', 'naca0012.json'), 'utf8'));
  for (const scale of scales) {
    const request = structuredClone(base);
    request.density.size = `${scale} * (${base.density.size})`;
    await page.evaluate((t) => {
      const e = document.getElementById('editor');
      e.value = t;
      e.dispatchEvent(new Event('input'));
      window.meshdPage.state.source = null;
      document.getElementById('as-job').checked = true;
    }, JSON.stringify(request));
    await page.click('#mesh');
    // The job's end as the page sees it, then the first frame.
    await page.waitForFunction(() => /fetching/.test(document.getElementById('job-status').textContent), { timeout: 600000, polling: 20 });
    const t0 = Date.now();
    await page.waitForFunction(() => !window.meshdPage.state.busy && window.meshdPage.state.source, { timeout: 600000, polling: 20 });
    const shown = Date.now() - t0;
    const figures = await page.evaluate(() => {
      const v = window.meshdPage.view, gl = v.gl;
      // A pixel read back waits for the frame to be drawn (gl.finish does not, in Chromium).
      const timed = (f) => {
        const s = performance.now();
        f();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        return performance.now() - s;
      };
      const median = (xs) => xs.sort((a, b) => a - b)[xs.length >> 1];
      // The cells drawn (into the cached picture, then shown): the first frame, and each frame
      // once the view stands still.
      const full = median([0, 1, 2].map(() => timed(() => v.refresh())));
      // Frames while the view moves: the picture, moved.
      const moved = [];
      for (let k = 0; k < 10; k++) {
        moved.push(timed(() => { v.panBy(7, 3); v.drawNow(); }));
        moved.push(timed(() => { v.zoomAt(500, 400, k % 2 ? 0.8 : 1.25); v.drawNow(); }));
      }
      v.refresh();
      const g = performance.now();
      v.cellAt(0.5, 0.05);
      const grid = performance.now() - g;
      return { triangles: v.mesh.nTriangles, cached: v.gpuCount > v.cacheAbove, full, moved: median(moved), grid, heap: performance.memory?.usedJSHeapSize };
    });
    rows.push({ scale, ...figures, shown });
    console.log(`scale ${scale}: ${figures.triangles} triangles; finished job to mesh in the page ${shown} ms; cells drawn ${figures.full.toFixed(0)} ms; frame while moving ${figures.moved.toFixed(1)} ms (median of 20${figures.cached ? '' : ', no picture: below cacheAbove'}); picking grid ${figures.grid.toFixed(0)} ms; JS heap ${(figures.heap / 2 ** 20).toFixed(0)} MiB`);
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
console.log('\n| triangles | finished job to mesh in the page: download, parse, buffers (ms) | cells drawn: first frame, and after a move (ms) | frame while panning or zooming (ms) | picking grid, first hover (ms) | JS heap (MiB) |\n|---:|---:|---:|---:|---:|---:|');
for (const r of rows) console.log(`| ${r.triangles.toLocaleString('en')} | ${r.shown} | ${r.full.toFixed(0)} | ${r.moved.toFixed(1)} | ${r.grid.toFixed(0)} | ${(r.heap / 2 ** 20).toFixed(0)} |`);
