// The GLB files the program writes, loaded in Debian's Chromium (driven
// headless by playwright-core, offline) by three.js's GLTFLoader from the
// same three package the report uses, and drawn: the renderer must draw as
// many triangles as the mesh has, with vertex colours exactly when the
// input had colours. Run by CTest (tests/CMakeLists.txt) as
//   RECON_CLI=build/release/app/recon node --test web/tests/glb_browser.test.mjs
// Exits with 77 (CTest: skipped) when Chromium or the program is missing.

import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { writeGlbCases } from './glb_files.mjs';

const recon = process.env.RECON_CLI;
const chromiumPath = process.env.RECON_CHROMIUM || '/usr/bin/chromium';
if (!recon || !existsSync(recon) || !existsSync(chromiumPath)) {
  console.log(`SKIPPED: the GLB browser test needs the program (RECON_CLI=${recon}) and Chromium ` +
    `(${chromiumPath}); scripts/setup installs Chromium`);
  process.exit(77);
}
const { chromium } = await import('playwright-core');
const esbuild = await import('esbuild');

// The page's script: three.js and its GLTFLoader, bundled as the report's
// viewer is (web/report/build.mjs), so nothing is fetched.
const viewer = `
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
window.drawGlb = async (base64) => {
  const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
  const gltf = await new GLTFLoader().parseAsync(bytes.buffer, '');
  const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById('canvas') });
  renderer.setSize(400, 400, false);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.1, 100);
  camera.position.set(0, 0, 5);
  camera.lookAt(0, 0, 0);
  const scene = new THREE.Scene();
  scene.add(new THREE.DirectionalLight(0xffffff, 2), gltf.scene);
  renderer.render(scene, camera);
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
  const geometry = meshes[0]?.geometry;
  return {
    meshes: meshes.length,
    drawn: renderer.info.render.triangles,
    indexed: geometry?.index ? geometry.index.count / 3 : 0,
    colors: !!geometry?.attributes.color,
    normals: !!geometry?.attributes.normal,
    vertexColors: !!meshes[0]?.material.vertexColors,
  };
};`;

const work = mkdtempSync(join(tmpdir(), 'recon-glb-browser-'));
let browser, script;
before(async () => {
  const web = join(dirname(fileURLToPath(import.meta.url)), '..');
  const built = await esbuild.build({
    stdin: { contents: viewer, resolveDir: web, loader: 'js' }, bundle: true, write: false, format: 'iife', logLevel: 'silent',
  });
  script = built.outputFiles[0].text;
  browser = await chromium.launch({ executablePath: chromiumPath, args: ['--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });
});
after(async () => {
  await browser?.close();
  rmSync(work, { recursive: true, force: true });
});

const cases = writeGlbCases(recon, work);
for (const c of cases) {
  test(`${c.name}: three.js draws the mesh's ${c.colors ? 'coloured ' : ''}triangles`, async () => {
    const context = await browser.newContext({ offline: true });
    const page = await context.newPage();
    const problems = [], requests = [];
    page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
    page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
    page.on('request', (r) => requests.push(r.url()));
    await page.setContent('<!doctype html><canvas id="canvas" width="400" height="400"></canvas>');
    await page.addScriptTag({ content: script });
    const drawn = await page.evaluate((b64) => window.drawGlb(b64), c.bytes.toString('base64'));
    await context.close();
    assert.deepEqual(problems, []);
    assert.deepEqual(requests, [], 'the page fetched nothing');
    assert.equal(drawn.meshes, 1);
    assert.equal(drawn.indexed, c.triangles);
    assert.equal(drawn.drawn, c.triangles, 'triangles drawn');
    assert.equal(drawn.normals, true);
    assert.equal(drawn.colors, c.colors);
    assert.equal(drawn.vertexColors, c.colors);
  });
}
