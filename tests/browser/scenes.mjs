// The page's time bar and layer list (issue 27) in headless Chromium against the real daemon.
// Time: a LAMMPS dump (per-vertex timestep) shows the bar, the demo points do not; moving t sends
// time.window, the link carries it (timeWindow=t0,t1) and the image changes; a window length narrows
// the window; play steps t (the window's end grows, frames keep coming, no error) and pause stops it;
// a link with timeWindow reopens the bar at that t.
// Layers: adding the dump to the points makes a two-layer session (the points stay layer 1) whose
// frames differ from the points alone, with a legend line per layer; the rows' controls keep a readable width
// (>= 60 px, no row wider than the panel) at 1280x800 and on a phone (390x844); hiding the dump brings the
// points' picture back; a layer's colour attribute and role go to the server (the legend follows); a time
// window, a filter and a cluster count typed into the dump's row go as layers[1].time / .filter / .lines
// (the window changes the picture) and into the link; the link reopens both layers in a new session; removing them returns to the single dataset.
//
//   node tests/browser/scenes.mjs --binary build/lucent
//
// Exit codes: 0 passed, 1 a failure, 77 skipped (chromium or node_modules missing, outside CI).

import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { check, finish, launch, pageHelpers, setup, startDaemon } from './harness.mjs';

const { chromium, binary } = await setup();

// 30 atoms crossing the box along x over 20 frames, TIMESTEP = 10 x frame: timestep spans [0, 190], and a
// window [t0, t1] draws a band of x.
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'lucent-time-'));
const dumpPath = path.join(tmp, 'spiral.dump');
let text = '';
for (let fr = 0; fr < 20; fr++) {
  text += `ITEM: TIMESTEP\n${fr * 10}\nITEM: NUMBER OF ATOMS\n30\nITEM: BOX BOUNDS ff ff ff\n-20 20\n-20 20\n-20 20\nITEM: ATOMS id type xu yu zu\n`;
  for (let a = 0; a < 30; a++) {
    text += `${a + 1} 1 ${(-18 + 1.8 * fr + 0.3 * Math.sin(a)).toFixed(4)} ${(-14.5 + a).toFixed(4)} ${(0.1 * a).toFixed(4)}\n`;
  }
}
fs.writeFileSync(dumpPath, text);

const { url } = await startDaemon(binary, [
  '--data',
  dumpPath,
  '--data',
  'demo:points',
  '--demo-size',
  '80',
  '--workers',
  '1',
  '--cache',
  'off',
]);
process.on('exit', () => {
  fs.rmSync(tmp, { recursive: true, force: true });
});

const browser = await launch(chromium);
const pageErrors = [];
try {
  const list = await (await fetch(`${url}/api/v1/datasets`)).json();
  const name = (list.datasets ?? list).map((d) => d.name).find((n) => n !== 'demo:points');
  check(!!name, `the dump is served (${name})`);
  const context = await browser.newContext({ viewport: { width: 640, height: 480 } });
  const page = await context.newPage();
  page.on('pageerror', (e) => pageErrors.push(e.message));
  const frames = () => page.evaluate(() => Number(document.body.dataset.frames ?? 0));
  const { settled, newest, sig, diff } = pageHelpers(page);

  await page.goto(`${url}/#dataset=demo:points`);
  await page.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  check(
    await page.evaluate(() => document.getElementById('time').hidden),
    'no time bar on the points demo (no time attribute)',
  );

  await page.goto(`${url}/#dataset=${encodeURIComponent(name)}`);
  await page.waitForFunction(
    () => !document.getElementById('time').hidden && Number(document.body.dataset.frames ?? 0) >= 1,
    null,
    { timeout: 60000 },
  );
  await settled();
  const st = await page.evaluate(() => ({
    min: document.getElementById('time-t').min,
    max: document.getElementById('time-t').max,
    label: document.getElementById('time-label').textContent,
  }));
  check(st.min === '0' && st.max === '190', `the bar spans the dump's timesteps [${st.min}, ${st.max}] (${st.label})`);
  const whole = await sig();

  // t = 60, everything up to it
  let f0 = await newest();
  await page.evaluate(() => {
    const s = document.getElementById('time-t');
    s.value = '60';
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction(() => /timeWindow=0,60/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const upTo60 = await sig();
  const err1 = await page.evaluate(() => window.lucent.state.error);
  check(!err1, `the server took time.window [0, 60] (${JSON.stringify(err1)})`);
  check(
    diff(whole, upTo60) > 0.5,
    `the window up to t = 60 changes the image (mean difference ${diff(whole, upTo60).toFixed(2)})`,
  );
  check(
    /≤ 60/.test(await page.evaluate(() => document.getElementById('time-label').textContent)),
    'the label says timestep ≤ 60',
  );

  // a window of length 30: [30, 60]
  f0 = await newest();
  await page.fill('#time-length', '30');
  await page.dispatchEvent('#time-length', 'change');
  await page
    .waitForFunction(() => /timeWindow=30,60/.test(location.hash), null, { timeout: 30000 })
    .catch(async (e) => {
      throw new Error(
        `${e.message}: ${await page.evaluate(() => location.hash + ' ' + document.getElementById('time-length').value)}`,
      );
    });
  await settled(f0);
  const win = await sig();
  // the stream has ended (a final, converged still): nothing more may change the picture, however long one looks
  await page.waitForTimeout(500);
  const again = await sig();
  check(
    diff(win, again) < 0.05,
    `the settled image holds still (${diff(win, again).toFixed(3)}): the differences measure the windows`,
  );
  check(
    diff(upTo60, win) > 0.2,
    `a window of length 30 draws less than everything up to 60 (${diff(upTo60, win).toFixed(2)})`,
  );

  // markers: a dot at each line's position at t, over the picture; the link carries them
  f0 = await newest();
  await page.check('#time-markers');
  await page.waitForFunction(() => /timeMarkers=true/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const marked = await sig();
  check(diff(win, marked) > 0.05, `markers change the picture (${diff(win, marked).toFixed(3)})`);
  check(!(await page.evaluate(() => window.lucent.state.error)), 'the server draws the markers');
  f0 = await newest();
  await page.uncheck('#time-markers');
  await page.waitForFunction(() => !/timeMarkers=true/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);

  // play: t steps on, frames keep coming, the link follows; pause stops it
  const n0 = await frames();
  await page.click('#time-play');
  // Waited for, not timed (a loaded CI host renders slower): five more frames while t is past 60 and the link
  // follows, all read in one go (play starts over at the range's end, so t is sampled with the frame count).
  const during = await page
    .waitForFunction(
      (n) => {
        const t = Number(document.getElementById('time-t').value),
          m = /timeWindow=([\d.]+),([\d.]+)/.exec(location.hash);
        const st = {
          pressed: document.getElementById('time-play').getAttribute('aria-pressed'),
          t,
          hash: location.hash,
          err: window.lucent.state.error,
          frames: Number(document.body.dataset.frames ?? 0),
        };
        return st.frames >= n && t > 60 && m && Number(m[2]) > 60 ? st : null;
      },
      n0 + 5,
      { timeout: 120000, polling: 50 },
    )
    .then(
      (h) => h.jsonValue(),
      async () =>
        page.evaluate(() => ({
          pressed: document.getElementById('time-play').getAttribute('aria-pressed'),
          t: Number(document.getElementById('time-t').value),
          hash: location.hash,
          err: window.lucent.state.error,
          frames: Number(document.body.dataset.frames ?? 0),
        })),
    );
  check(during.pressed === 'true' && during.t > 60, `play steps t on (t = ${during.t})`);
  check(during.frames - n0 >= 5, `frames keep coming while playing (${during.frames - n0})`);
  check(!during.err, `no error while playing (${JSON.stringify(during.err)})`);
  const m = /timeWindow=([\d.]+),([\d.]+)/.exec(during.hash);
  check(m && Number(m[2]) - Number(m[1]) <= 30 + 1e-9 && Number(m[2]) > 60, `the link follows play (${m && m[0]})`);
  await page.click('#time-play');
  const tStop = await page.evaluate(() => Number(document.getElementById('time-t').value));
  // paused: a correct page steps no more, however long one looks (a step is 200 ms: 700 ms would see several)
  await page.waitForTimeout(700);
  const tLater = await page.evaluate(() => Number(document.getElementById('time-t').value));
  check(tStop === tLater, `pause stops t (${tStop} then ${tLater})`);

  // a link with a window reopens the bar there
  const page2 = await context.newPage();
  page2.on('pageerror', (e) => pageErrors.push(e.message));
  await page2.goto(`${url}/#dataset=${encodeURIComponent(name)}&timeWindow=100,150`);
  await page2.waitForFunction(
    () => !document.getElementById('time').hidden && Number(document.body.dataset.frames ?? 0) >= 1,
    null,
    { timeout: 60000 },
  );
  const st2 = await page2.evaluate(() => ({
    t: document.getElementById('time-t').value,
    len: document.getElementById('time-length').value,
    defaults: window.lucent.state.lastReady?.defaults?.time,
  }));
  check(
    st2.t === '150' && st2.len === '50',
    `a link with timeWindow=100,150 opens at t = 150, length 50 (${st2.t}, ${st2.len})`,
  );
  check(
    JSON.stringify(st2.defaults?.window) === '[100,150]',
    `the session has the link's window (${JSON.stringify(st2.defaults)})`,
  );

  // ---- layers
  const page3 = await context.newPage();
  page3.on('pageerror', (e) => pageErrors.push(e.message));
  const sig3 = () =>
    page3.evaluate(() => {
      const c = document.createElement('canvas');
      c.width = 48;
      c.height = 32;
      const g = c.getContext('2d');
      g.drawImage(document.getElementById('canvas'), 0, 0, 48, 32);
      return Array.from(g.getImageData(0, 0, 48, 32).data);
    });
  const settled3 = async (min) => {
    await page3.waitForFunction(
      (m) => {
        const f = window.lucent?.state?.lastFrame;
        return !!f && f.frame > m && f.converged && !f.detail?.interactive && f.final !== false;
      },
      min,
      { timeout: 60000, polling: 100 },
    );
  };
  const lastFrame = () => page3.evaluate(() => window.lucent.state.lastFrame?.frame ?? 0);
  await page3.goto(`${url}/#dataset=demo:points&position=0,0,60&focalPoint=0,0,0&viewUp=0,1,0`);
  await page3.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  await settled3(0);
  const pointsAlone = await sig3();
  check(
    await page3.evaluate(
      () => document.querySelectorAll('.layer-row').length === 0 && document.querySelector('.legend-layers').hidden,
    ),
    'no layers at first',
  );
  let f = await lastFrame();
  await page3.selectOption('#layer-add', name);
  await page3
    .waitForFunction(() => /layers=/.test(location.hash), null, { timeout: 30000 })
    .catch(async (e) => {
      throw new Error(
        `${e.message}: ${await page3.evaluate(() => JSON.stringify({ hash: location.hash, update: window.lucent.state.update, toast: document.getElementById('toast').textContent, err: window.lucent.state.error }))}`,
      );
    });
  await settled3(f);
  const two = await page3.evaluate(() => ({
    rows: [...document.querySelectorAll('.layer-row .layer-name')].map((e) => e.textContent.trim()),
    legend: [...document.querySelectorAll('.legend-layer')].map((e) => e.dataset.dataset),
    layered: document.getElementById('legend').classList.contains('layered'),
    err: window.lucent.state.error,
  }));
  check(
    JSON.stringify(two.rows) === JSON.stringify(['demo:points', name]),
    `adding ${name}: the points stay layer 1 (${two.rows})`,
  );
  check(
    JSON.stringify(two.legend) === JSON.stringify(['demo:points', name]) && two.layered,
    `a legend line per layer (${two.legend})`,
  );
  check(!two.err, `the session draws the two layers (${JSON.stringify(two.err)})`);
  const both = await sig3();
  check(
    diff(pointsAlone, both) > 0.3,
    `the two-layer frame differs from the points alone (${diff(pointsAlone, both).toFixed(2)})`,
  );
  // The layer rows fit a desktop (1280x800) and a phone (390x844): every select and box wide enough to read, no row
  // wider than the panel.
  for (const [w, h] of [
    [1280, 800],
    [390, 844],
  ]) {
    await page3.setViewportSize({ width: w, height: h });
    const fit = await page3.evaluate(() => {
      const rows = [...document.querySelectorAll('.layer-row')];
      const widths = rows.flatMap((r) =>
        [...r.querySelectorAll('select, input[type=number]')].map((e) => Math.round(e.getBoundingClientRect().width)),
      );
      const over = rows.filter((r) => r.scrollWidth > r.clientWidth + 1).length;
      return { narrowest: Math.min(...widths), over, count: widths.length };
    });
    console.log(
      `layer rows at ${w}x${h}: ${fit.count} controls, the narrowest ${fit.narrowest} px, ${fit.over} rows overflow`,
    );
    check(
      fit.count > 0 && fit.narrowest >= 60 && fit.over === 0,
      `layer rows at ${w}x${h}: narrowest control ${fit.narrowest} px, ${fit.over} rows overflow`,
    );
  }
  await page3.setViewportSize({ width: 640, height: 480 });

  f = await lastFrame();
  await page3.click('.layer-row[data-index="1"] input[type=checkbox]');
  await settled3(f);
  const hidden = await sig3();
  check(
    diff(pointsAlone, hidden) < 0.25 * diff(pointsAlone, both),
    `hiding the dump brings the points' picture back (${diff(pointsAlone, hidden).toFixed(2)} against ${diff(pointsAlone, both).toFixed(2)})`,
  );
  check(
    await page3.evaluate(() => document.querySelectorAll('.legend-layer').length === 1),
    'the legend lists the visible layer only',
  );
  await page3.click('.layer-row[data-index="1"] input[type=checkbox]');

  f = await lastFrame();
  await page3.selectOption('.layer-row[data-index="1"] select[aria-label^="Colour attribute"]', 'timestep');
  await page3.selectOption('.layer-row[data-index="1"] select[aria-label^="Role"]', 'context');
  // the link (written 200 ms after a change) carries both changes, and a still newer than both is there
  await page3
    .waitForFunction(
      () =>
        /"role":"context"/.test(decodeURIComponent(location.hash)) &&
        /"attribute":"timestep"/.test(decodeURIComponent(location.hash)),
      null,
      { timeout: 30000 },
    )
    .catch(() => {});
  await settled3(f);
  const mapped = await page3.evaluate(() => ({
    legend: document.querySelector(`.legend-layer[data-dataset]:last-child`)?.textContent,
    err: window.lucent.state.error,
    hash: decodeURIComponent(location.hash),
  }));
  check(!mapped.err, `colour by timestep and opaque context: no error (${JSON.stringify(mapped.err)})`);
  check(
    /\(context\): timestep/.test(mapped.legend) && /190/.test(mapped.legend),
    `the legend line says context, timestep and its range (${mapped.legend})`,
  );
  check(
    /"role":"context"/.test(mapped.hash) && /"attribute":"timestep"/.test(mapped.hash),
    'the link carries the role and the colour attribute',
  );

  // The dump's own time window and filter, typed into its row: each goes to the server as layers[1].time /
  // layers[1].filter, changes the picture, and the link carries it.
  const row1 = '.layer-row[data-index="1"]';
  const typed = async (label, value) => {
    await page3.fill(`${row1} input[aria-label^="${label}"]`, value);
    await page3.dispatchEvent(`${row1} input[aria-label^="${label}"]`, 'change');
  };
  const beforeWindow = await sig3();
  f = await lastFrame();
  await typed('Time window start', '0');
  await typed('Time window end', '40');
  await page3
    .waitForFunction(() => /"time":\{"window":\[0,40\]\}/.test(decodeURIComponent(location.hash)), null, {
      timeout: 30000,
    })
    .catch(() => {});
  await settled3(f).catch(async (e) => {
    throw new Error(
      `${e.message}: ${await page3.evaluate(() => JSON.stringify({ hash: decodeURIComponent(location.hash), err: window.lucent.state.error, last: window.lucent.state.lastFrame, toast: document.getElementById('toast').textContent }))}`,
    );
  });
  const windowed = await page3.evaluate(() => ({
    err: window.lucent.state.error,
    hash: decodeURIComponent(location.hash),
  }));
  const afterWindow = await sig3();
  check(
    !windowed.err && /"window":\[0,40\]/.test(windowed.hash),
    `a time window on the dump layer: no error, in the link (${JSON.stringify(windowed.err)})`,
  );
  check(
    diff(beforeWindow, afterWindow) > 0.05,
    `the window changes the picture (${diff(beforeWindow, afterWindow).toFixed(3)})`,
  );
  f = await lastFrame();
  await page3.selectOption(`${row1} select[aria-label^="Filter attribute"]`, 'timestep');
  await page3.selectOption(`${row1} select[aria-label^="Filter statistic"]`, 'min');
  await typed('Filter value', '5');
  await page3
    .waitForFunction(() => /"filter":\[\{"attribute":"timestep"/.test(decodeURIComponent(location.hash)), null, {
      timeout: 30000,
    })
    .catch(() => {});
  await settled3(f);
  const filteredLayer = await page3.evaluate(() => ({
    err: window.lucent.state.error,
    hash: decodeURIComponent(location.hash),
  }));
  check(
    !filteredLayer.err && /"over":"min","gt":5/.test(filteredLayer.hash),
    `a filter on the dump layer: no error, in the link (${JSON.stringify(filteredLayer.err)}; ${filteredLayer.hash.slice(0, 300)})`,
  );
  f = await lastFrame();
  await typed('Clusters', '3');
  await page3
    .waitForFunction(() => /"lines":\{"clusters":3\}/.test(decodeURIComponent(location.hash)), null, { timeout: 30000 })
    .catch(() => {});
  await settled3(f);
  const clusteredLayer = await page3.evaluate(() => ({
    err: window.lucent.state.error,
    hash: decodeURIComponent(location.hash),
  }));
  check(
    !clusteredLayer.err && /"lines":\{"clusters":3\}/.test(clusteredLayer.hash),
    `clusters on the dump layer: no error, in the link (${JSON.stringify(clusteredLayer.err)})`,
  );
  // the points' own equalized colours (the dump is context: its row has no such box)
  check(
    (await page3.locator(`${row1} input[aria-label^="Equalize"]`).count()) === 0,
    'a context layer offers no equalization',
  );
  f = await lastFrame();
  await page3.click('.layer-row[data-index="0"] input[aria-label^="Equalize"]');
  await page3
    .waitForFunction(() => /"equalize":true/.test(decodeURIComponent(location.hash)), null, { timeout: 30000 })
    .catch(() => {});
  await settled3(f);
  const eqLayer = await page3.evaluate(() => ({
    err: window.lucent.state.error,
    hash: decodeURIComponent(location.hash),
  }));
  check(
    !eqLayer.err && /"equalize":true/.test(eqLayer.hash),
    `the points layer's equalized colours: no error, in the link (${JSON.stringify(eqLayer.err)})`,
  );

  // The screenshot's and the movie's request (renderRequest, the Record group's too) carries the layers shown.
  await page3.locator('#shot-size').selectOption('custom');
  await page3.locator('#shot-width').fill('64');
  await page3.locator('#shot-height').fill('48');
  const [shotRequest] = await Promise.all([
    page3.waitForRequest('**/api/v1/render', { timeout: 30000 }),
    page3.locator('#screenshot').click(),
  ]);
  await page3.waitForFunction(() => !document.getElementById('screenshot').disabled, null, { timeout: 30000 });
  const shotBody = shotRequest.postData() ?? '{}';
  const shot = JSON.parse(shotBody);
  const shotAnswer = await shotRequest.response();
  check(
    shot.layers?.length === 2 && shot.layers[1].role === 'context' && shotAnswer?.status() === 200,
    `the screenshot's (and the movie's) request draws both layers (${shotAnswer?.status()}: ${shotBody.slice(0, 200)})`,
  );

  const page4 = await context.newPage();
  page4.on('pageerror', (e) => pageErrors.push(e.message));
  await page4.goto(await page3.evaluate(() => location.href));
  await page4.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  const reopened = await page4.evaluate(() => ({
    rows: document.querySelectorAll('.layer-row').length,
    server: window.lucent.state.lastReady?.defaults?.layers,
  }));
  check(
    reopened.rows === 2 && reopened.server?.length === 2 && reopened.server[1].role === 'context',
    `the link reopens both layers in a new session (${JSON.stringify(reopened.server?.map((l) => [l.dataset, l.role]))})`,
  );
  await page4.close();

  f = await lastFrame();
  await page3.click('.layer-row[data-index="1"] .layer-remove');
  await page3.click('.layer-row[data-index="0"] .layer-remove');
  await settled3(f);
  const none = await page3.evaluate(() => ({
    rows: document.querySelectorAll('.layer-row').length,
    layered: document.getElementById('legend').classList.contains('layered'),
    err: window.lucent.state.error,
  }));
  const back = await sig3();
  check(none.rows === 0 && !none.layered && !none.err, 'removing both layers returns to the single dataset');
  check(
    diff(pointsAlone, back) < 0.25 * diff(pointsAlone, both),
    `and its picture (${diff(pointsAlone, back).toFixed(2)})`,
  );
  check(pageErrors.length === 0, `no page errors (${pageErrors.join('; ')})`);
} catch (e) {
  check(false, `exception: ${e.stack ?? e}`);
} finally {
  await browser.close();
}
finish();
