// The playground page in a real headless Chromium (Debian's, driven by
// playwright-core): points clicked on the canvas become curves, through the
// recon library compiled to WebAssembly. Assertions read the page's
// read-only state hook (window.reconPlayground.state()), not pixels.
//
// Run by CTest through web/playground/run-browser-tests, which builds the
// page first; PLAYGROUND_PAGE names the built index.html.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';

const page_file = process.env.PLAYGROUND_PAGE;
const chromium_path = process.env.PLAYGROUND_CHROMIUM || '/usr/bin/chromium';

let browser;
let page;
const console_errors = [];

before(async () => {
  assert.ok(page_file, 'PLAYGROUND_PAGE must name the built page (web/playground/run-browser-tests sets it)');
  browser = await chromium.launch({ executablePath: chromium_path, args: ['--no-sandbox'] });
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('console', (message) => {
    if (message.type() === 'error') console_errors.push(message.text());
  });
  page.on('pageerror', (error) => console_errors.push(String(error)));
  // Offline: any request leaving the file system fails the test.
  await page.route(/^(?!file:)/, (route) => {
    console_errors.push('network request: ' + route.request().url());
    return route.abort();
  });
  await page.goto(pathToFileURL(page_file).href);
  await page.waitForFunction(() => window.reconPlayground && window.reconPlayground.state().ready);
});

after(async () => {
  if (browser) await browser.close();
});

const state = () => page.evaluate(() => window.reconPlayground.state());

// Waits for the page to finish the updates that `action` causes.
async function settled(action) {
  const before_count = (await state()).updateCount;
  await action();
  await page.waitForFunction((n) => {
    const s = window.reconPlayground.state();
    return s.updateCount > n && !s.pending;
  }, before_count);
  return state();
}

async function clear() {
  await settled(() => page.click('button[data-preset="clear"]'));
}

// Clicks n points evenly around a circle (world units).
async function click_circle(cx, cy, r, n) {
  for (let i = 0; i < n; ++i) {
    const t = (2 * Math.PI * (i + 0.3)) / n;
    const at = await page.evaluate(([x, y]) => window.reconPlayground.worldToPage(x, y), [cx + r * Math.cos(t), cy + r * Math.sin(t)]);
    await page.mouse.click(at.x, at.y);
  }
}

test('points clicked around a circle make one closed curve', async () => {
  await clear();
  const s = await settled(() => click_circle(0, 0, 1, 24));
  assert.equal(s.points, 24);
  assert.equal(s.error, '');
  assert.equal(s.curves, 1);
  assert.deepEqual(s.closed, [true]);
});

test('two separate clusters make two closed curves', async () => {
  await clear();
  const s = await settled(async () => {
    await click_circle(-1.0, 0.2, 0.5, 16);
    await click_circle(1.1, -0.3, 0.45, 16);
  });
  assert.equal(s.points, 32);
  assert.equal(s.curves, 2);
  assert.deepEqual(s.closed, [true, true]);
});

test('shift-click removes a point and dragging moves one', async () => {
  await clear();
  let s = await settled(() => click_circle(0, 0, 1, 20));
  assert.equal(s.points, 20);
  const first = await page.evaluate(() => window.reconPlayground.worldToPage(Math.cos(0.3 * 2 * Math.PI / 20), Math.sin(0.3 * 2 * Math.PI / 20)));
  await page.keyboard.down('Shift');
  s = await settled(() => page.mouse.click(first.x, first.y));
  await page.keyboard.up('Shift');
  assert.equal(s.points, 19);
  // Drag the point at angle 1.3 steps outward; it stays one point.
  const t = (2 * Math.PI * 1.3) / 20;
  const from = await page.evaluate(([x, y]) => window.reconPlayground.worldToPage(x, y), [Math.cos(t), Math.sin(t)]);
  const to = await page.evaluate(([x, y]) => window.reconPlayground.worldToPage(x, y), [1.05 * Math.cos(t), 1.05 * Math.sin(t)]);
  s = await settled(async () => {
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    await page.mouse.move(to.x, to.y, { steps: 4 });
    await page.mouse.up();
  });
  assert.equal(s.points, 19);
  assert.equal(s.curves, 1);
});

test('the graph and the spanning-tree algorithm are the student\'s choice', async () => {
  // Two circles: every graph but the complete one keeps them apart.
  await settled(() => page.click('button[data-preset="two-circles"]'));
  const riemannian = await settled(() => page.selectOption('#graph', '4'));
  assert.equal(riemannian.graph, 'Riemannian');
  assert.equal(riemannian.components, 2);
  const complete = await settled(() => page.selectOption('#graph', '0'));
  assert.equal(complete.components, 1);
  assert.equal(complete.graphEdges, complete.points - 1);  // the complete graph's Euclidean MST, a tree
  const knn = await settled(() => page.selectOption('#graph', '2'));
  const mutual = await settled(() => page.selectOption('#graph', '3'));
  assert.ok(mutual.graphEdges < knn.graphEdges, `${mutual.graphEdges} vs ${knn.graphEdges}`);
  await settled(() => page.selectOption('#graph', '4'));
  // Every algorithm: a forest of the same weight, n - pieces edges, and the
  // counts of its own kind of work shown beside the timing.
  const runs = [];
  for (const tree of ['0', '1', '2', '3', '4', '5']) runs.push(await settled(() => page.selectOption('#tree', tree)));
  for (const r of runs) {
    assert.ok(Math.abs(r.treeWeight - runs[0].treeWeight) <= 1e-9 * Math.max(1, runs[0].treeWeight), r.tree);
    assert.equal(r.treeEdges, r.points - r.components, r.tree);
    assert.ok(r.countsText.startsWith(r.tree + ' on the Riemannian graph'), r.countsText);
  }
  for (const r of runs.slice(0, 4)) {  // Prim, on each queue
    assert.equal(r.counts.pops, r.points, r.tree);
    assert.equal(r.counts.decreaseKeys, runs[0].counts.decreaseKeys, r.tree);
    assert.ok(r.counts.comparisons > 0 && r.countsText.includes('decrease-keys'), r.countsText);
  }
  assert.ok(runs[3].counts.comparisons > runs[0].counts.comparisons, 'the list heap scans its list');
  assert.equal(runs[4].counts.unions, runs[4].points - runs[4].components);  // Kruskal
  assert.ok(runs[4].countsText.includes('finds'), runs[4].countsText);
  assert.ok(runs[5].counts.rounds >= 1 && runs[5].countsText.includes('rounds'), runs[5].countsText);  // Borůvka
  await settled(() => page.selectOption('#tree', '0'));
});

test('moving a slider changes the result', async () => {
  await settled(() => page.click('button[data-preset="noisy-ellipse"]'));
  const coarse_cell = 0.1;
  const fine = await settled(() => page.locator('#cell').fill('0.02'));
  const coarse = await settled(() => page.locator('#cell').fill(String(coarse_cell)));
  assert.equal(fine.cell, 0.02);
  assert.equal(coarse.cell, coarse_cell);
  assert.equal(fine.curves, 1);
  assert.equal(coarse.curves, 1);
  // Five times the cell: far fewer vertices on the same curve.
  assert.ok(coarse.vertexCounts[0] * 2 < fine.vertexCounts[0], `${coarse.vertexCounts} vs ${fine.vertexCounts}`);
  // k too: the slider's k is the k used.
  const k = await settled(() => page.locator('#k').fill('12'));
  assert.equal(k.k, 12);
  await settled(() => page.locator('#cell').fill('0'));
  await settled(() => page.locator('#k').fill('8'));
});

test('a few hundred points update well under 50 ms', async () => {
  // The noisy ellipse has 300 points; nudge the rho slider a few times and
  // take the median update time (reconstruction, copies and all).
  const s0 = await settled(() => page.click('button[data-preset="noisy-ellipse"]'));
  assert.equal(s0.points, 300);
  const times = [];
  for (const rho of ['0.1', '0.105', '0.11', '0.115', '0.12', '0']) {
    const s = await settled(() => page.locator('#rho').fill(rho));
    times.push(s.lastUpdateMs);
  }
  times.sort((a, b) => a - b);
  const median = times[Math.floor(times.length / 2)];
  console.log(`playground update, 300 points: median ${median.toFixed(2)} ms (${times.map((t) => t.toFixed(1)).join(', ')})`);
  assert.ok(median < 50, `median update ${median} ms`);
  const timing = await page.textContent('#timing');
  assert.match(timing, /update [0-9.]+ ms for 300 points/);
});

test("Hoppe's curve1 preset is embedded and makes one open curve", async () => {
  const s = await settled(() => page.click('button[data-preset="curve1"]'));
  assert.equal(s.points, 126);
  assert.equal(s.curves, 1);
  assert.deepEqual(s.closed, [false]);
});

test('no console errors and no network requests', () => {
  assert.deepEqual(console_errors, []);
});
