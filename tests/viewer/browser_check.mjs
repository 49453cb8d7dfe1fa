// Drives the live viewer in headless Chromium (Debian's `chromium`, through
// playwright-core) for tests/viewer.rs, and prints what it saw as one JSON object.
//
//   node tests/viewer/browser_check.mjs URL SCRIPT OUT_DIR
//
// URL is a running `dieface view SCRIPT`. The steps, each recorded in the output:
//   1. load the page; wait for the model to be drawn; screenshot `OUT_DIR/model.png`,
//      and the kinds' legend colours;
//   2. click a binder piece where the page says it is drawn; read the pick panel;
//   3. draft-angle mode: screenshot `OUT_DIR/draft.png`; seam mode: the seam figures;
//   4. save the script with the wheel-arch bead moved 5 mm: time until the new model
//      is drawn, and whether the camera stayed;
//   5. save a broken script: the diagnostic shown, and the model still there;
//   6. every console error and page error along the way;
//   7. in a browser without WebGL, what the page says instead of drawing.
// The script is restored at the end. Rust checks the figures and the pixels.

import { chromium } from 'playwright-core';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

const [url, script, outDir] = process.argv.slice(2);
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
const original = readFileSync(script, 'utf8');
const result = { consoleErrors: [] };

const browser = await chromium.launch({
  executablePath,
  args: [
    '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync',
  ],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  page.on('console', (m) => { if (m.type() === 'error') result.consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => result.consoleErrors.push(String(e)));

  // 1. The model drawn.
  await page.goto(url);
  await page.waitForFunction(() => window.dieface && window.dieface.loadedVersion > 0
    && window.dieface.renderedVersion === window.dieface.loadedVersion, null, { timeout: 120000 });
  await page.screenshot({ path: join(outDir, 'model.png') });
  result.loadedVersion = await page.evaluate(() => window.dieface.loadedVersion);
  result.pieces = await page.evaluate(() => window.dieface.pieces());
  result.legend = await page.$$eval('#legend .legend-row', (rows) => rows.map((r) => ({
    kind: r.textContent.trim(), color: getComputedStyle(r.querySelector('.swatch')).backgroundColor,
  })));
  result.title = await page.textContent('#title');
  result.canvas = await page.evaluate(() => {
    const r = document.querySelector('#view canvas').getBoundingClientRect();
    return { x: r.left, y: r.top, width: r.width, height: r.height };
  });

  // 2. A click on the binder.
  const binder = result.pieces.filter((p) => p.startsWith('binder/'));
  for (const name of binder) {
    const at = await page.evaluate((n) => window.dieface.screenPointOf(n), name);
    if (!at) continue;
    await page.mouse.click(at.x, at.y);
    await page.waitForSelector('#pick:not([hidden])', { timeout: 5000 });
    await page.waitForFunction(() => window.dieface.lastPick && window.dieface.lastPick.summary, null, { timeout: 10000 })
      .catch(() => {});
    result.click = { target: name, at, panel: await page.textContent('#pick'), pick: await page.evaluate(() => window.dieface.lastPick) };
    break;
  }

  // 3. The analysis modes (the pick panel closed first, with Escape).
  await page.keyboard.press('Escape');
  await page.waitForSelector('#pick', { state: 'hidden', timeout: 5000 });
  await page.check('input[name=mode][value=draft]');
  await page.waitForTimeout(300);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await page.screenshot({ path: join(outDir, 'draft.png') });
  result.draftLegend = await page.textContent('#legend');
  await page.check('input[name=mode][value=seams]');
  await page.waitForFunction(() => window.dieface.seams !== null, null, { timeout: 30000 });
  const seams = await page.evaluate(() => window.dieface.seams);
  result.seams = { count: seams.count, max_deg: seams.max_deg, between: seams.max_between };
  result.seamLegend = await page.textContent('#legend');
  // The binder switched off takes its seams with it; on again, they come back.
  result.seams.drawn = await page.evaluate(() => window.dieface.seamPointsDrawn);
  await page.uncheck('#tree input[data-name="binder"]');
  result.seams.drawnWithoutBinder = await page.evaluate(() => window.dieface.seamPointsDrawn);
  await page.check('#tree input[data-name="binder"]');
  result.seams.drawnAgain = await page.evaluate(() => window.dieface.seamPointsDrawn);
  await page.check('input[name=mode][value=kind]');

  // 4. A save that moves the wheel-arch bead 5 mm outwards.
  const camera = () => page.evaluate(() => window.dieface.camera);
  const cameraBefore = await camera();
  const before = result.loadedVersion;
  const moved = original.replace('from (-200, -623.6); line to (500, -628.8)', 'from (-200, -628.6); line to (500, -633.8)');
  if (moved === original) throw new Error('the bead line to move is not in the script');
  const t0 = Date.now();
  writeFileSync(script, moved);
  await page.waitForFunction((v) => window.dieface.loadedVersion > v
    && window.dieface.renderedVersion === window.dieface.loadedVersion
    && window.dieface.timings, before, { timeout: 60000, polling: 20 });
  result.seenAfterMs = Date.now() - t0;
  // From the save to the frame that drew the new model, on this machine's clock (the
  // page stamps the frame; polling from here only adds its own delay).
  const timings = await page.evaluate(() => window.dieface.timings);
  result.saveToModelMs = timings.drawn_epoch_ms - t0;
  result.saveToStatusMs = timings.heard_epoch_ms - t0;
  result.buildMs = await page.evaluate(() => window.dieface.status.took_ms);
  result.pageTimings = await page.evaluate(() => window.dieface.timings);
  result.afterSave = await page.evaluate(() => ({ version: window.dieface.loadedVersion, pieces: window.dieface.pieces().length }));
  result.cameraKept = JSON.stringify(await camera()) === JSON.stringify(cameraBefore);
  await page.screenshot({ path: join(outDir, 'saved.png') });

  // 5. A broken save.
  const shown = result.afterSave.version;
  writeFileSync(script, moved + '\nlet broken = 1 mm + 2 deg\n');
  await page.waitForSelector('#diagnostic:not([hidden])', { timeout: 60000 });
  result.diagnostic = await page.textContent('#diagnostic');
  result.afterBroken = await page.evaluate(() => ({
    version: window.dieface.loadedVersion, pieces: window.dieface.pieces().length, state: window.dieface.status.state,
  }));
  await page.screenshot({ path: join(outDir, 'broken.png') });
  result.modelKept = result.afterBroken.version === shown && result.afterBroken.pieces === result.afterSave.pieces;

  // Fixed again: the diagnostic goes.
  writeFileSync(script, original);
  await page.waitForSelector('#diagnostic', { state: 'hidden', timeout: 60000 });
  result.recovered = true;
} finally {
  writeFileSync(script, original);
  await browser.close();
}

// 7. A browser without WebGL: the page says it cannot draw, rather than stay blank.
const noGl = await chromium.launch({
  executablePath,
  args: ['--no-sandbox', '--disable-gpu', '--disable-3d-apis', '--disable-webgl',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
try {
  const page = await noGl.newPage({ viewport: { width: 1200, height: 800 } });
  await page.goto(url);
  await page.waitForSelector('#diagnostic:not([hidden])', { timeout: 30000 });
  result.withoutWebgl = await page.textContent('#diagnostic');
} finally {
  await noGl.close();
}
console.log(JSON.stringify(result));
