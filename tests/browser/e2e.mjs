// End-to-end tests of the web client: headless Chromium (Debian's /usr/bin/chromium)
// driven by playwright-core against the real daemon, which this script starts on a
// free port and stops at the end. Covers issue 4's "What must be true" list.
//
//   LUCENT_BINARY=build/lucent node tests/browser/e2e.mjs [--only NAME] [--docs-screenshot docs/screenshot.png]
//
// Exit codes: 0 all passed, 1 a failure, 77 skipped (chromium or node_modules
// missing, outside CI; with CI=true missing tools fail instead).
// Screenshots of every step go to tests/browser/artifacts/ (or $LUCENT_ARTIFACTS).

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const env = process.env;
const CI = /^(1|true|yes)$/i.test(env.CI ?? '');
const argv = process.argv.slice(2);
const opt = (name) => {
  const i = argv.indexOf(name);
  return i >= 0 ? argv[i + 1] : undefined;
};

function skip(why) {
  if (CI) {
    console.error(`FAIL: ${why} (CI=true: the CI script installs it, so its absence is an error)`);
    process.exit(1);
  }
  console.log(`SKIP: ${why}`);
  process.exit(77);
}

const chromiumPath = env.CHROMIUM ?? '/usr/bin/chromium';
if (!fs.existsSync(chromiumPath)) skip(`${chromiumPath} not found (apt-get install chromium)`);
const pwEntry = path.join(here, 'node_modules', 'playwright-core', 'index.mjs');
if (!fs.existsSync(pwEntry)) skip(`playwright-core not installed (cd tests/browser && npm ci)`);
const binary = opt('--binary') ?? env.LUCENT_BINARY ?? path.join(here, '..', '..', 'build', 'lucent');
if (!fs.existsSync(binary)) {
  console.error(`FAIL: daemon binary ${binary} not found (set LUCENT_BINARY)`);
  process.exit(1);
}
const { chromium } = await import(pathToFileURL(pwEntry).href);

const artifacts = env.LUCENT_ARTIFACTS ?? path.join(here, 'artifacts');
fs.mkdirSync(artifacts, { recursive: true });
const only = opt('--only');
const docsShot = opt('--docs-screenshot') ?? env.LUCENT_DOCS_SCREENSHOT;
const T0 = Date.now();
const log = (...a) => console.log(`[${((Date.now() - T0) / 1000).toFixed(1)}s]`, ...a);

// ------------------------------------------------------------------ daemon
const DAEMON_ARGS = ['--data', 'demo:tornado', 'demo:points', '--demo-size', env.LUCENT_E2E_DEMO_SIZE ?? '80', '--workers', '1'];
const daemons = new Set();

/** Starts `lucent serve` on a free port (port 0, read back from the log); resolves {proc, url, port, lines}. */
function startDaemon(extra = [], port = 0) {
  return new Promise((resolve, reject) => {
    const args = ['serve', '--listen', `127.0.0.1:${port}`, ...DAEMON_ARGS, ...extra];
    const proc = spawn(binary, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    daemons.add(proc);
    const lines = [];
    let done = false;
    const timer = setTimeout(() => fail(new Error('daemon did not start listening within 90 s')), 90000);
    const fail = (e) => {
      if (done) return;
      done = true;
      clearTimeout(timer);
      proc.kill('SIGKILL');
      reject(new Error(`${e.message}\n${lines.slice(-20).join('\n')}`));
    };
    const onData = (buf) => {
      for (const line of buf.toString().split('\n')) {
        if (!line) continue;
        lines.push(line);
        if (env.LUCENT_E2E_VERBOSE) console.log(`  daemon: ${line}`);
        const m = /listening on (http:\/\/[^\s/]+)\//.exec(line);
        if (m && !done) {
          done = true;
          clearTimeout(timer);
          const url = m[1];
          resolve({ proc, url, port: Number(new URL(url).port), lines });
        }
      }
    };
    proc.stdout.on('data', onData);
    proc.stderr.on('data', onData);
    proc.on('exit', (code, sig) => {
      daemons.delete(proc);
      fail(new Error(`daemon exited early (code ${code}, signal ${sig})`));
    });
    proc.on('error', fail);
  });
}

function stopDaemon(d, signal = 'SIGTERM') {
  return new Promise((resolve) => {
    if (!d || d.proc.exitCode !== null || d.proc.signalCode !== null) return resolve();
    const t = setTimeout(() => d.proc.kill('SIGKILL'), 10000);
    d.proc.once('exit', () => {
      clearTimeout(t);
      resolve();
    });
    d.proc.kill(signal);
  });
}

process.on('exit', () => {
  for (const p of daemons) p.kill('SIGKILL');
});
for (const s of ['SIGINT', 'SIGTERM']) process.on(s, () => process.exit(130));

// ------------------------------------------------------------------ browser helpers
const VIEWPORT = { width: 640, height: 480 };
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'lucent-e2e-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath: chromiumPath,
  headless: true,
  viewport: VIEWPORT,
  acceptDownloads: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-quic',
    '--no-first-run', '--disable-component-update', '--disable-sync'],
});
const pageErrors = [];

async function newPage(url) {
  const page = await context.newPage();
  page.on('pageerror', (e) => pageErrors.push(`${page.url()}: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error' && !/WebSocket|Failed to load resource|ERR_CONNECTION_REFUSED/.test(m.text())) pageErrors.push(`console: ${m.text()}`);
  });
  if (url) await page.goto(url);
  return page;
}

const shot = (page, name) => page.screenshot({ path: path.join(artifacts, `${name}.png`) });

/** Waits until the newest frame reflects the last camera sent, is converged and full size. */
async function settled(page, timeout = 60000, minFrame = -1) {
  await page.waitForFunction((min) => {
    const s = window.lucent?.state;
    const f = s?.lastFrame;
    const c = document.getElementById('canvas');
    return !!f && f.frame > min && f.converged && s.confirmedSeq >= s.seq && f.width === c.width && f.height === c.height;
  }, minFrame, { timeout, polling: 100 });
}

/** A small grayscale thumbnail (48×32) of the canvas, for image comparisons. */
const signature = (page) =>
  page.evaluate(() => {
    const src = document.getElementById('canvas');
    const c = document.createElement('canvas');
    c.width = 48;
    c.height = 32;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0, 48, 32);
    const d = g.getImageData(0, 0, 48, 32).data;
    const out = [];
    for (let i = 0; i < d.length; i += 4) out.push((d[i] + d[i + 1] + d[i + 2]) / 3);
    return out;
  });
const meanDiff = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;
const spread = (a) => {
  const m = a.reduce((s, x) => s + x, 0) / a.length;
  return Math.sqrt(a.reduce((s, x) => s + (x - m) ** 2, 0) / a.length);
};
const camDiff = (a, b) => Math.max(...['position', 'focalPoint', 'viewUp'].flatMap((k) => a[k].map((x, i) => Math.abs(x - b[k][i]))));

function check(cond, what) {
  if (!cond) throw new Error(what);
}

// ------------------------------------------------------------------ tests
const tests = [];
const test = (name, fn) => tests.push({ name, fn });
const ctx = {}; // shared between the tests, in order

test('first frame', async () => {
  const page = await newPage(`${ctx.d.url}/#dataset=demo:tornado`);
  ctx.page = page;
  await page.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  await settled(page);
  const sig = await signature(page);
  check(spread(sig) > 3, `the first frame looks blank (spread ${spread(sig).toFixed(2)})`);
  const st = await page.evaluate(() => ({ conn: document.body.dataset.connection, ds: document.getElementById('dataset').value, q: document.getElementById('ctl-params-q').value, stats: document.getElementById('stats').textContent }));
  check(st.conn === 'open', `connection state ${st.conn}`);
  check(st.ds === 'demo:tornado', `dataset picker shows ${st.ds}`);
  check(st.q === '60', `q slider shows ${st.q}, not the server default 60`);
  check(/fps/.test(st.stats) && /encode/.test(st.stats) && /llvmpipe|renderer/i.test(st.stats), `stats overlay incomplete: ${st.stats}`);
  await shot(page, '01-first-frame');
});

test('drag rotates: new camera, newer frames, different image', async () => {
  const page = ctx.page;
  const before = await page.evaluate(() => ({ cam: window.lucent.camera, frame: window.lucent.state.lastFrame.frame, seq: window.lucent.state.seq }));
  const sig0 = await signature(page);
  const box = await page.locator('#canvas').boundingBox();
  const x = box.x + box.width / 2, y = box.y + box.height / 2;
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let i = 1; i <= 12; i++) await page.mouse.move(x + i * 9, y + i * 3, { steps: 1 });
  await page.mouse.up();
  const mid = await page.evaluate(() => window.lucent.state.seq);
  check(mid > before.seq, 'dragging sent no camera message');
  check(mid - before.seq <= 12, `${mid - before.seq} camera messages for 12 pointer moves: not throttled`);
  await settled(page, 60000, before.frame);
  const after = await page.evaluate(() => ({ cam: window.lucent.camera, frame: window.lucent.state.lastFrame, seq: window.lucent.state.seq }));
  check(camDiff(after.cam, before.cam) > 1e-3, 'camera did not change');
  check(after.frame.frame > before.frame, 'no newer frame');
  check(after.frame.cameraSeq === after.seq, `last frame reflects seq ${after.frame.cameraSeq}, last sent ${after.seq}`);
  const d = meanDiff(sig0, await signature(page));
  check(d > 1, `image barely changed after the drag (mean diff ${d.toFixed(2)})`);
  await shot(page, '02-after-drag');
  // keyboard: X looks along +X, R refits keeping that direction
  await page.locator('#canvas').focus();
  await page.keyboard.press('x');
  const cx = await page.evaluate(() => window.lucent.camera);
  const dir = cx.focalPoint.map((f, i) => f - cx.position[i]);
  check(dir[0] > 0 && Math.abs(dir[1]) < 1e-9 && Math.abs(dir[2]) < 1e-9 && cx.viewUp[2] === 1, `X key: ${JSON.stringify(cx)}`);
  await page.keyboard.press('ArrowLeft');
  await page.keyboard.press('r');
  await settled(page);
});

test('resize follows the window at CSS size × devicePixelRatio', async () => {
  const page = ctx.page;
  const before = await page.evaluate(() => document.getElementById('canvas').width);
  await page.setViewportSize({ width: 560, height: 480 });
  await page.waitForFunction((w) => document.getElementById('canvas').width !== w, before, { timeout: 5000 });
  await settled(page);
  const st = await page.evaluate(() => {
    const c = document.getElementById('canvas');
    const r = c.getBoundingClientRect();
    return { w: c.width, h: c.height, cssW: r.width, cssH: r.height, dpr: devicePixelRatio, frame: window.lucent.state.lastFrame };
  });
  check(st.w === Math.round(st.cssW * st.dpr) && st.h === Math.round(st.cssH * st.dpr), `canvas ${st.w}x${st.h} for ${st.cssW}x${st.cssH} CSS px`);
  check(st.frame.width === st.w && st.frame.height === st.h, `frame ${st.frame.width}x${st.frame.height}, canvas ${st.w}x${st.h}`);
  await page.setViewportSize(VIEWPORT);
  await settled(page);
});

test('slider changes the image; the server confirms the value', async () => {
  const page = ctx.page;
  const f0 = await page.evaluate(() => window.lucent.state.lastFrame.frame);
  const sig0 = await signature(page);
  const slider = page.locator('#ctl-params-q');
  await slider.focus();
  await slider.press('End'); // keyboard on the range input: q -> its maximum, 1000
  const shown = await page.locator('#ctl-params-q + .num, .row[data-path="params.q"] .num').first().inputValue();
  check(shown === '1000', `number box shows ${shown}`);
  await page.waitForFunction(() => Number(document.body.dataset.paramsSent ?? 0) >= 1, null, { timeout: 5000 });
  await settled(page, 60000, f0);
  const d = meanDiff(sig0, await signature(page));
  check(d > 0.5, `image did not change with q (mean diff ${d.toFixed(2)})`);
  const err = await page.evaluate(() => window.lucent.state.error);
  check(!err, `server error: ${JSON.stringify(err)}`);
  await shot(page, '03-slider-q-1000');
  // the server's own state: a new session from the page's state reports q = 1000 in ready.defaults,
  // and the view comes back the same (what a reconnect after a lost connection does)
  const sigBefore = await signature(page);
  const session0 = await page.evaluate(() => window.lucent.state.session);
  await page.evaluate(() => window.lucent.reconnect());
  await page.waitForFunction((s) => window.lucent.state.session && window.lucent.state.session !== s, session0, { timeout: 30000 });
  await settled(page);
  const ready = await page.evaluate(() => window.lucent.state.lastReady);
  check(ready.defaults.params.q === 1000, `server reports q = ${ready.defaults.params.q}`);
  const back = meanDiff(sigBefore, await signature(page));
  check(back < 3, `view not restored after reconnecting (mean diff ${back.toFixed(2)})`);
});

test('reloading the copied URL restores dataset, camera and parameters', async () => {
  const page = ctx.page;
  await context.grantPermissions(['clipboard-read', 'clipboard-write'], { origin: ctx.d.url });
  await page.locator('#copy-link').click();
  await page.waitForTimeout(300);
  const link = await page.evaluate(() => navigator.clipboard.readText());
  check(link.startsWith(ctx.d.url) && /dataset=demo:tornado/.test(link) && /q=1000/.test(link) && /position=/.test(link), `copied link: ${link}`);
  const before = await page.evaluate(() => window.lucent.camera);
  const sig0 = await signature(page);
  const page2 = await newPage(link);
  await settled(page2);
  const st = await page2.evaluate(() => ({
    cam: window.lucent.camera, ds: document.getElementById('dataset').value, q: document.getElementById('ctl-params-q').value,
    serverQ: window.lucent.state.lastReady.defaults.params.q, serverCam: window.lucent.state.lastReady.defaults.camera,
  }));
  check(st.ds === 'demo:tornado', `dataset ${st.ds}`);
  check(st.q === '1000' && st.serverQ === 1000, `q page ${st.q}, server ${st.serverQ}`);
  check(camDiff(st.cam, before) < 1e-5 && camDiff(st.serverCam, before) < 1e-5, `camera not restored: ${JSON.stringify(st.cam)} vs ${JSON.stringify(before)}`);
  const d = meanDiff(sig0, await signature(page2));
  check(d < 3, `reloaded image differs (mean diff ${d.toFixed(2)})`);
  await shot(page2, '04-reloaded-link');
  await page2.close();
});

test('screenshot button downloads a PNG of the chosen size', async () => {
  const page = ctx.page;
  await page.locator('#shot-size').selectOption('custom');
  await page.locator('#shot-width').fill('400');
  await page.locator('#shot-height').fill('300');
  const [download] = await Promise.all([page.waitForEvent('download', { timeout: 60000 }), page.locator('#screenshot').click()]);
  const file = path.join(artifacts, '05-download.png');
  await download.saveAs(file);
  const b = fs.readFileSync(file);
  check(b.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a])), 'not a PNG signature');
  check(b.readUInt32BE(16) === 400 && b.readUInt32BE(20) === 300, `PNG is ${b.readUInt32BE(16)}x${b.readUInt32BE(20)}`);
  check(b.length > 2000, `PNG of ${b.length} bytes`);
  check(/\.png$/.test(download.suggestedFilename()), `file name ${download.suggestedFilename()}`);
});

test('unknown dataset shows a readable message', async () => {
  const page = await newPage(`${ctx.d.url}/#dataset=demo:nope`);
  await page.waitForFunction(() => !document.getElementById('banner').hidden && window.lucent.state.error, null, { timeout: 30000 });
  await page.waitForTimeout(500); // the server's answer to hello, too
  const text = await page.locator('#banner-text').textContent();
  check(/demo:nope/.test(text) && /not available/.test(text) && /demo:tornado/.test(text), `banner: ${text}`);
  const code = await page.evaluate(() => window.lucent.state.error.code ?? null);
  await shot(page, '06-unknown-dataset');
  // choosing a real dataset recovers
  await page.locator('#dataset').selectOption('demo:points');
  await settled(page);
  check(await page.locator('#banner').isHidden(), 'banner still shown after picking a dataset');
  log(`  unknown dataset error code: ${code}`);
  await page.close();
});

test('access token: prompt on 401, and ?token= in the URL', async () => {
  const d = await startDaemon(['--token', 's3cret-token']);
  try {
    const page = await newPage(`${d.url}/#dataset=demo:points`);
    await page.locator('#token-dialog').waitFor({ state: 'visible', timeout: 20000 });
    await shot(page, '07-token-prompt');
    await page.locator('#token-input').fill('s3cret-token');
    await page.locator('#token-form button[value="ok"]').click();
    await settled(page);
    await page.close();
    const page2 = await newPage(`${d.url}/?token=s3cret-token#dataset=demo:points`);
    await settled(page2);
    check(await page2.locator('#token-dialog').isHidden(), 'token dialog shown despite ?token=');
    await page2.close();
  } finally {
    await stopDaemon(d);
  }
});

test('docs screenshot', async () => {
  if (!docsShot) return 'skipped (no --docs-screenshot)';
  const page = await context.newPage();
  await page.setViewportSize({ width: 1000, height: 600 });
  await page.goto(`${ctx.d.url}/#dataset=demo:tornado&position=0.5,-2.3,0.75&focalPoint=0.5,0.5,0.45&viewUp=0,0,1&viewAngle=30&quality=100`);
  await settled(page, 90000);
  await page.waitForTimeout(400); // the overlay refreshes 4 times a second
  await page.screenshot({ path: docsShot });
  const size = fs.statSync(docsShot).size;
  await page.close();
  return `${docsShot}: ${(size / 1024).toFixed(0)} KiB`;
});

test('stopped server: visible state, then reconnection restores the view', async () => {
  const page = ctx.page;
  const cam = await page.evaluate(() => window.lucent.camera);
  const sig0 = await signature(page);
  const port = ctx.d.port;
  await stopDaemon(ctx.d);
  await page.waitForFunction(() => document.body.dataset.connection === 'waiting' && !document.getElementById('banner').hidden, null, { timeout: 20000 });
  const text = await page.locator('#banner-text').textContent();
  const label = await page.locator('#connection').textContent();
  check(/lost/.test(text) && /Reconnecting in \d+ s/.test(text), `banner: ${text}`);
  check(/retrying/.test(label), `status: ${label}`);
  await shot(page, '08-server-stopped');
  ctx.d = await startDaemon([], port);
  await page.waitForFunction(() => document.body.dataset.connection === 'open', null, { timeout: 45000 });
  await settled(page);
  const st = await page.evaluate(() => ({ cam: window.lucent.camera, server: window.lucent.state.lastReady.defaults }));
  check(camDiff(st.cam, cam) < 1e-9 && camDiff(st.server.camera, cam) < 1e-5 && st.server.params.q === 1000, 'view not restored after reconnecting');
  check(await page.locator('#banner').isHidden(), 'banner still shown after reconnecting');
  const d = meanDiff(sig0, await signature(page));
  check(d < 3, `image after reconnect differs (mean diff ${d.toFixed(2)})`);
  await shot(page, '09-reconnected');
});

// ------------------------------------------------------------------ runner
let passed = 0, failed = 0, skipped = 0;
try {
  ctx.d = await startDaemon();
  log(`daemon at ${ctx.d.url}`);
  for (const t of tests) {
    if (only && !t.name.includes(only) && t.name !== 'first frame') {
      skipped++;
      continue;
    }
    const t1 = Date.now();
    try {
      const note = await t.fn();
      passed++;
      log(`ok - ${t.name} (${Date.now() - t1} ms)${note ? ` # ${note}` : ''}`);
    } catch (e) {
      failed++;
      log(`not ok - ${t.name} (${Date.now() - t1} ms)\n    ${String(e.stack ?? e).split('\n').slice(0, 6).join('\n    ')}`);
      if (ctx.page) await shot(ctx.page, `fail-${t.name.replace(/\W+/g, '-')}`).catch(() => {});
    }
  }
  if (pageErrors.length) {
    failed++;
    log(`not ok - page errors:\n    ${pageErrors.join('\n    ')}`);
  }
} catch (e) {
  failed++;
  log(`not ok - setup: ${e.message}`);
} finally {
  await context.close().catch(() => {});
  await stopDaemon(ctx.d);
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed${skipped ? `, ${skipped} skipped` : ''}`);
process.exit(failed ? 1 : 0);
