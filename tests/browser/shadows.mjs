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

import { check, finish, launch, pageHelpers, setup, startDaemon } from './harness.mjs';

const { chromium, binary } = await setup();

const { url } = await startDaemon(binary, [
  '--data',
  'demo:tornado',
  '--demo-size',
  '150',
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
  const { settled, newest, sig, diff, rowHidden, setNumber } = pageHelpers(page);

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
finish();
