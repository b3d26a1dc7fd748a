// What the page's browser tests share (shadows.mjs, scenes.mjs, streamlines.mjs): the environment's checks
// (Chromium and playwright-core present, or a skip that fails under CI=true), the check counter and exit code,
// the daemon started on a free loopback port, and headless Chromium.

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
