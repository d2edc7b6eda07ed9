// The README's pictures of the page: headless Chromium against a meshd started here.
// usage: node tests/web/screenshots.mjs [out-dir]   (default docs/; MESHD, CHROMIUM as the tests)

import { spawn } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const MESHD = process.env.MESHD || path.join(ROOT, 'build', 'server', 'meshd');
const OUT = process.argv[2] || path.join(ROOT, 'docs');

const server = spawn(MESHD, ['--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
const origin = await new Promise((resolve) => {
  let log = '';
  server.stdout.on('data', (d) => {
    log += d;
    const m = /listening on ([0-9.]+):(\d+)/.exec(log);
    if (m) resolve(`http://${m[1]}:${m[2]}`);
  });
});
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--disable-dev-shm-usage', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 820 });
  await page.goto(`${origin}/`);
  await page.waitForFunction(() => window.meshdPage?.ready);
  const mesh = async (name) => {
    await page.select('#example', name);
    await page.waitForFunction((n) => document.getElementById('editor').value.includes(n), {}, name === 'high_lift_layers' ? 'boundary_layers' : '"geometry"');
    await page.evaluate(() => { window.meshdPage.state.source = null; });
    await page.click('#mesh');
    await page.waitForFunction(() => !window.meshdPage.state.busy && window.meshdPage.state.source);
  };
  // 1. The NACA 0012 example, zoomed onto the wing, a triangle under the pointer.
  await mesh('naca0012');
  await page.evaluate(() => window.meshdPage.view.show(-0.15, -0.45, 1.15, 0.45));
  const box = await (await page.$('#canvas')).boundingBox();
  const [px, py] = await page.evaluate(() => window.meshdPage.view.toScreen(0.45, 0.12));
  await page.mouse.move(box.x + px, box.y + py);
  await page.screenshot({ path: path.join(OUT, 'page-naca0012.png') });
  // 2. The high-lift wing with boundary layers, the slat gap, coloured by size against rho.
  await mesh('high_lift_layers');
  await page.select('#colour', 'size');
  await page.evaluate(() => window.meshdPage.view.show(-0.2, -0.1, 0.1, 0.08));
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(OUT, 'page-high-lift.png') });
  // 3. A problem shown at its field: hole 2 moved onto hole 1.
  await page.select('#colour', 'quality');
  await page.select('#example', 'plate_with_holes');
  await page.waitForFunction(() => document.getElementById('editor').value.includes('hole3'));
  await page.evaluate(() => {
    const e = document.getElementById('editor');
    e.value = e.value.replace('"H2": [2.8, 0.6]', '"H2": [1.9, 1.0]').replace('"center": [2.5, 0.6]', '"center": [1.6, 1.0]');
    e.dispatchEvent(new Event('input'));
  });
  await page.click('#mesh');
  await page.waitForSelector('#marks .mark');
  await page.screenshot({ path: path.join(OUT, 'page-problem.png') });
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
