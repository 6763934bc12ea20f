// The report's first view, as pure functions of plain arrays (no three.js),
// so that web/tests/framing.test.mjs can check them in Node.
//
// The view frames the bounding sphere of everything drawn (src/report/report.cpp
// writes the box, data.drawn_box): the camera looks at the sphere's centre
// from a fixed direction, at the distance where the sphere fits inside the
// narrower of the two fields of view. A sphere, not the box, so that the
// model stays in view whichever way it is then turned, and a tall model
// (taller than the view is wide, say) fits as a wide one does. The clipping
// planes enclose the sphere and follow the camera as it moves.

// Seen from the front, right and above (z is up, as Hoppe's orientation has it).
export const defaultDirection = [0.65, -0.95, 0.6];

// Room left around the sphere: its outline covers 1 / margin of the narrower field of view.
export const defaultMargin = 1.02;

const length = (v) => Math.hypot(...v);

// The sphere through the corners of the box min..max (3 numbers each).
export function boundingSphere(min, max) {
  const centre = min.map((m, i) => 0.5 * (m + max[i]));
  const radius = 0.5 * length(max.map((m, i) => m - min[i]));
  return { centre, radius };
}

// Half the vertical and horizontal fields of view, in radians, of a
// perspective camera with vertical field fovYDegrees and width / height aspect.
export function halfFields(fovYDegrees, aspect) {
  const vertical = (fovYDegrees * Math.PI) / 360;
  return { vertical, horizontal: Math.atan(Math.tan(vertical) * aspect) };
}

// Near and far planes that clip nothing of a sphere of this radius whose
// centre lies `distance` from the camera. Inside the sphere, the near plane
// stays a thousandth of the radius away, which keeps the depth buffer's
// precision.
export function clipPlanes(distance, radius) {
  const r = radius > 0 ? radius : 1;
  return { near: Math.max(0.9 * (distance - r), 1e-3 * r), far: 1.1 * (distance + r) };
}

// The camera that frames `sphere` ({ centre, radius }) from `direction`
// (towards the camera; need not be unit): its position, the point it looks
// at, its distance from it, and its clipping planes. A point of the sphere
// is seen at most asin(radius / distance) off the axis, which the margin
// keeps inside both fields of view.
export function frameSphere(sphere, { fovY, aspect, direction = defaultDirection, margin = defaultMargin }) {
  const radius = sphere.radius > 0 ? sphere.radius : 1;
  const { vertical, horizontal } = halfFields(fovY, aspect);
  const distance = (margin * radius) / Math.sin(Math.min(vertical, horizontal));
  const unit = direction.map((c) => c / length(direction));
  const position = sphere.centre.map((c, i) => c + distance * unit[i]);
  return { position, target: [...sphere.centre], distance, ...clipPlanes(distance, radius) };
}
