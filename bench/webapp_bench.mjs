// The web page's targets (issue 29), measured in headless Chromium on this
// machine; not part of CI (a minute or two). Prints the figures that
// docs/benchmarks.md records under "Issue 29".
//   1. 100k points, refined, end to end (the file given to the page's input
//      until the mesh is there, reading included) against the program with
//      --threads 1 on the same file (reading included): at most 3 times.
//   2. 1M points: the run completes, and no main-thread task takes over
//      100 ms while the worker runs (PerformanceObserver 'longtask').
// Usage (after scripts/webapp and a release build):
//   node bench/webapp_bench.mjs [build/webapp/index.html] [build/release/app/recon]
import { execFileSync } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir, cpus } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';
import { createRequire } from 'node:module';

const require = createRequire(resolve('web/package.json'));
const { chromium } = require('playwright-core');
const pageFile = resolve(process.argv[2] ?? 'build/webapp/index.html');
const cli = resolve(process.argv[3] ?? 'build/release/app/recon');
const folder = mkdtempSync(join(tmpdir(), 'recon-webapp-bench-'));

function cloud(points) {
  const path = join(folder, `torus-${points}.ply`);
  execFileSync(cli, ['--quiet', 'generate', 'torus', '-n', String(points), '-o', path]);
  return path;
}

function native(path) {
  const start = process.hrtime.bigint();
  execFileSync(cli, ['--quiet', 'reconstruct', '--threads', '1', path, '-o', join(folder, 'mesh.ply')]);
  return Number(process.hrtime.bigint() - start) / 1e9;
}

// The page's run on `path`: seconds from the file input to 'done', the
// main thread's long tasks meanwhile, and the run's statistics.
async function inPage(browser, path) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.addInitScript(() => {
    window.longTasks = [];
    new PerformanceObserver((list) => { for (const e of list.getEntries()) window.longTasks.push(e); })
      .observe({ type: 'longtask', buffered: true });
  });
  await page.goto(pathToFileURL(pageFile).href);
  await page.waitForFunction(() => document.body.dataset.state === 'idle');
  await page.evaluate(() => { window.longTasks = []; });
  const start = Date.now();
  await page.setInputFiles('#file', path);
  await page.waitForFunction(() => ['done', 'error'].includes(document.body.dataset.state), null, { timeout: 900000, polling: 10 });
  const seconds = (Date.now() - start) / 1000;
  // The main thread's tasks over 50 ms while the worker ran, and after (the final layers drawn).
  const result = await page.evaluate(() => ({ state: document.body.dataset.state, error: window.recon.error,
    stats: window.recon.stats, layerTimes: window.recon.views, timeline: window.recon.timeline,
    longTasks: window.longTasks.filter((e) => e.startTime < window.recon.runEndedAt).map((e) => e.duration),
    longTasksAfter: window.longTasks.filter((e) => e.startTime >= window.recon.runEndedAt).map((e) => e.duration) }));
  await page.close();
  console.log(`  in the worker ${result.stats?.seconds_total?.toFixed(2)} s (reading ${result.stats?.input?.seconds?.toFixed(2)} s); ` +
    `layers set up on the main thread: ${result.layerTimes.map((t) => `${(t.bytes / 1e6).toFixed(1)} MB in ${t.ms.toFixed(0)} ms`).join('; ')}`);
  const t = result.timeline;
  if (t) console.log(`  the page's run: file read and handed to the worker, and its reader ${((t.loaded - t.start) / 1000).toFixed(2)} s; ` +
    `the run, its layers and their copies ${((t.answered - t.loaded) / 1000).toFixed(2)} s; the final view ${((t.done - t.answered) / 1000).toFixed(2)} s`);
  return { seconds, ...result };
}

const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox'] });
try {
  console.log(`machine: ${cpus()[0].model}, ${cpus().length} cores; ${new Date().toISOString()}`);
  const p100k = cloud(100000);
  const nativeSeconds = native(p100k);
  const page100k = await inPage(browser, p100k);
  console.log(`100k points, refined: page ${page100k.seconds.toFixed(2)} s (${page100k.state}${page100k.error}), ` +
    `program --threads 1 ${nativeSeconds.toFixed(2)} s: ${(page100k.seconds / nativeSeconds).toFixed(2)} times; ` +
    `${page100k.stats?.mesh?.faces} triangles; longest main-thread task while the worker ran ${Math.max(0, ...page100k.longTasks).toFixed(0)} ms, ` +
    `after ${Math.max(0, ...page100k.longTasksAfter).toFixed(0)} ms`);
  const p1m = cloud(1000000);
  const page1m = await inPage(browser, p1m);
  console.log(`1M points, refined: page ${page1m.seconds.toFixed(1)} s (${page1m.state}${page1m.error}); ` +
    `${page1m.stats?.mesh?.faces} triangles; main-thread tasks over 50 ms while the worker ran: ${page1m.longTasks.length}, ` +
    `the longest ${Math.max(0, ...page1m.longTasks).toFixed(0)} ms; after (the final layers drawn): the longest ${Math.max(0, ...page1m.longTasksAfter).toFixed(0)} ms`);
  console.log(`1M points, the program --threads 1: ${native(p1m).toFixed(1)} s`);
} finally {
  await browser.close();
  rmSync(folder, { recursive: true, force: true });
}
