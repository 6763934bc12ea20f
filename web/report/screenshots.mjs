// Pictures of a report's layers for docs/phases.md: opens REPORT.html in
// headless Chromium and saves one PNG of the 3D view per step below.
//   node report/screenshots.mjs REPORT.html OUT_FOLDER PREFIX
// (scripts/phase-pictures makes the report and runs this.)
import { chromium } from 'playwright-core';
import { resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const [report, folder, prefix = 'phase'] = process.argv.slice(2);
if (!report || !folder) {
  console.error('usage: node report/screenshots.mjs REPORT.html OUT_FOLDER [PREFIX]');
  process.exit(2);
}
const chromiumPath = process.env.RECON_CHROMIUM || '/usr/bin/chromium';

// Each picture: the layers shown, the kd-tree depth, and a camera move
// (orbit angle in radians about z, distance factor) from the default view.
const steps = [
  { name: 'overview', layers: ['mesh'], page: true },
  { name: '1-points', layers: ['points'] },
  { name: '2-kdtree-depth-2', layers: ['points', 'kdtree'], depth: 2 },
  { name: '2-kdtree-depth-6', layers: ['points', 'kdtree'], depth: 6 },
  { name: '3-tangent-planes', layers: ['pca'], zoom: 0.6 },
  { name: '4-graph-and-tree', layers: ['graph'], zoom: 0.45 },
  { name: '5-oriented-normals', layers: ['normals'], zoom: 0.6 },
  { name: '6-signed-distance', layers: ['distance'] },
  { name: '7-mesh', layers: ['mesh'] },
  { name: '8-refinement', layers: ['refinement'] },
];
const only = process.env.RECON_PICTURES?.split(',');

const browser = await chromium.launch({ executablePath: chromiumPath, args: ['--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });
const page = await browser.newPage({ viewport: { width: 1240, height: 640 }, offline: true });
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
await page.goto(pathToFileURL(resolve(report)).href);
await page.waitForFunction(() => window.reconReport?.ready === true, null, { timeout: 120000 });
await page.addStyleTag({ content: '#hint { display: none; }' });
const available = await page.evaluate(() => window.reconReport.layers.filter((l) => l.available).map((l) => l.id));
for (const step of steps) {
  if (only && !only.includes(step.name)) continue;
  if (!step.layers.every((id) => available.includes(id))) continue;
  await page.evaluate(({ layers, depth, zoom }) => {
    const r = window.reconReport;
    for (const l of r.layers) r.setVisible(l.id, layers.includes(l.id));
    if (depth !== undefined) { r.setKdDepth(depth); document.getElementById('kd-depth').value = depth; }
    r.resetView();
    if (zoom !== undefined) r.zoom(zoom);
  }, step);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const path = `${folder}/${prefix}-${step.name}.png`;
  if (step.page) await page.screenshot({ path });
  else await page.locator('#canvas').screenshot({ path });
  console.log(`wrote ${path}`);
}
await browser.close();
if (errors.length) {
  console.error(errors.join('\n'));
  process.exit(1);
}
