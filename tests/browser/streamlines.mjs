// Streamline sets seeded from the page (docs/ALGORITHM.md §22) in headless Chromium against the real
// daemon: the dataset picker offers the vector field; choosing it (a link with dataset=demo:shear-flow)
// shows the Streamlines group and the server's traced lines (the picture is not the empty background);
// choosing a rake fills in its two ends, draws them as the view's seed handles and sends the whole
// streamlines object (the link carries it, the picture changes, no error); five curves instead of the
// rake's 64 change it again; the importance menu offers the set's vorticity and line measures and the vorticity
// renders; two-way curves change the picture; dragging a handle moves the rake's end; a loaded dataset hides the group
// and streams without an error (the section stays out of its requests).
//
//   node tests/browser/streamlines.mjs --binary build/lucent
//
// Exit codes: 0 passed, 1 a failure, 77 skipped (chromium or node_modules missing, outside CI).

import { check, finish, launch, pageHelpers, setup, startDaemon } from './harness.mjs';

const { chromium, binary } = await setup();

const { url } = await startDaemon(binary, [
  '--data',
  'demo:points',
  '--data',
  'demo:shear-flow',
  '--demo-size',
  '300',
  '--workers',
  '1',
  '--cache',
  'off',
]);

const browser = await launch(chromium);
const pageErrors = [];
try {
  const context = await browser.newContext({ viewport: { width: 900, height: 700 } });
  const page = await context.newPage();
  page.on('pageerror', (e) => pageErrors.push(e.message));
  const { settled, newest, sig, diff, setNumber } = pageHelpers(page);

  await page.goto(`${url}/#dataset=demo:shear-flow`);
  await page.waitForFunction(() => Number(document.body.dataset.frames ?? 0) >= 1, null, { timeout: 60000 });
  await settled();
  const offered = await page.evaluate(() => [...document.getElementById('dataset').options].map((o) => o.value));
  check(
    offered.includes('demo:shear-flow') && offered.includes('demo:points'),
    `the picker offers the field beside the datasets (${offered})`,
  );
  const group = () => page.evaluate(() => document.getElementById('group-streamlines')?.hidden ?? null);
  check((await group()) === false, 'a field shows the Streamlines group');
  const bg = await sig();
  // the lines drawn: pixels away from the corner's background colour
  const inked = (s) => {
    let n = 0;
    for (let i = 0; i < s.length; i += 4)
      if (Math.abs(s[i] - s[0]) + Math.abs(s[i + 1] - s[1]) + Math.abs(s[i + 2] - s[2]) > 30) n++;
    return n / (s.length / 4);
  };
  const info = await page.evaluate(() => ({ err: window.lucent.state.error, info: window.lucent.state.info }));
  check(
    !info.err && info.info?.type === 'lines' && info.info?.lines > 0 && inked(bg) > 0.01,
    `the server traces the default set and the view shows its lines (${info.info?.lines} lines, ${(100 * inked(bg)).toFixed(1)}% of pixels inked)`,
  );

  let f0 = await newest();
  await page.selectOption('#streamlines-seeding', 'rake');
  await page.waitForFunction(() => /streamlinesSeeding=rake/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const rake = await sig();
  const seeds = await page.$eval('#streamlines-seeds', (e) => e.value);
  check(seeds.split(';').length === 2, `a rake fills in its two ends (${seeds})`);
  check(!(await page.evaluate(() => window.lucent.state.error)), 'the server takes the rake');
  check(
    diff(bg, rake) > 0.3 && inked(rake) > 0.005,
    `the rake's curves change the picture (${diff(bg, rake).toFixed(2)}, ${(100 * inked(rake)).toFixed(1)}% inked)`,
  );
  const handles = await page.evaluate(() => !document.getElementById('seed-overlay')?.hasAttribute('hidden'));
  check(handles, 'the rake is drawn with the seed handles');

  f0 = await newest();
  await setNumber('#streamlines-count', 5);
  await page.waitForFunction(() => /streamlinesCount=5/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const five = await sig();
  check(
    !(await page.evaluate(() => window.lucent.state.error)) && diff(rake, five) > 0.1,
    `five curves change the picture again (${diff(rake, five).toFixed(2)})`,
  );

  // Issue 44's techniques on a field's set: vorticity and a line measure as importance, two-way tracing.
  const offeredAttrs = await page.evaluate(() =>
    [...document.getElementById('ctl-importance-attribute').options].map((o) => o.value),
  );
  check(
    offeredAttrs.includes('vorticity') && offeredAttrs.includes('angular_entropy') && offeredAttrs.includes('speed'),
    `the importance menu offers the traced set's vorticity, speed and line measures (${offeredAttrs.join(', ')})`,
  );
  f0 = await newest();
  await page.selectOption('#ctl-importance-attribute', 'vorticity');
  await page.waitForFunction(() => /importance=vorticity/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  check(
    !(await page.evaluate(() => window.lucent.state.error)),
    "importance from the vorticity renders (the shear flow's is uniform)",
  );
  f0 = await newest();
  await page.selectOption('#ctl-importance-attribute', 'speed');
  await page.waitForFunction(() => /importance=speed/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const bySpeed = await sig();
  // the rake runs across the middle and the shear flow along +x: only two-way curves reach the left part
  const leftInk = () =>
    page.evaluate(() => {
      const src = document.getElementById('canvas');
      const c = document.createElement('canvas');
      c.width = src.width;
      c.height = src.height;
      const g = c.getContext('2d');
      g.drawImage(src, 0, 0); // full resolution: the lines are a pixel wide
      const d = g.getImageData(0, 0, Math.floor(0.4 * c.width), c.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4)
        if (Math.abs(d[i] - d[0]) + Math.abs(d[i + 1] - d[1]) + Math.abs(d[i + 2] - d[2]) > 30) n++;
      return n;
    });
  const leftForward = await leftInk();
  f0 = await newest();
  await page.selectOption('#streamlines-direction', 'both');
  await page.waitForFunction(() => /streamlinesDirection=both/.test(location.hash), null, { timeout: 30000 });
  await settled(f0);
  const both = await sig();
  const leftBoth = await leftInk();
  check(
    !(await page.evaluate(() => window.lucent.state.error)) && leftForward === 0 && leftBoth > 50,
    `two-way curves from the rake reach the part upstream of it (${leftForward} inked pixels there forward, ${leftBoth} both ways)`,
  );

  const box = await page.locator('[data-testid="seed-end"]').boundingBox();
  if (box) {
    f0 = await newest();
    const x = box.x + box.width / 2,
      y = box.y + box.height / 2;
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.mouse.move(x + 40, y + 10, { steps: 4 });
    await page.mouse.up();
    await page.waitForFunction((s) => document.getElementById('streamlines-seeds').value !== s, seeds, {
      timeout: 30000,
    });
    await settled(f0);
    check(
      !(await page.evaluate(() => window.lucent.state.error)),
      `dragging a handle moves the rake's end (${await page.$eval('#streamlines-seeds', (e) => e.value)})`,
    );
  } else check(false, 'the rake end handle has a box');

  f0 = await newest();
  await page.selectOption('#dataset', 'demo:points');
  await page.waitForFunction(
    () => window.lucent.state.info?.type === 'points' && Number(window.lucent.state.lastFrame?.frame ?? -1) >= 0,
    null,
    { timeout: 60000 },
  );
  await settled();
  const after = await page.evaluate(() => ({ err: window.lucent.state.error, hash: location.hash }));
  check(
    (await group()) === true && !after.err && !/streamlines/.test(after.hash),
    `a loaded dataset hides the group and streams without the section (${JSON.stringify(after)})`,
  );
  check(pageErrors.length === 0, `no page errors (${pageErrors.join('; ')})`);
} catch (e) {
  check(false, `exception: ${e.stack ?? e}`);
} finally {
  await browser.close();
}
finish();
