// What the browser tests, the screenshots and the view benchmark share: a meshd on a free
// port, and Debian's chromium driven by puppeteer-core.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

export const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
export const MESHD = process.env.MESHD || path.join(ROOT, 'build', 'server', 'meshd');
export const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';

// Starts meshd with `args` on a port it picks; resolves to {proc, origin} once it listens.
export function startMeshd(args = []) {
  return new Promise((resolve, reject) => {
    const proc = spawn(MESHD, ['--port', '0', ...args], { stdio: ['ignore', 'pipe', 'inherit'] });
    let log = '';
    proc.stdout.on('data', (d) => {
      log += d;
      const m = /listening on ([0-9.]+):(\d+)/.exec(log);
      if (m) resolve({ proc, origin: `http://${m[1]}:${m[2]}` });
    });
    proc.on('exit', (code) => reject(new Error(`meshd exited (${code}): ${log}`)));
  });
}

// Headless chromium as root and in containers (no sandbox, no /dev/shm), WebGL in software
// (SwiftShader) where there is no GPU.
export function launchChromium(extraArgs = []) {
  return puppeteer.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--disable-dev-shm-usage', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', ...extraArgs],
  });
}

// A new page of `browser`, laptop-sized, at meshd's page, once the examples are loaded.
export async function openPage(browser, origin, setup = async () => {}) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 820 });
  await setup(page);
  await page.goto(`${origin}/`);
  await page.waitForFunction(() => window.meshdPage?.ready);
  return page;
}

export const example = (name) => fs.readFileSync(path.join(ROOT, 'examples', `${name}.json`), 'utf8');

// Picks an example in the page's list and waits until the editor holds it.
export async function pickExample(page, name) {
  await page.select('#example', name);
  await page.waitForFunction((n) => {
    try {
      return JSON.stringify(JSON.parse(document.getElementById('editor').value)) === n;
    } catch (_) {
      return false;
    }
  }, {}, JSON.stringify(JSON.parse(example(name))));
}

// Presses Mesh and waits until the page shows the new mesh.
export async function meshAndWait(page) {
  await page.evaluate(() => { window.meshdPage.state.source = null; });
  await page.click('#mesh');
  await page.waitForFunction(() => !window.meshdPage.state.busy && window.meshdPage.state.source, { timeout: 120000 });
}
