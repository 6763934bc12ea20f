// Tests of the report's first view (web/report/framing.js), in Node alone:
// run by CTest (tests/CMakeLists.txt) as
//   node --test web/tests/framing.test.mjs
// The oracle projects each corner of the box with a camera built here from
// the position and target (a look-at frame, z up), as three.js's
// PerspectiveCamera would, and checks it lands inside the viewport and
// between the clipping planes.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { boundingSphere, clipPlanes, defaultDirection, frameSphere, halfFields } from '../report/framing.js';

const sub = (a, b) => a.map((x, i) => x - b[i]);
const dot = (a, b) => a.reduce((s, x, i) => s + x * b[i], 0);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => a.map((x) => x / Math.hypot(...a));

function corners(min, max) {
  const out = [];
  for (let i = 0; i < 8; ++i) out.push([0, 1, 2].map((c) => ((i >> c) & 1 ? max[c] : min[c])));
  return out;
}

// Where p lands: normalised device x and y (the viewport is [-1, 1]^2),
// its depth along the view axis and its distance from the camera.
function project(p, view, fovY, aspect) {
  const forward = unit(sub(view.target, view.position));
  const right = unit(cross(forward, [0, 0, 1]));
  const up = cross(right, forward);
  const v = sub(p, view.position);
  const depth = dot(v, forward);
  const tanY = Math.tan((fovY * Math.PI) / 360);
  return { x: dot(v, right) / (depth * tanY * aspect), y: dot(v, up) / (depth * tanY), depth, distance: Math.hypot(...v) };
}

function assertFramed(min, max, fovY, aspect, direction = defaultDirection) {
  const sphere = boundingSphere(min, max);
  const view = frameSphere(sphere, { fovY, aspect, direction });
  const where = `box ${min}..${max}, aspect ${aspect}, from ${direction}`;
  assert.ok(Math.hypot(...sub(view.position, sphere.centre)) > sphere.radius, `the camera is outside the bounding sphere (${where})`);
  const seen = corners(min, max).map((p) => project(p, view, fovY, aspect));
  for (const s of seen) {
    assert.ok(Math.abs(s.x) < 1 && Math.abs(s.y) < 1, `corner at (${s.x.toFixed(3)}, ${s.y.toFixed(3)}) is in the viewport (${where})`);
    assert.ok(s.depth > 0, `corner in front of the camera (${where})`);
  }
  const nearest = Math.min(...seen.map((s) => s.depth)), farthest = Math.max(...seen.map((s) => s.distance));
  assert.ok(view.near > 0 && view.near < nearest, `near ${view.near} < nearest corner ${nearest} (${where})`);
  assert.ok(view.far > farthest, `far ${view.far} > farthest corner ${farthest} (${where})`);
  return { view, seen };
}

// The model's extent along the narrower field of view, in the viewport
// (2 is the viewport's whole width or height).
const spread = (seen, axis) => Math.max(...seen.map((s) => s[axis])) - Math.min(...seen.map((s) => s[axis]));

test('a tall thin box is framed whole, from outside, in landscape and portrait views', () => {
  for (const aspect of [1.5, 1, 0.6]) {
    const { seen } = assertFramed([-0.1, -0.1, -5], [0.1, 0.1, 5], 40, aspect);
    // And not lost in the distance: it spans much of the height.
    assert.ok(spread(seen, 'y') > 0.5 * Math.min(1, aspect), `spans ${spread(seen, 'y').toFixed(2)} of 2 (aspect ${aspect})`);
  }
  // Tall along y (the armadillo's up), far from the origin.
  assertFramed([100, 180, 300], [102, 260, 305], 40, 1.6);
});

test('a wide flat box is framed whole, from outside', () => {
  for (const aspect of [2.5, 1.5, 0.7]) assertFramed([-5, -3, -0.05], [5, 3, 0.05], 40, aspect);
  // Seen from straight above and along an axis as well.
  assertFramed([-5, -3, -0.05], [5, 3, 0.05], 40, 1.5, [0.01, 0, 1]);
  assertFramed([-5, -3, -0.05], [5, 3, 0.05], 40, 1.5, [1, 0, 0]);
});

test('other fields of view: the narrower one decides the distance', () => {
  for (const fovY of [20, 60, 90]) for (const aspect of [0.5, 2]) assertFramed([-1, -2, -3], [1, 2, 3], fovY, aspect);
  const { vertical, horizontal } = halfFields(40, 0.5);
  assert.ok(horizontal < vertical);
  const sphere = { centre: [0, 0, 0], radius: 1 };
  assert.ok(Math.abs(frameSphere(sphere, { fovY: 40, aspect: 0.5, margin: 1 }).distance - 1 / Math.sin(horizontal)) < 1e-12);
});

test('the clipping planes enclose the sphere wherever the camera is, and a degenerate box still gives a view', () => {
  for (const distance of [0, 0.5, 1, 1.01, 3, 1000]) {
    const { near, far } = clipPlanes(distance, 1);
    assert.ok(near > 0 && far > distance + 1 && near <= Math.max(distance - 1, 1e-3));
  }
  const view = frameSphere(boundingSphere([2, 2, 2], [2, 2, 2]), { fovY: 40, aspect: 1 });
  assert.ok(view.distance > 0 && Number.isFinite(view.near) && view.near < view.distance && view.far > view.distance);
});
