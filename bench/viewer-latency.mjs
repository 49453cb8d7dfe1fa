// From save to the new model drawn in the live viewer's page, for the fender, as a
// designer sees it: the real `dieface view` (release build) and the real page in
// headless Chromium.
//
//   cargo build --release && node bench/viewer-latency.mjs [SAVES]
//   (DIEFACE=/path/to/dieface measures another binary; CHROMIUM=/path/to/chromium)
//
// Copies examples/fender/fender.die to a temporary folder, starts `dieface view` on it,
// opens the page, and saves edits the way an editor does (a new file renamed over the
// old one), alternating each edit's two texts. Per save, on one wall clock:
//   save -> status: until the page hears the build is done (debounce + build + event);
//   status -> drawn: fetching the GLB and info, parsing, and the frame that draws it;
//   save -> drawn: the whole wait.
// The build's own time is what `view` prints for the rebuild. Baseline in the same run:
// a cold `dieface build fender.die -o fender.glb`, timed as a whole process (median
// of 5). Prints markdown for BENCHMARKS.md.

import { chromium } from 'playwright-core';
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, renameSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createInterface } from 'node:readline';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const saves = Number(process.argv[2] || 11);
const dieface = process.env.DIEFACE || join(root, 'target/release/dieface');
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';

const edits = [
  {
    what: 'an edit no feature uses (the blank outline\'s size)',
    before: '1700 mm, 1400 mm, 80 mm',
    after: '1720 mm, 1400 mm, 80 mm',
  },
  {
    what: 'the wheel-arch bead moved 5 mm',
    before: 'from (-200, -623.6); line to (500, -628.8)',
    after: 'from (-200, -628.6); line to (500, -633.8)',
  },
  {
    what: 'a binder-wrap edit (one point of the front wrap)',
    before: '(0, -78)',
    after: '(0, -76)',
  },
];

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};
const fmt = (ms) => `${ms.toFixed(0)} ms`;

const dir = mkdtempSync(join(tmpdir(), 'dieface-viewer-bench-'));
const script = join(dir, 'fender.die');
const original = readFileSync(join(root, 'examples/fender/fender.die'), 'utf8');
writeFileSync(script, original);

// Saves `text` as an editor does: a new file renamed over the script.
function save(text) {
  const tmp = join(dir, '.fender.die.swp');
  writeFileSync(tmp, text);
  renameSync(tmp, script);
}

// Baseline: cold builds of the same script, as whole processes.
const cold = [];
for (let i = 0; i < 5; i++) {
  const t = performance.now();
  execFileSync(dieface, ['build', 'fender.die', '-o', 'fender.glb'], { cwd: dir, stdio: 'ignore' });
  cold.push(performance.now() - t);
}

const server = spawn(dieface, ['view', 'fender.die', '--port', '0'], { cwd: dir, stdio: ['ignore', 'pipe', 'ignore'] });
const lines = createInterface({ input: server.stdout });
const printed = [];
const url = await new Promise((resolve) => {
  lines.on('line', (l) => {
    printed.push(l);
    const m = l.match(/^viewer at (http:\/\/\S+)/);
    if (m) resolve(m[1]);
  });
});

const browser = await chromium.launch({
  executablePath,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
const rows = [];
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  await page.goto(url);
  await page.waitForFunction(() => window.dieface && window.dieface.loadedVersion > 0
    && window.dieface.timings, null, { timeout: 120000 });
  let text = original;
  for (const edit of edits) {
    if (!text.includes(edit.before)) throw new Error(`not in the script: ${edit.before}`);
    const samples = { status: [], drawn: [], total: [], build: [] };
    for (let i = 0; i < saves; i++) {
      const next = i % 2 === 0 ? text.replace(edit.before, edit.after) : text;
      const before = await page.evaluate(() => window.dieface.status.version);
      const t0 = Date.now();
      save(next);
      // The status after this save (a new version, done), then its model drawn.
      await page.waitForFunction((v) => window.dieface.status.version > v
        && window.dieface.status.state === 'ok', before, { timeout: 60000, polling: 10 });
      const status = await page.evaluate(() => window.dieface.status);
      // Every edit here changes what is drawn, so a new model follows.
      await page.waitForFunction(([mv, since]) => window.dieface.loadedVersion >= mv
        && window.dieface.timings && window.dieface.timings.drawn_epoch_ms > since
        && window.dieface.renderedVersion === window.dieface.loadedVersion,
      [status.model_version, t0], { timeout: 60000, polling: 10 });
      const t = await page.evaluate(() => window.dieface.timings);
      samples.status.push(t.heard_epoch_ms - t0);
      samples.drawn.push(t.drawn_epoch_ms - t.heard_epoch_ms);
      samples.total.push(t.drawn_epoch_ms - t0);
      samples.build.push(status.took_ms);
      // Let the page settle before the next save.
      await page.waitForTimeout(300);
    }
    text = original;
    rows.push({ what: edit.what, ...Object.fromEntries(Object.entries(samples).map(([k, v]) => [k, median(v)])) });
  }
} finally {
  await browser.close();
  server.kill();
  save(original);
}
rmSync(dir, { recursive: true, force: true });

const coldMs = median(cold);
console.log(`Cold \`dieface build fender.die -o fender.glb\` (whole process, median of 5): ${fmt(coldMs)}.`);
console.log(`Medians of ${saves} saves each:\n`);
console.log('| edit (fender) | build (as `view` prints it) | save -> status heard | status -> model drawn | save -> model drawn | drawn / cold build |');
console.log('| --- | ---: | ---: | ---: | ---: | ---: |');
for (const r of rows) {
  console.log(`| ${r.what} | ${fmt(r.build)} | ${fmt(r.status)} | ${fmt(r.drawn)} | **${fmt(r.total)}** | ${(r.total / coldMs).toFixed(2)}x |`);
}
