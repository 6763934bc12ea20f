// GLB files written by the program for the GLB tests (glb_validator.test.mjs,
// glb_browser.test.mjs): a refined and a hoppe92 mesh of a sphere, each with
// and without vertex colours. The clouds are written here (an ASCII PLY of
// points on a sphere, seeded), so the tests need nothing but the program.

import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

// A small seeded generator (mulberry32), so every run writes the same cloud.
function random(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// n points uniform on the unit sphere, red above the equator and blue below
// when `colors`.
function sphereCloud(path, n, colors) {
  const next = random(7);
  const lines = ['ply', 'format ascii 1.0', `element vertex ${n}`, 'property double x', 'property double y',
    'property double z'];
  if (colors) lines.push('property uchar red', 'property uchar green', 'property uchar blue');
  lines.push('end_header');
  for (let i = 0; i < n; ++i) {
    const z = 2 * next() - 1, phi = 2 * Math.PI * next(), r = Math.sqrt(1 - z * z);
    const p = [r * Math.cos(phi), r * Math.sin(phi), z];
    lines.push(p.join(' ') + (colors ? (z > 0 ? ' 220 30 30' : ' 30 30 220') : ''));
  }
  writeFileSync(path, lines.join('\n') + '\n');
}

/// Writes the cases into `work` with the program `recon`; returns, per case,
/// its name, the GLB's bytes, whether it has colours, and the triangle count
/// of the same mesh written as PLY (read from its header).
export function writeGlbCases(recon, work) {
  sphereCloud(join(work, 'plain.ply'), 3000, false);
  sphereCloud(join(work, 'colored.ply'), 3000, true);
  const cases = [];
  for (const method of ['refined', 'hoppe92'])
    for (const input of ['plain', 'colored']) {
      const name = `${input}-${method}`;
      const args = ['reconstruct', join(work, `${input}.ply`), '--method', method, '-q'];
      execFileSync(recon, [...args, '-o', join(work, `${name}.glb`)], { stdio: 'pipe' });
      execFileSync(recon, [...args, '-o', join(work, `${name}.ply`), '--ascii'], { stdio: 'pipe' });
      const header = readFileSync(join(work, `${name}.ply`), 'latin1').split('end_header')[0];
      cases.push({
        name,
        bytes: readFileSync(join(work, `${name}.glb`)),
        colors: input === 'colored',
        triangles: Number(/element face (\d+)/.exec(header)[1]),
      });
    }
  return cases;
}
