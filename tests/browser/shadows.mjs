// Ground shadows and smart transparency on the page (docs/ALGORITHM.md §28) in headless Chromium
// against the real daemon: the Style panel shows their controls under the Fourier method; the shadow's
// slider sends style.shadow (the link carries it, the picture changes, the server takes it), the light's
// three boxes send style.shadowLight, smart transparency changes the picture again; under the exact method
// the rows are hidden and the page keeps streaming without an error (the fields stay out of its updates);
// a link with shadow= reopens with the slider there and the session's defaults holding it.
//
//   node tests/browser/shadows.mjs --binary build/lucent
//
// Exit codes: 0 passed, 1 a failure, 77 skipped (chromium or node_modules missing, outside CI).

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
if (!fs.existsSync(chromiumPath)) skip(`${chromiumPath} not found (apt-get install chromium)`);
const pwEntry = path.join(here, 'node_modules', 'playwright-core', 'index.mjs');
if (!fs.existsSync(pwEntry)) skip('playwright-core not installed (cd tests/browser && npm ci)');
const binary = opt('--binary') ?? env.LUCENT_BINARY ?? path.join(here, '..', '..', 'build', 'lucent');
const { chromium } = await import(pathToFileURL(pwEntry).href);

let failures = 0;
function check(cond, what) {
  console.log(`${cond ? 'ok  ' : 'FAIL'} ${what}`);
  if (!cond) failures++;
  return cond;
}

const proc = spawn(
  binary,
  [
    'serve',
    '--listen',
    '127.0.0.1:0',
    '--data',
    'demo:tornado',
    '--demo-size',
    '150',
    '--workers',
    '1',
    '--cache',
    'off',
  ],
  { stdio: ['ignore', 'pipe', 'pipe'] },
);
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

const browser = await chromium.launch({
  executablePath: chromiumPath,
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu'],
});
const pageErrors = [];
try {
  const context = await browser.newContext({ viewport: { width: 900, height: 700 } });
  const page = await context.newPage();
  page.on('pageerror', (e) => pageErrors.push(e.message));
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
  // Typed, then left (the blur fires the box's change event once, as a user's Tab does).
  const setNumber = async (selector, value) => {
    await page.fill(selector, String(value));
    await page.locator(selector).blur();
  };

  await page.goto(`${url}/#dataset=demo:tornado`);
  await page.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  await settled();
  const plain = await sig();
  const ids = [
    'ctl-style-shadow',
    'ctl-style-shadowLight',
    'ctl-style-shadowColored',
    'ctl-style-ground',
    'ctl-style-smartTransparency',
  ];
  const shown = await Promise.all(ids.map(rowHidden));
  check(
    shown.every((h) => h === false),
    `the Style panel shows the shadow and smart transparency controls (hidden: ${JSON.stringify(shown)})`,
  );

  let f0 = await newest();
  await setNumber('#ctl-style-shadow ~ input.num', 0.8);
  await page.waitForFunction(() => /(^|&)shadow=0\.8/.test(location.hash.slice(1)), null, { timeout: 30000 });
  await settled(f0);
  const shadowed = await sig();
  check(!(await page.evaluate(() => window.lucent.state.error)), 'the server takes style.shadow');
  check(
    diff(plain, shadowed) > 0.5,
    `the shadow on the ground changes the picture (mean difference ${diff(plain, shadowed).toFixed(2)})`,
  );

  f0 = await newest();
  await setNumber('input[name="style.shadowLight.0"]', 0);
  await setNumber('input[name="style.shadowLight.1"]', 1);
  await setNumber('input[name="style.shadowLight.2"]', 1);
  await page.waitForFunction(() => /shadowLight=0,1,1/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const tilted = await sig();
  check(!(await page.evaluate(() => window.lucent.state.error)), 'the server takes style.shadowLight');
  check(
    diff(shadowed, tilted) > 0.5,
    `another light moves the ground and its shadow (${diff(shadowed, tilted).toFixed(2)})`,
  );

  f0 = await newest();
  await setNumber('#ctl-style-smartTransparency ~ input.num', 1);
  await page.waitForFunction(() => /smartTransparency=1/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const outlined = await sig();
  check(diff(tilted, outlined) > 0.05, `smart transparency changes the picture (${diff(tilted, outlined).toFixed(3)})`);

  f0 = await newest();
  await page.selectOption('#ctl-method', 'exact');
  await settled(f0);
  const exact = await page.evaluate(() => ({
    err: window.lucent.state.error,
    method: window.lucent.state.lastFrame?.method,
  }));
  const hidden = await Promise.all(ids.map(rowHidden));
  check(
    hidden.every((h) => h === true),
    `under the exact method their rows are hidden (${JSON.stringify(hidden)})`,
  );
  check(!exact.err, `and the exact method streams without an error (${JSON.stringify(exact.err)})`);
  f0 = await newest();
  await page.selectOption('#ctl-method', 'fourier');
  await settled(f0);

  const page2 = await context.newPage();
  page2.on('pageerror', (e) => pageErrors.push(e.message));
  await page2.goto(`${url}/#dataset=demo:tornado&shadow=0.6&shadowColored=true`);
  await page2.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  const st2 = await page2.evaluate(() => ({
    v: document.querySelector('#ctl-style-shadow ~ input.num')?.value,
    colored: document.getElementById('ctl-style-shadowColored')?.checked,
    defaults: window.lucent.state.lastReady?.defaults?.style,
  }));
  check(
    st2.v === '0.6' && st2.colored === true && st2.defaults?.shadow === 0.6 && st2.defaults?.shadowColored === true,
    `a link with shadow=0.6 reopens with the slider and the session there (${JSON.stringify(st2)})`,
  );
  check(pageErrors.length === 0, `no page errors (${pageErrors.join('; ')})`);
} catch (e) {
  check(false, `exception: ${e.stack ?? e}`);
} finally {
  await browser.close();
}
console.log(`${failures} failed`);
process.exit(failures ? 1 : 0);
