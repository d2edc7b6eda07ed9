// The README's pictures of the page: headless Chromium against a meshd started here.
// usage: node tests/web/screenshots.mjs [out-dir]   (default docs/; MESHD, CHROMIUM as the tests)

import path from 'node:path';
import { ROOT, launchChromium, meshAndWait, openPage, pickExample, startMeshd } from './harness.mjs';

const OUT = process.argv[2] || path.join(ROOT, 'docs');
const { proc: server, origin } = await startMeshd();
const browser = await launchChromium();
try {
  const page = await openPage(browser, origin);
  const mesh = async (name) => {
    await pickExample(page, name);
    await meshAndWait(page);
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
  await pickExample(page, 'plate_with_holes');
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
