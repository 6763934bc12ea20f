// The report's viewer: reads the data block recon wrote into the page
// (src/report/report.cpp) and draws each phase as a layer with three.js; with the
// alternatives lab's data, its panel too (lab.js) and a layer per
// orientation graph. Bundled with three.js into one script by
// web/report/build.mjs at build time, so the page needs nothing from the
// network.
//
// The JSON block holds the figures; each array is base64 text in its own
// element, little-endian; positions are float32 relative to data.centre.
// The page renders only when something changes (a toggle, the slider, the
// camera). One viewer for the report (report.js) and the web page
// (web/webapp/page.js): both call showReport below.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { boundingSphere, clipPlanes, frameSphere } from './framing.js';
import { labPanel } from './lab.js';

const colours = {
  kdtree: 0x3c4a5c, graph: 0x9aa0a6, tree: 0x1a73e8, flip: 0xd62728,
  outside: 0xe8710a, inside: 0x1a73e8, undefined: 0xc000c0,
  meshFront: 0xd8d8d8, meshBack: 0xb04040, boundary: 0xe00000,
};

// The meshes' material (layers 7 and 8). One pass for both sides: diffuse light from the viewer's direction, the
// outside grey (or, with vertexColours, the colour of each vertex), the
// inside (a back face: a hole, or a wrongly oriented part) red.
function meshMaterial(vertexColours = false) {
  return new THREE.ShaderMaterial({
    side: THREE.DoubleSide,
    vertexColors: vertexColours,  // defines USE_COLOR and the colour attribute
    uniforms: { front: { value: new THREE.Color(colours.meshFront) }, back: { value: new THREE.Color(colours.meshBack) } },
    vertexShader: `
      uniform vec3 front;
      varying vec3 viewNormal;
      varying vec3 viewPosition;
      varying vec3 outside;
      void main() {
        vec4 p = modelViewMatrix * vec4(position, 1.0);
        viewPosition = p.xyz;
        viewNormal = normalMatrix * normal;
        #ifdef USE_COLOR
          outside = color;
        #else
          outside = front;
        #endif
        gl_Position = projectionMatrix * p;
      }`,
    fragmentShader: `
      uniform vec3 back;
      varying vec3 viewNormal;
      varying vec3 viewPosition;
      varying vec3 outside;
      void main() {
        vec3 n = normalize(viewNormal) * (gl_FrontFacing ? 1.0 : -1.0);
        float light = 0.35 + 0.65 * abs(dot(n, normalize(-viewPosition)));
        gl_FragColor = vec4((gl_FrontFacing ? outside : back) * light, 1.0);
        #include <colorspace_fragment>
      }`,
  });
}

// A renderer for the canvas, as the views draw: multisampled or not
// (antialiasing costs little on a graphics card but doubles the time of a
// frame drawn in software; large meshes, which fill the picture with tiny
// triangles anyway, go without), its picture kept for reading (the report's
// screenshots, scripts/phase-pictures) or not (the web page: a copy less
// per frame).
export function makeRenderer(canvas, antialias, preserveDrawingBuffer = true) {
  const renderer = new THREE.WebGLRenderer({ canvas, antialias, preserveDrawingBuffer });
  renderer.setPixelRatio(Math.min(2, window.devicePixelRatio));
  renderer.setClearColor(0xf4f5f7);
  return renderer;
}

// Compiles, on `renderer`, the shaders of everything a view draws (points,
// lines plain and coloured, meshes plain and coloured), from a scene of one
// of each. The web page does it while idle: compiling a shader takes a
// few hundred milliseconds in a software renderer, more than a task should
// while the worker runs.
export function warmUp(renderer) {
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 10);
  camera.position.set(0, 0, 3);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9), 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1]), 3));
  const objects = [
    new THREE.Points(geometry, new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: true })),
    new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0 })),
    new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0, transparent: true, opacity: 0.5 })),
    new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true })),
    new THREE.Mesh(geometry, meshMaterial(false)),
    new THREE.Mesh(geometry, meshMaterial(true)),
  ];
  for (const o of objects) scene.add(o);
  renderer.compile(scene, camera);
  renderer.render(scene, camera);
  geometry.dispose();
  for (const o of objects) o.material.dispose();
}

// Frames that never hold the page's main thread while they are drawn (the
// web page's, while its worker runs). Without a graphics card, the browser
// draws in software and, to show the canvas, reads its picture back on the
// main thread, waiting there until the frame is drawn: 30-70 ms for a view
// of phases I-II while the worker takes a core. So each frame is drawn
// into a picture of its own (a render target), with a fence behind it; the
// page polls the fence between tasks and, once the drawing is done, copies
// the picture to the canvas, which is quick to draw and to read back. A
// frame asked for while one is being drawn replaces any other waiting, and
// is drawn next. frames.draw(scene, camera) takes the place of
// renderer.render(scene, camera).
export function fencedFrames(renderer) {
  const gl = renderer.getContext();
  // Half floats: the picture is kept linear, as drawn, and made sRGB by the copy.
  const target = new THREE.WebGLRenderTarget(1, 1, { type: THREE.HalfFloatType });
  const copy = new THREE.Scene();
  copy.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), new THREE.MeshBasicMaterial({ map: target.texture, toneMapped: false })));
  const copyCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  const size = new THREE.Vector2();
  let fence = null, next = null;
  function start(scene, camera) {
    renderer.getDrawingBufferSize(size);
    if (target.width !== size.x || target.height !== size.y) target.setSize(size.x, size.y);
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    renderer.setRenderTarget(null);
    fence = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl.flush();
    setTimeout(poll, 4);
  }
  function poll() {
    if (gl.getSyncParameter(fence, gl.SYNC_STATUS) !== gl.SIGNALED) { setTimeout(poll, 4); return; }
    gl.deleteSync(fence);
    fence = null;
    renderer.render(copy, copyCamera);
    frames.drawn += 1;
    if (next) { const [scene, camera] = next; next = null; start(scene, camera); }
  }
  const frames = {
    drawn: 0,  // frames on the canvas (the tests wait for one)
    draw(scene, camera) { if (fence) next = [scene, camera]; else start(scene, camera); },
  };
  return frames;
}

// Draws `data` (the JSON block report.cpp writes) in the page's elements
// (#canvas, #layers, #parameters, #statistics, ...: template.html);
// arrayBytes(id) gives array id's bytes (a Uint8Array). Returns the view's
// handle (window.reconReport in the report; the tests and
// scripts/phase-pictures use it). The report calls it once (report.js); the
// web page (web/webapp/page.js) after each stage of a run, disposing of the
// previous view, with `deferFirstFrame` (the first frame is drawn in a task
// of its own, an animation frame, rather than waited for here, so that no
// task of the page's main thread holds both) and its own `renderer`
// (makeRenderer, warmUp: kept from view to view, its shaders compiled once),
// drawing through `frames` (fencedFrames) when given.
export function showReport(data, arrayBytes, { deferFirstFrame = false, renderer: sharedRenderer = null, frames = null } = {}) {
  // A section filled by an earlier view keeps only its heading.
  for (const id of ['layers', 'lab', 'parameters', 'statistics'])
    for (const child of [...document.getElementById(id).children]) if (child.tagName !== 'H2') child.remove();
  const timings = { start: performance.now() };  // the viewer's start and first frame (the load test prints both)

  // An array is given by its number.
  const bytes = arrayBytes;
  const f32 = (b64) => { const b = bytes(b64); return new Float32Array(b.buffer, b.byteOffset, b.byteLength / 4); };
  const u32 = (b64) => { const b = bytes(b64); return new Uint32Array(b.buffer, b.byteOffset, b.byteLength / 4); };
  const u8 = (b64) => bytes(b64);
  // Normals are stored as int8 times 127.
  const normals8 = (b64) => { const b = bytes(b64); return Float32Array.from(new Int8Array(b.buffer, b.byteOffset, b.byteLength), (v) => v / 127); };
  // The input's colours are stored as r g b bytes, sRGB as in the file; three.js
  // blends vertex colours as linear values and encodes the picture as sRGB.
  const srgbToLinear = Float32Array.from({ length: 256 }, (_, v) => new THREE.Color().setRGB(v / 255, 0, 0, THREE.SRGBColorSpace).r);
  const colours8 = (b64) => Float32Array.from(bytes(b64), (v) => srgbToLinear[v]);

  const count = (n) => Math.round(n).toLocaleString('en-US');
  // "every 2nd", "every 11th", "every 23rd".
  function every(n) {
    const suffix = n % 100 >= 11 && n % 100 <= 13 ? 'th' : ['th', 'st', 'nd', 'rd'][n % 10] ?? 'th';
    return `every ${count(n)}${suffix}`;
  }
  function formatNumber(v) {
    if (typeof v !== 'number') return String(v);
    if (Number.isInteger(v)) return count(v);
    return String(Number(v.toPrecision(4)));
  }

  // ---- colours

  const palette = [0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728, 0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f, 0xbcbd22, 0x17becf]
    .map((hex) => new THREE.Color(hex));
  // Planarity: blue (flat) through green and yellow to red (surface variation planarityFull and above).
  const rampStops = [[0.0, 0x2b59c3], [0.33, 0x2ca02c], [0.66, 0xe8c21a], [1.0, 0xd62728]].map(([t, c]) => [t, new THREE.Color(c)]);
  const planarityFull = 0.05;
  const rampCss = `linear-gradient(90deg,${rampStops.map(([t, c]) => '#' + c.getHexString() + ' ' + 100 * t + '%').join(',')})`;
  function ramp(t, out) {
    t = Math.min(1, Math.max(0, t));
    for (let s = 1; s < rampStops.length; ++s) {
      if (t <= rampStops[s][0]) {
        const [t0, c0] = rampStops[s - 1];
        const [t1, c1] = rampStops[s];
        return out.copy(c0).lerp(c1, (t - t0) / (t1 - t0));
      }
    }
    return out.copy(rampStops[rampStops.length - 1][1]);
  }
  const css = (hex) => '#' + new THREE.Color(hex).getHexString();

  // ---- scene

  const canvas = document.getElementById('canvas');
  const renderer = sharedRenderer ?? makeRenderer(canvas, ((data.refinement ?? data.mesh)?.drawn ?? 0) <= 200000);
  const scene = new THREE.Scene();
  const diagonal = data.diagonal > 0 ? data.diagonal : 1;
  // The sphere around everything drawn, which the first view frames (framing.js).
  const sphere = data.drawn_box ? boundingSphere(data.drawn_box.min, data.drawn_box.max) : { centre: [0, 0, 0], radius: diagonal / 2 };
  const sphereCentre = new THREE.Vector3(...sphere.centre);
  const camera = new THREE.PerspectiveCamera(40, 1, diagonal * 1e-3, diagonal * 20);
  camera.up.set(0, 0, 1);  // Hoppe's orientation starts from the largest z: z is up
  scene.add(camera);
  const controls = new OrbitControls(camera, canvas);
  controls.screenSpacePanning = true;

  // Frames are drawn on demand, at most one per animation frame, and none
  // before the page is set up (a frame of a large mesh is costly when the
  // browser draws in software).
  let started = false, renderQueued = false;
  function render() {
    if (frames) frames.draw(scene, camera);
    else renderer.render(scene, camera);
  }
  function requestRender() {
    if (!started || renderQueued) return;
    renderQueued = true;
    requestAnimationFrame(() => { renderQueued = false; render(); });
  }
  // The clipping planes follow the camera, so that nothing drawn is cut off
  // however far it orbits, pans or zooms.
  function fitClipPlanes() {
    const { near, far } = clipPlanes(camera.position.distanceTo(sphereCentre), sphere.radius);
    if (near === camera.near && far === camera.far) return;
    camera.near = near;
    camera.far = far;
    camera.updateProjectionMatrix();
  }
  controls.addEventListener('change', () => { fitClipPlanes(); requestRender(); });

  // The whole model, from outside, for the view's present shape.
  function resetView() {
    const view = frameSphere(sphere, { fovY: camera.fov, aspect: camera.aspect });
    camera.position.set(...view.position);
    controls.target.set(...view.target);
    controls.update();
    fitClipPlanes();
    requestRender();
  }

  const view = document.getElementById('view');
  function resize() {
    const w = Math.max(1, view.clientWidth), h = Math.max(1, view.clientHeight);
    const size = renderer.getSize(new THREE.Vector2());
    if (size.x === w && size.y === h) return;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    requestRender();
  }
  const resizeObserver = new ResizeObserver(resize);
  resizeObserver.observe(view);

  function lineSegments(positions, colour, opacity = 1) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    const material = new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity });
    return new THREE.LineSegments(geometry, material);
  }
  function colouredSegments(positions, colours3) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours3, 3));
    return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  }
  function points(positions, colours3, size) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours3, 3));
    return new THREE.Points(geometry, new THREE.PointsMaterial({ size, sizeAttenuation: false, vertexColors: true }));
  }
  // Segments from each origin along its normal (length len); `keep(i)` filters.
  function normalSegments(origin, normal, len, keep) {
    const n = origin.length / 3;
    const out = new Float32Array(6 * n);
    let m = 0;
    for (let i = 0; i < n; ++i) {
      if (!keep(i)) continue;
      for (let c = 0; c < 3; ++c) {
        out[6 * m + c] = origin[3 * i + c];
        out[6 * m + 3 + c] = origin[3 * i + c] + len * normal[3 * i + c];
      }
      ++m;
    }
    return { positions: out.subarray(0, 6 * m), kept: m };
  }

  // ---- the layers

  const P = data.points;
  const drawnPoints = P.drawn;
  const normalLength = data.rho > 0 ? data.rho : diagonal / 100;  // one sample spacing
  const subsample = (drawn, total, what, stride) =>
    drawn >= total ? `all ${count(total)} ${what}` :
      `${count(drawn)} of ${count(total)} ${what} drawn (${every(stride)})`;

  // A layer's geometry is built the first time it is shown, so that a large
  // report opens as fast as its default layers allow. Its toggle goes into
  // the element `container` (the layers' section, or the lab panel's). A
  // layer that can be coloured in more than one way has `colourings`, each
  // { id, label, legend }; the first is shown first, and build(colouring)
  // draws the one chosen.
  const layers = [];
  function addLayer(id, label, build, note, legend, visible, container = 'layers', colourings = null) {
    layers.push({ id, label, build, available: build !== null, visible: false, object: null, note, legend,
      defaultVisible: visible && build !== null, container, colourings, colouring: colourings?.[0].id ?? null });
  }
  function layerObject(layer) {
    if (layer.object === null) {
      layer.object = layer.build(layer.colouring);
      scene.add(layer.object);
    }
    return layer.object;
  }
  const layerLegend = (layer) => layer.colourings?.find((c) => c.id === layer.colouring).legend ?? layer.legend;

  // 1. input points by component, or in their own colours when the run had them
  const byComponent = 'coloured by component (piece of the data)';
  const inputColours = 'in the input\'s colours';
  addLayer('points', '1. Input points', (colouring) => {
    if (colouring === 'input') return points(f32(P.position), colours8(P.color), 2);
    const component = u32(P.component);
    const c = new Float32Array(3 * drawnPoints);
    for (let i = 0; i < drawnPoints; ++i) palette[component[i] % palette.length].toArray(c, 3 * i);
    return points(f32(P.position), c, 2);
  }, subsample(drawnPoints, P.total, 'points', P.stride) + `; ${count(P.components)} component${P.components === 1 ? '' : 's'}`,
  byComponent, !data.mesh, 'layers',
  P.color === undefined ? null : [{ id: 'input', label: 'their colours', legend: inputColours },
    { id: 'component', label: 'component', legend: byComponent }]);

  // 2. kd-tree cells
  const K = data.kdtree;
  const kdBoxes = f32(K.boxes), kdLevel = u8(K.level);
  let kdDepth = Math.min(4, K.drawn_depth);
  function kdSegments(depth) {
    const out = [];
    for (let b = 0; b < kdLevel.length; ++b) {
      const level = kdLevel[b] & 127, shallowLeaf = kdLevel[b] >= 128;
      if (!(level === depth || (shallowLeaf && level < depth))) continue;
      const lo = kdBoxes.subarray(6 * b, 6 * b + 3), hi = kdBoxes.subarray(6 * b + 3, 6 * b + 6);
      const corner = (i) => [(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]];
      for (const [a, z] of [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]])
        out.push(...corner(a), ...corner(z));
    }
    return new Float32Array(out);
  }
  addLayer('kdtree', '2. kd-tree cells', () => lineSegments(kdSegments(kdDepth), colours.kdtree, 0.7),
    `the tree is ${K.depth} levels deep; the cells of one depth are drawn`, null, false);
  const kdLayer = layers[layers.length - 1];
  function setKdDepth(depth) {
    kdDepth = Math.max(0, Math.min(K.drawn_depth, depth));
    if (kdLayer.object !== null) {
      kdLayer.object.geometry.dispose();
      kdLayer.object.geometry = new THREE.BufferGeometry();
      kdLayer.object.geometry.setAttribute('position', new THREE.BufferAttribute(kdSegments(kdDepth), 3));
    }
    document.getElementById('kd-depth-value').textContent = String(kdDepth);
    requestRender();
  }

  // 3. normals before orientation, by planarity
  let origins = null, noPlane = null;  // decoded when layer 3 or 5 is first shown
  function planeArrays() {
    if (origins === null) { origins = f32(P.origin); noPlane = u8(P.no_plane); }
  }
  addLayer('pca', '3. Tangent planes (unoriented normals)', () => {
    planeArrays();
    const { positions, kept } = normalSegments(origins, normals8(P.pca_normal), normalLength, (i) => !noPlane[i]);
    const planarity = f32(P.planarity);
    const c = new Float32Array(3 * positions.length / 3);
    const colour = new THREE.Color();
    let m = 0;
    for (let i = 0; i < drawnPoints && m < kept; ++i) {
      if (noPlane[i]) continue;
      ramp(planarity[i] / planarityFull, colour);
      colour.toArray(c, 6 * m);
      colour.toArray(c, 6 * m + 3);
      ++m;
    }
    return colouredSegments(positions, c);
  }, 'from each plane origin o_i along n_i (PCA), before orientation',
  `<span class="swatch" style="background:${css(0x2b59c3)}"></span>flat <span class="ramp" style="background:${rampCss}"></span> surface variation ≥ ${planarityFull}`,
  false);

  // 4. Riemannian graph and spanning tree
  // A graph as drawn (layer 4's, or one of the lab's: the same keys): its
  // edges faint, its spanning tree over them, the tree edges where the
  // orientation turned in red.
  function graphGroup(G) {
    const group = new THREE.Group();
    group.add(lineSegments(f32(G.segments), colours.graph, 0.4));
    const tree = f32(G.tree_segments), flip = u8(G.tree_flip);
    const kept = [], flipped = [];
    for (let e = 0; e < flip.length; ++e) (flip[e] ? flipped : kept).push(...tree.subarray(6 * e, 6 * e + 6));
    group.add(lineSegments(new Float32Array(kept), colours.tree));
    group.add(lineSegments(new Float32Array(flipped), colours.flip));
    return group;
  }
  const graphNote = (G) => (G.vertex_stride === 1 ? `all ${count(G.edges_total)} graph edges; ` :
    `${count(G.drawn)} of ${count(G.edges_total)} graph edges drawn (those of ${every(G.vertex_stride)} point); `) +
    'the tree edge of each drawn point; ' +
    `orientation reversed across ${count(G.flips_total)} of ${count(G.tree_total)} tree edges`;
  const graphLegend = `<span class="swatch" style="background:${css(colours.graph)}"></span>graph ` +
    `<span class="swatch" style="background:${css(colours.tree)}"></span>spanning tree ` +
    `<span class="swatch" style="background:${css(colours.flip)}"></span>flip`;
  const G = data.graph;
  addLayer('graph', '4. Riemannian graph and spanning tree', G ? () => graphGroup(G) : null,
    G ? graphNote(G) : 'not available: phase II was skipped (the input normals were used)', graphLegend, false);

  // 5. oriented normals, coloured by direction
  addLayer('normals', '5. Oriented normals', P.normal === undefined ? null : () => {
    planeArrays();
    const normal = normals8(P.normal);
    const { positions, kept } = normalSegments(origins, normal, normalLength, (i) => !noPlane[i]);
    const c = new Float32Array(positions.length);
    let m = 0;
    for (let i = 0; i < drawnPoints && m < kept; ++i) {
      if (noPlane[i]) continue;
      for (let k = 0; k < 3; ++k) c[6 * m + k] = c[6 * m + 3 + k] = 0.5 + 0.5 * normal[3 * i + k];
      ++m;
    }
    return colouredSegments(positions, c);
  }, P.normal === undefined ? 'not yet: phase II is running' :
    'coloured by direction (x, y, z as red, green, blue): consistent normals change colour smoothly', null, !data.mesh);

  // 6. signed distance at the lattice corners
  const C = data.corners;
  addLayer('distance', '6. Signed distance at lattice corners', C ? () => {
    const value = f32(C.value);
    const c = new Float32Array(3 * value.length);
    const outside = new THREE.Color(colours.outside), inside = new THREE.Color(colours.inside),
      undef = new THREE.Color(colours.undefined);
    for (let i = 0; i < value.length; ++i) (Number.isNaN(value[i]) ? undef : value[i] > 0 ? outside : inside).toArray(c, 3 * i);
    return points(f32(C.position), c, 3);
  } : null, C ? `${subsample(C.drawn, C.total, 'evaluated corners', C.stride)}; ${count(C.undefined_total)} undefined; cell ${formatNumber(C.cell)}` :
    'not available in this run',
  `<span class="swatch" style="background:${css(colours.outside)}"></span>f &gt; 0 outside <span class="swatch" style="background:${css(colours.inside)}"></span>f &lt; 0 inside <span class="swatch" style="background:${css(colours.undefined)}"></span>undefined`,
  false);

  // 7. and 8. the meshes and their boundaries
  // A mesh layer's object: the shaded triangles and the boundary edges;
  // `vertexColours` (3 per drawn vertex) colours the outside.
  function meshGroup(mesh, vertexColours = null) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(f32(mesh.vertices), 3));
    geometry.setIndex(new THREE.BufferAttribute(u32(mesh.triangles), 1));
    if (vertexColours) geometry.setAttribute('color', new THREE.BufferAttribute(vertexColours, 3));
    geometry.computeVertexNormals();
    const group = new THREE.Group();
    group.add(new THREE.Mesh(geometry, meshMaterial(vertexColours !== null)));
    group.add(lineSegments(f32(mesh.boundary), colours.boundary));
    return group;
  }
  const meshNote = (mesh) => `${subsample(mesh.drawn, mesh.triangles_total, 'triangles', mesh.stride)}; ` +
    (mesh.boundary_stride > 1 ? subsample(mesh.boundary_drawn, mesh.boundary_total, 'boundary edges', mesh.boundary_stride) :
      `${count(mesh.boundary_total)} boundary edges`);
  const insideAndBoundary = `<span class="swatch" style="background:${css(colours.meshBack)}"></span>inside (seen from behind) ` +
    `<span class="swatch" style="background:${css(colours.boundary)}"></span>boundary edge`;

  const M = data.mesh, R = data.refinement;
  // A mesh with colours (the final one of a run whose input had them) is drawn in them.
  addLayer('mesh', R ? '7. Mesh of phase IV (the 1992 surface)' : '7. Mesh',
    M ? () => meshGroup(M, M.colors === undefined ? null : colours8(M.colors)) : null,
    M ? meshNote(M) : 'not available: this run made no mesh',
    (M?.colors === undefined ? `<span class="swatch" style="background:${css(colours.meshFront)}"></span>outside ` :
      `outside ${inputColours} `) + insideAndBoundary,
    M !== undefined && !R);

  // 8. the refined mesh, coloured by each vertex's distance to the 1992 surface
  // (layer 7's mesh), on the ramp of layer 3 from 0 to the distance scale.
  const distanceScale = R ? (R.distance.scale > 0 ? R.distance.scale : R.distance.max > 0 ? R.distance.max : 1) : 1;
  const distanceLegend = R ? `distance to the 1992 surface: 0 <span class="ramp" style="background:${rampCss}"></span> ≥ ${formatNumber(distanceScale)}` +
    (C?.cell > 0 ? ` (${formatNumber(distanceScale / C.cell)} cell)` : '') + `<br>${insideAndBoundary}` : null;
  addLayer('refinement', '8. Refined mesh (phase V)', R ? (colouring) => {
    if (colouring === 'input') return meshGroup(R, colours8(R.colors));
    const distance = f32(R.distance.value);
    const c = new Float32Array(3 * distance.length);
    const colour = new THREE.Color();
    for (let i = 0; i < distance.length; ++i) ramp(distance[i] / distanceScale, colour).toArray(c, 3 * i);
    return meshGroup(R, c);
  } : null, R ? `${meshNote(R)}; its vertices lie ${formatNumber(R.distance.mean)} from the 1992 surface on average, ` +
    `${formatNumber(R.distance.max)} at most` : M ? 'not available: phase V runs in the refined method only (this run: hoppe92)'
    : 'not available: this run made no mesh',
  distanceLegend, true, 'layers',
  R?.colors === undefined ? null : [{ id: 'input', label: 'the input\'s colours', legend: `${inputColours} ${insideAndBoundary}` },
    { id: 'distance', label: 'distance to the 1992 surface', legend: distanceLegend }]);

  // The lab's orientation graphs (data.lab.graphs), a layer each: the graph
  // as layer 4 draws it, and layer 1's points coloured by the piece of this
  // graph they lie in.
  const lab = data.lab;
  for (const L of lab?.graphs ?? []) {
    addLayer(`lab-${L.name}`, `${L.name} graph`, () => {
      const group = graphGroup(L);
      const component = u32(L.component);
      const c = new Float32Array(3 * component.length);
      for (let i = 0; i < component.length; ++i) palette[component[i] % palette.length].toArray(c, 3 * i);
      group.add(points(f32(P.position), c, 3));
      return group;
    }, `${count(L.components)} piece${L.components === 1 ? '' : 's'}; ${count(L.flips)} normals flipped; ${graphNote(L)}`,
    `${graphLegend}<br>points coloured by piece`, false, 'lab-layers');
  }

  // ---- the panel

  function setVisible(id, on) {
    const layer = layers.find((l) => l.id === id);
    if (!layer || !layer.available) return false;
    layer.visible = on;
    if (on || layer.object !== null) layerObject(layer).visible = on;
    document.getElementById('layer-' + id).checked = on;
    requestRender();
    return true;
  }

  // Draws a layer in another of its colourings (rebuilt when next shown).
  function setColouring(id, colouring) {
    const layer = layers.find((l) => l.id === id);
    if (!layer?.available || !layer.colourings?.some((c) => c.id === colouring)) return false;
    layer.colouring = colouring;
    if (layer.object !== null) {
      scene.remove(layer.object);
      layer.object.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
      layer.object = null;
      if (layer.visible) layerObject(layer).visible = true;
    }
    document.getElementById('colouring-' + id).value = colouring;
    document.getElementById('legend-' + id).innerHTML = layerLegend(layer);
    requestRender();
    return true;
  }

  if (lab) {
    labPanel(lab, document.getElementById('lab'));
    document.body.classList.add('has-lab');
  }
  for (const layer of layers) {
    const div = document.createElement('div');
    div.className = 'layer';
    const legend = layerLegend(layer);
    div.innerHTML = `<input type="checkbox" id="layer-${layer.id}"${layer.available ? '' : ' disabled'}>` +
      ` <label for="layer-${layer.id}">${layer.label}</label>` +
      `<div class="note" id="note-${layer.id}">${layer.note}</div>` +
      (layer.colourings && layer.available ? `<div class="note">colour by <select id="colouring-${layer.id}">` +
        layer.colourings.map((c) => `<option value="${c.id}">${c.label}</option>`).join('') + '</select></div>' : '') +
      (legend && layer.available ? `<div class="legend" id="legend-${layer.id}">${legend}</div>` : '');
    document.getElementById(layer.container).appendChild(div);
    div.querySelector('input').addEventListener('change', (e) => setVisible(layer.id, e.target.checked));
    div.querySelector('select')?.addEventListener('change', (e) => setColouring(layer.id, e.target.value));
    if (layer.id === 'kdtree') {
      const slider = document.createElement('div');
      slider.className = 'note';
      slider.innerHTML = `depth <input type="range" id="kd-depth" min="0" max="${K.drawn_depth}" value="${kdDepth}">` +
        ` <span id="kd-depth-value">${kdDepth}</span> of ${K.drawn_depth} stored`;
      div.appendChild(slider);
      slider.querySelector('input').addEventListener('input', (e) => setKdDepth(Number(e.target.value)));
    }
  }
  document.getElementById('reset').onclick = resetView;  // (one handler: the web page makes a view per stage)

  // Statistics: the run's --stats JSON as it was written, section by section;
  // each value cell carries its key path and exact value (data-key, data-value).
  const stats = data.stats || {};
  const lookup = (path) => path.split('.').reduce((o, k) => (o && typeof o === 'object' ? o[k] : undefined), stats);
  function valueCell(path, value) {
    const td = document.createElement('td');
    td.className = 'value';
    td.dataset.key = path;
    td.dataset.value = JSON.stringify(value);
    // A list of numbers is a size (the lattice's); a list of objects (the
    // lab's runs) is counted here and shown by its own panel.
    const objects = Array.isArray(value) && value.some((v) => v !== null && typeof v === 'object');
    td.textContent = objects ? `${value.length} entries` : Array.isArray(value) ? value.map(formatNumber).join(' × ') :
      typeof value === 'boolean' ? (value ? 'yes' : 'no') : formatNumber(value);
    return td;
  }
  function row(table, key, cell, section = false) {
    const tr = document.createElement('tr');
    if (section) tr.className = 'section';
    const td = document.createElement('td');
    td.className = 'key';
    td.textContent = key;
    tr.appendChild(td);
    if (cell) tr.appendChild(cell); else td.colSpan = 2;
    table.appendChild(tr);
  }
  function statsTable(object, prefix, table) {
    for (const [key, value] of Object.entries(object)) {
      const path = prefix ? `${prefix}.${key}` : key;
      if (value && typeof value === 'object' && !Array.isArray(value)) {
        row(table, path.replaceAll('_', ' '), null, true);
        statsTable(value, path, table);
      } else {
        row(table, key.replaceAll('_', ' '), valueCell(path, value));
      }
    }
  }
  const statsElement = document.createElement('table');
  statsTable(stats, '', statsElement);
  document.getElementById('statistics').appendChild(statsElement);

  const parameters = [
    ['points', 'input.points'], ['k (neighbours)', 'tangent_planes.k'], ['ρ (sampling density)', 'tangent_planes.rho'],
    ['δ (noise)', 'signed_distance.delta'], ['cell', 'contouring.cell'], ['threads', 'threads'],
  ];
  const parameterTable = document.createElement('table');
  for (const [label, path] of parameters) {
    const value = lookup(path);
    if (value !== undefined) row(parameterTable, label, valueCell(path, value));
  }
  document.getElementById('parameters').appendChild(parameterTable);

  const title = data.title || 'recon report';
  document.getElementById('title').textContent = title;
  document.title = `recon report: ${title}`;
  document.getElementById('version').textContent = data.version ?? '';

  for (const layer of layers) if (layer.defaultVisible) setVisible(layer.id, true);
  resize();
  resetView();
  if (deferFirstFrame) {
    // The shaders compiled in the background first (where the browser can:
    // KHR_parallel_shader_compile), then the frame.
    renderer.compileAsync(scene, camera).catch(() => {}).then(() => { started = true; requestRender(); });
  } else {
    render();
    // Wait for the frame itself (a pixel read waits for the drawing to finish),
    // so that loadMs is the time until the picture is there.
    const gl = renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    started = true;
    timings.rendered = performance.now();
  }

  return {
    ready: true,
    loadMs: performance.now(),
    timings,
    layers: layers.map(({ id, label, available }) => ({ id, label, available })),
    visible: (id) => layers.find((l) => l.id === id)?.visible ?? false,
    // The line segments a layer draws now (0 when it is hidden or not built).
    segments(id) {
      const layer = layers.find((l) => l.id === id);
      let n = 0;
      if (layer?.visible) layer.object.traverse((o) => { if (o.isLineSegments) n += o.geometry.getAttribute('position').count / 2; });
      return n;
    },
    setVisible,
    // A layer's colourings (ids, the first shown first) and the one drawn; null without a choice.
    colourings: (id) => layers.find((l) => l.id === id)?.colourings?.map((c) => c.id) ?? null,
    colouring: (id) => layers.find((l) => l.id === id)?.colouring ?? null,
    setColouring,
    setKdDepth,
    resetView,
    // Moves the camera towards the target: the distance times `factor`.
    zoom(factor) {
      camera.position.sub(controls.target).multiplyScalar(factor).add(controls.target);
      controls.update();
      requestRender();
    },
    // The camera as it is, and the sphere the first view frames (for the tests).
    view: () => ({
      position: camera.position.toArray(), target: controls.target.toArray(), near: camera.near, far: camera.far,
      fov: camera.fov, aspect: camera.aspect, sphere,
    }),
    stats,
    // Frees the view (the web page shows a new run's layers in a new one).
    dispose() {
      resizeObserver.disconnect();
      scene.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
      if (!sharedRenderer) renderer.dispose();
    },
  };
}
