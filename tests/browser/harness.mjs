// What the page's browser tests share (shadows.mjs, scenes.mjs, streamlines.mjs): the environment's checks
// (Chromium and playwright-core present, or a skip that fails under CI=true), the check counter and exit code,
// the daemon started on a free loopback port, headless Chromium, and the helpers a test asks of a page.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const env = process.env;
const CI = /^(1|true|yes)$/i.test(env.CI ?? '');
const argv = process.argv.slice(2);
const opt = (name) => (argv.indexOf(name) >= 0 ? argv[argv.indexOf(name) + 1] : undefined);

function skip(why) {
  if (CI) {
    console.error(`FAIL: ${why} (CI=true)`);
    process.exit(1);
  }
  console.log(`SKIP: ${why}`);
  process.exit(77);
}

const chromiumPath = env.CHROMIUM ?? '/usr/bin/chromium';

/** Playwright's chromium and the lucent binary under test (--binary, LUCENT_BINARY or build/lucent), or a skip. */
export async function setup() {
  if (!fs.existsSync(chromiumPath)) skip(`${chromiumPath} not found (apt-get install chromium)`);
  const pwEntry = path.join(here, 'node_modules', 'playwright-core', 'index.mjs');
  if (!fs.existsSync(pwEntry)) skip('playwright-core not installed (cd tests/browser && npm ci)');
  const binary = opt('--binary') ?? env.LUCENT_BINARY ?? path.join(here, '..', '..', 'build', 'lucent');
  const { chromium } = await import(pathToFileURL(pwEntry).href);
  return { chromium, binary };
}

let failures = 0;
/** Prints one check's line and counts it when it fails; returns cond. */
export function check(cond, what) {
  console.log(`${cond ? 'ok  ' : 'FAIL'} ${what}`);
  if (!cond) failures++;
  return cond;
}

/** Prints the count and exits 1 when a check failed. */
export function finish() {
  console.log(`${failures} failed`);
  process.exit(failures ? 1 : 0);
}

/** Starts `lucent serve --listen 127.0.0.1:0 ARGS...`; resolves to {url, proc, lines} once it listens (the
 * daemon is killed when the test exits). */
export async function startDaemon(binary, args) {
  const proc = spawn(binary, ['serve', '--listen', '127.0.0.1:0', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
  const lines = [];
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`daemon did not start:\n${lines.join('\n')}`)), 90000);
    const onData = (buf) => {
      for (const line of buf.toString().split('\n')) {
        if (line) lines.push(line);
        const m = /listening on (http:\/\/[^\s/]+)\//.exec(line);
        if (m) {
          clearTimeout(timer);
          resolve(m[1]);
        }
      }
    };
    proc.stdout.on('data', onData);
    proc.stderr.on('data', onData);
    proc.on('exit', (code) => reject(new Error(`daemon exited (${code}):\n${lines.join('\n')}`)));
  });
  process.on('exit', () => proc.kill('SIGKILL'));
  return { url, proc, lines };
}

/** Headless Chromium as the tests run it. */
export function launch(chromium) {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu'],
  });
}

/** What the page tests ask of a page: a converged final still newer than frame `min` (not a moving frame, nor a
 * stage 1 that reuses the moving frames' opacities), the newest frame's number, a 48x32 signature of the view
 * and the mean difference of two, whether a control's row is hidden, and a number typed then left (the blur
 * fires the box's change event once, as a user's Tab does). */
export function pageHelpers(page) {
  const settled = (min = -1) =>
    page.waitForFunction(
      (m) => {
        const f = window.lucent?.state?.lastFrame;
        return !!f && f.frame > m && f.converged && !f.detail?.interactive && f.final !== false;
      },
      min,
      { timeout: 60000, polling: 100 },
    );
  const newest = () => page.evaluate(() => window.lucent.state.lastFrame?.frame ?? -1);
  const sig = () =>
    page.evaluate(() => {
      const c = document.createElement('canvas');
      c.width = 48;
      c.height = 32;
      const g = c.getContext('2d');
      g.drawImage(document.getElementById('canvas'), 0, 0, 48, 32);
      return Array.from(g.getImageData(0, 0, 48, 32).data);
    });
  const diff = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;
  const rowHidden = (id) => page.evaluate((i) => document.getElementById(i)?.closest('.row')?.hidden ?? null, id);
  const setNumber = async (selector, value) => {
    await page.fill(selector, String(value));
    await page.locator(selector).blur();
  };
  return { settled, newest, sig, diff, rowHidden, setNumber };
}
