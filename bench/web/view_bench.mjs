// How the page's view copes with large meshes: headless Chromium (software WebGL, SwiftShader:
// a real GPU draws far faster; the JavaScript figures hold for any machine like this one)
// against a meshd started here. For each size: the job's time, the page's time from the
// finished job to the first frame (download, JSON parse, buffers), the time of one frame
// while panning and zooming (drawn and read back), and of building the picking grid
// on the first hover.
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
    const figures = await page.evaluate(() => {
      const v = window.meshdPage.view, gl = v.gl;
      const frame = () => {
        const s = performance.now();
        v.drawNow();
        // A pixel read back waits for the frame to be drawn (gl.finish does not, in Chromium).
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        return performance.now() - s;
      };
      frame();
      const times = [];
      for (let k = 0; k < 10; k++) {
        v.panBy(7, 3);
        times.push(frame());
        v.zoomAt(500, 400, k % 2 ? 0.8 : 1.25);
        times.push(frame());
      }
      times.sort((a, b) => a - b);
      const g = performance.now();
      v.cellAt(0.5, 0.05);
      const grid = performance.now() - g;
      return { triangles: v.mesh.triangles.length, frame: times[times.length >> 1], grid, heap: performance.memory?.usedJSHeapSize };
    });
    const shown = Date.now() - t0;
    rows.push({ scale, ...figures, shown });
    console.log(`scale ${scale}: ${figures.triangles} triangles; mesh to first frame ${shown} ms; frame ${figures.frame.toFixed(1)} ms (median of 20); picking grid ${figures.grid.toFixed(0)} ms; JS heap ${(figures.heap / 2 ** 20).toFixed(0)} MiB`);
  }
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
console.log('\n| triangles | download, parse and upload to the first frame (ms) | one frame, pan or zoom (ms) | picking grid, first hover (ms) | JS heap (MiB) |\n|---:|---:|---:|---:|---:|');
for (const r of rows) console.log(`| ${r.triangles.toLocaleString('en')} | ${r.shown} | ${r.frame.toFixed(1)} | ${r.grid.toFixed(0)} | ${(r.heap / 2 ** 20).toFixed(0)} |`);
