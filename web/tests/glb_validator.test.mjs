// The GLB files the program writes, checked by the Khronos glTF validator
// (gltf-validator, web/package.json). Run by CTest (tests/CMakeLists.txt) as
//   RECON_CLI=build/release/app/recon node --test web/tests/glb_validator.test.mjs
// Exits with 77 (CTest: skipped) when the program or the validator is missing.
//
// Every case must have no error, no warning, no information and no hint:
// the validator's whole report is empty of issues.

import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { writeGlbCases } from './glb_files.mjs';

const recon = process.env.RECON_CLI;
let validator;
try {
  validator = (await import('gltf-validator')).default;
} catch {
  validator = undefined;
}
if (!recon || !existsSync(recon) || !validator) {
  console.log(`SKIPPED: the GLB validator test needs the program (RECON_CLI=${recon}) and web/'s npm ` +
    `package gltf-validator (${validator ? 'found' : 'missing'}); scripts/setup installs it`);
  process.exit(77);
}

const work = mkdtempSync(join(tmpdir(), 'recon-glb-validator-'));
after(() => rmSync(work, { recursive: true, force: true }));
const cases = writeGlbCases(recon, work);

for (const c of cases) {
  test(`${c.name}: the validator finds no issue`, async () => {
    const report = await validator.validateBytes(new Uint8Array(c.bytes), { uri: `${c.name}.glb`, maxIssues: 100 });
    const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
    assert.deepEqual({ numErrors, numWarnings, numInfos, numHints }, { numErrors: 0, numWarnings: 0, numInfos: 0, numHints: 0 },
      JSON.stringify(messages, null, 1));
    const info = report.info;
    assert.equal(info.version, '2.0');
    assert.equal(info.drawCallCount, 1);
    assert.equal(info.totalTriangleCount, c.triangles, 'the same triangles as the PLY of the same run');
    assert.equal(info.generator.startsWith('recon '), true);
    assert.equal(info.maxAttributes, c.colors ? 3 : 2, 'POSITION, NORMAL (and COLOR_0)');
    assert.equal(info.totalVertexCount > 0, true);
  });
}
