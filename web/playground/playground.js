// The playground page: points edited with the mouse, the recon library
// (recon_playground.js, WebAssembly) run on them after every change, and
// each phase's result drawn on a canvas. Plain script, no modules, so that
// the page also works when opened from the file system.
'use strict';

(function () {
  // Layer ids and stats entries, as laid out by playground.cpp.
  const LAYER = { normals: 0, kdSplits: 1, graphEdges: 2, treeEdges: 3, squares: 4, corners: 5, vertices: 6, curves: 7, stats: 8 };
  const STAT = {
    k: 0, rho: 1, delta: 2, cell: 3, components: 4, secondsPlanes: 5, secondsOrientation: 6, secondsDistance: 7,
    secondsContour: 8, secondsTotal: 9, undefinedSquares: 10, seamSquares: 11, saddleSquares: 12,
    secondsTree: 13, treeWeight: 14, pushes: 15, pops: 16, decreaseKeys: 17, comparisons: 18, finds: 19, unions: 20,
    rounds: 21, graphEdges: 22,
  };

  const canvas = document.getElementById('view');
  const context = canvas.getContext('2d');
  const statusLine = document.getElementById('status');
  const timingLine = document.getElementById('timing');
  const countsLine = document.getElementById('counts');
  // Phase II's choices (ids as playground.cpp numbers them).
  const graphChoice = document.getElementById('graph');
  const treeChoice = document.getElementById('tree');
  graphChoice.addEventListener('change', () => changed());
  treeChoice.addEventListener('change', () => changed());
  const errorLine = document.getElementById('error');

  // The world shown: x in [-2, 2], y in [-1.5, 1.5] (y up), on the canvas's
  // 800 x 600 CSS pixels.
  const view = { xMin: -2, xMax: 2, yMin: -1.5, yMax: 1.5 };
  const cssWidth = canvas.width, cssHeight = canvas.height;
  const ratio = window.devicePixelRatio || 1;
  canvas.width = Math.round(cssWidth * ratio);
  canvas.height = Math.round(cssHeight * ratio);
  canvas.style.width = cssWidth + 'px';
  canvas.style.height = cssHeight + 'px';
  const scale = cssWidth / (view.xMax - view.xMin);
  const toCanvas = (x, y) => [(x - view.xMin) * scale, (view.yMax - y) * scale];
  const toWorld = (cx, cy) => [view.xMin + cx / scale, view.yMax - cy / scale];

  let module = null;
  let points = [];          // [x, y] pairs in world units
  let result = null;        // the layers of the last successful run
  let errorText = '';
  let dirty = true;
  let updateCount = 0;
  const recentMs = [];      // the last update times, for the median shown
  let lastUpdateMs = 0;
  let dragging = -1;

  const sliders = {};
  for (const name of ['k', 'rho', 'delta', 'cell']) sliders[name] = document.getElementById(name);
  const layersShown = {};
  for (const box of document.querySelectorAll('input[data-layer]')) {
    layersShown[box.dataset.layer] = box.checked;
    box.addEventListener('change', () => { layersShown[box.dataset.layer] = box.checked; draw(); });
  }
  for (const name of Object.keys(sliders)) sliders[name].addEventListener('input', () => changed());

  // ------------------------------------------------------------ presets

  // A small seeded generator (the presets are the same on every load).
  function random(seed) {
    let s = seed >>> 0;
    return () => {
      s = (s + 0x6d2b79f5) >>> 0;
      let t = s;
      t = Math.imul(t ^ (t >>> 15), t | 1);
      t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
  }
  function gaussian(next) {
    const u = Math.max(next(), 1e-12), v = next();
    return Math.sqrt(-2 * Math.log(u)) * Math.cos(2 * Math.PI * v);
  }
  // n points on a closed curve c(t), t in [0, 1): one in each of n equal
  // parameter intervals.
  function sample(curve, n, next, from = 0, to = 1) {
    const out = [];
    for (let i = 0; i < n; ++i) out.push(curve(from + (to - from) * (i + next()) / n));
    return out;
  }
  const circle = (cx, cy, r) => (t) => [cx + r * Math.cos(2 * Math.PI * t), cy + r * Math.sin(2 * Math.PI * t)];

  function curve1Points() {
    const raw = [];
    for (const line of (window.reconCurve1Text || '').split('\n')) {
      const f = line.trim().split(/\s+/);
      if (f[0] === 'p' && f.length === 4) raw.push([Number(f[2]), Number(f[3])]);
    }
    if (raw.length === 0) return [];
    // Centred and scaled to fill most of the view.
    const xs = raw.map((p) => p[0]), ys = raw.map((p) => p[1]);
    const cx = (Math.min(...xs) + Math.max(...xs)) / 2, cy = (Math.min(...ys) + Math.max(...ys)) / 2;
    const size = Math.max(Math.max(...xs) - Math.min(...xs), (Math.max(...ys) - Math.min(...ys)) * 4 / 3);
    const s = 3.2 / size;
    return raw.map(([x, y]) => [(x - cx) * s, (y - cy) * s]);
  }

  const presets = {
    'circle': () => sample(circle(0, 0, 1), 60, random(1)),
    'two-circles': () => sample(circle(-0.95, 0.1, 0.65), 45, random(2)).concat(sample(circle(1.05, -0.15, 0.5), 35, random(3))),
    'spiral': () => {
      // An open Archimedean spiral r = a + b theta, sampled evenly in arc length.
      const a = 0.12, b = 0.085, turns = 2.6, out = [], next = random(4);
      let theta = 0.4;
      const end = 2 * Math.PI * turns, step = 0.045;
      while (theta < end) {
        const r = a + b * theta;
        out.push([r * Math.cos(theta) + 0.01 * (next() - 0.5), r * Math.sin(theta) + 0.01 * (next() - 0.5)]);
        theta += step / Math.hypot(r, b);
      }
      return out;
    },
    'noisy-ellipse': () => {
      const next = random(5);
      return sample((t) => [1.6 * Math.cos(2 * Math.PI * t), 0.95 * Math.sin(2 * Math.PI * t)], 300, next)
        .map(([x, y]) => [x + 0.012 * gaussian(next), y + 0.012 * gaussian(next)]);
    },
    'curve1': curve1Points,
    'clear': () => [],
  };
  for (const button of document.querySelectorAll('button[data-preset]'))
    button.addEventListener('click', () => { points = presets[button.dataset.preset](); changed(); });

  // ------------------------------------------------------------ editing

  function pointerPosition(event) {
    const box = canvas.getBoundingClientRect();
    return [event.clientX - box.left, event.clientY - box.top];
  }
  // The point within 8 pixels of (cx, cy), or -1.
  function pointNear(cx, cy) {
    let best = -1, bestDistance = 8;
    points.forEach(([x, y], i) => {
      const [px, py] = toCanvas(x, y);
      const d = Math.hypot(px - cx, py - cy);
      if (d <= bestDistance) { best = i; bestDistance = d; }
    });
    return best;
  }
  canvas.addEventListener('pointerdown', (event) => {
    const [cx, cy] = pointerPosition(event);
    const near = pointNear(cx, cy);
    if (event.shiftKey) {
      if (near >= 0) { points.splice(near, 1); changed(); }
      return;
    }
    if (near >= 0) {
      dragging = near;
    } else {
      points.push(toWorld(cx, cy));
      dragging = points.length - 1;
      changed();
    }
    canvas.setPointerCapture(event.pointerId);
  });
  canvas.addEventListener('pointermove', (event) => {
    if (dragging < 0) return;
    points[dragging] = toWorld(...pointerPosition(event));
    changed();
  });
  const stopDragging = () => { dragging = -1; };
  canvas.addEventListener('pointerup', stopDragging);
  canvas.addEventListener('pointercancel', stopDragging);

  // ------------------------------------------------------------ running recon

  function changed() {
    dirty = true;
    requestAnimationFrame(frame);
  }
  function frame() {
    if (!dirty || !module) return;
    dirty = false;
    update();
    draw();
  }

  function layer(id) {
    const pointer = module._recon_layer(id), size = module._recon_layer_size(id);
    return size > 0 ? new Float64Array(module.HEAPF64.buffer, pointer, size).slice() : new Float64Array(0);
  }

  function update() {
    const started = performance.now();
    result = null;
    errorText = '';
    const n = points.length;
    if (n === 0) {
      errorText = 'Click to add points.';
    } else {
      const memory = module._malloc(16 * n);
      const flat = new Float64Array(2 * n);
      points.forEach(([x, y], i) => { flat[2 * i] = x; flat[2 * i + 1] = y; });
      module.HEAPF64.set(flat, memory / 8);
      const status = module._recon_run(memory, n, Number(sliders.k.value), Number(sliders.rho.value),
                                       Number(sliders.delta.value), Number(sliders.cell.value),
                                       Number(graphChoice.value), Number(treeChoice.value));
      module._free(memory);
      if (status === 0) {
        result = {};
        for (const [name, id] of Object.entries(LAYER)) result[name] = layer(id);
      } else {
        errorText = module.UTF8ToString(module._recon_error()).replace('(lower --k)', '(add points or lower k)');
      }
    }
    lastUpdateMs = performance.now() - started;
    recentMs.push(lastUpdateMs);
    if (recentMs.length > 15) recentMs.shift();
    ++updateCount;
    report();
  }

  function curveList() {
    if (!result) return [];
    const list = [];
    for (let c = 0; c < result.curves.length; c += 3)
      list.push({ first: result.curves[c], count: result.curves[c + 1], closed: result.curves[c + 2] === 1 });
    return list;
  }

  const format = (v) => (Math.abs(v) >= 0.01 || v === 0 ? v.toFixed(3) : v.toExponential(2));

  function report() {
    const s = result ? result.stats : null;
    for (const [name, stat] of [['rho', STAT.rho], ['delta', STAT.delta], ['cell', STAT.cell]]) {
      const given = Number(sliders[name].value);
      document.getElementById(name + '-value').textContent =
        given > 0 ? format(given) : s ? format(s[stat]) + ' (est.)' : 'estimated';
    }
    document.getElementById('k-value').textContent = sliders.k.value;
    const curves = curveList();
    const closed = curves.filter((c) => c.closed).length;
    statusLine.textContent = points.length + ' points' + (s
      ? ' · ' + s[STAT.components] + (s[STAT.components] === 1 ? ' piece' : ' pieces') + ' · ' + curves.length +
        (curves.length === 1 ? ' curve' : ' curves') + ' (' + closed + ' closed, ' + (curves.length - closed) + ' open)' +
        ' · ' + s[STAT.undefinedSquares] + ' undefined, ' + s[STAT.seamSquares] + ' seam, ' + s[STAT.saddleSquares] +
        ' saddle squares'
      : '');
    const sorted = recentMs.slice().sort((a, b) => a - b);
    const median = sorted[Math.floor(sorted.length / 2)];
    timingLine.textContent = 'update ' + lastUpdateMs.toFixed(1) + ' ms for ' + points.length + ' points (median of last ' +
      sorted.length + ': ' + median.toFixed(1) + ' ms)' + (s
      ? '; phases I ' + (1e3 * s[STAT.secondsPlanes]).toFixed(1) + ', II ' + (1e3 * s[STAT.secondsOrientation]).toFixed(1) +
        ', III ' + (1e3 * s[STAT.secondsDistance]).toFixed(1) + ', IV ' + (1e3 * s[STAT.secondsContour]).toFixed(1) + ' ms'
      : '');
    countsLine.textContent = s ? treeCounts(s) : '';
    errorLine.textContent = errorText;
  }

  // What the chosen spanning-tree algorithm did on the chosen graph.
  function treeCounts(s) {
    const parts = [['pushes', STAT.pushes], ['pops', STAT.pops], ['decrease-keys', STAT.decreaseKeys],
      ['comparisons', STAT.comparisons], ['finds', STAT.finds], ['unions', STAT.unions], ['rounds', STAT.rounds]]
      .filter(([, id]) => s[id] > 0).map(([name, id]) => s[id] + ' ' + name);
    return treeChoice.selectedOptions[0].textContent + ' on the ' + graphChoice.selectedOptions[0].textContent +
      ' graph (' + s[STAT.graphEdges] + ' edges): ' + (1e3 * s[STAT.secondsTree]).toFixed(2) + ' ms, tree weight ' +
      format(s[STAT.treeWeight]) + (parts.length ? '; ' + parts.join(', ') : '');
  }

  // ------------------------------------------------------------ drawing

  function line(x0, y0, x1, y1) {
    const [a, b] = toCanvas(x0, y0), [c, d] = toCanvas(x1, y1);
    context.moveTo(a, b);
    context.lineTo(c, d);
  }

  function draw() {
    context.setTransform(ratio, 0, 0, ratio, 0, 0);
    context.clearRect(0, 0, cssWidth, cssHeight);
    if (result && layersShown.grid) {
      const cell = result.stats[STAT.cell] * scale;
      const q = result.squares;
      for (let i = 0; i < q.length; i += 4) {
        const [x, y] = toCanvas(q[i], q[i + 1]);
        if (q[i + 3] === 1) {
          context.fillStyle = q[i + 2] < 0 ? 'rgba(70, 120, 220, 0.22)' : 'rgba(235, 150, 50, 0.16)';
          context.fillRect(x, y - cell, cell, cell);
        } else {
          context.fillStyle = 'rgba(120, 120, 120, 0.18)';
          context.fillRect(x, y - cell, cell, cell);
          context.strokeStyle = 'rgba(90, 90, 90, 0.5)';
          context.lineWidth = 0.7;
          context.beginPath();
          context.moveTo(x, y - cell); context.lineTo(x + cell, y);
          context.moveTo(x + cell, y - cell); context.lineTo(x, y);
          context.stroke();
        }
      }
      if (cell >= 6) {
        const c = result.corners;
        for (let i = 0; i < c.length; i += 4) {
          const [x, y] = toCanvas(c[i], c[i + 1]);
          context.fillStyle = c[i + 3] !== 1 ? '#888' : c[i + 2] < 0 ? '#2f5fb8' : '#d08020';
          context.fillRect(x - 1.2, y - 1.2, 2.4, 2.4);
        }
      }
    }
    if (result && layersShown.kdtree) {
      const s = result.kdSplits;
      for (let i = 0; i < s.length; i += 5) {
        context.strokeStyle = 'rgba(40, 140, 60, 0.8)';
        context.lineWidth = Math.max(0.5, 2.2 - 0.3 * s[i + 4]);
        context.beginPath();
        line(s[i], s[i + 1], s[i + 2], s[i + 3]);
        context.stroke();
      }
    }
    const edges = (list, style, width) => {
      context.strokeStyle = style;
      context.lineWidth = width;
      context.beginPath();
      for (let i = 0; i < list.length; i += 2) {
        const a = points[list[i]], b = points[list[i + 1]];
        if (a && b) line(a[0], a[1], b[0], b[1]);
      }
      context.stroke();
    };
    if (result && layersShown.graph) edges(result.graphEdges, 'rgba(150, 150, 150, 0.6)', 0.8);
    if (result && layersShown.tree) edges(result.treeEdges, 'rgba(123, 63, 160, 0.85)', 1.6);
    if (result && layersShown.normals) {
      const n = result.normals, length = 0.1;
      context.strokeStyle = '#2f6fb8';
      context.lineWidth = 1.2;
      context.beginPath();
      for (let i = 0; i < points.length && 2 * i + 1 < n.length; ++i)
        line(points[i][0], points[i][1], points[i][0] + length * n[2 * i], points[i][1] + length * n[2 * i + 1]);
      context.stroke();
    }
    if (result && layersShown.curve) {
      const v = result.vertices;
      context.strokeStyle = '#d22';
      context.lineWidth = 2.4;
      context.lineJoin = 'round';
      for (const curve of curveList()) {
        context.beginPath();
        for (let j = 0; j < curve.count; ++j) {
          const [x, y] = toCanvas(v[2 * (curve.first + j)], v[2 * (curve.first + j) + 1]);
          if (j === 0) context.moveTo(x, y); else context.lineTo(x, y);
        }
        if (curve.closed) context.closePath();
        context.stroke();
        if (!curve.closed && curve.count > 0) {  // open ends marked
          context.fillStyle = '#d22';
          for (const j of [0, curve.count - 1]) {
            const [x, y] = toCanvas(v[2 * (curve.first + j)], v[2 * (curve.first + j) + 1]);
            context.fillRect(x - 3, y - 3, 6, 6);
          }
        }
      }
    }
    if (layersShown.points) {
      context.fillStyle = '#222';
      for (const [x, y] of points) {
        const [cx, cy] = toCanvas(x, y);
        context.beginPath();
        context.arc(cx, cy, 3.2, 0, 2 * Math.PI);
        context.fill();
      }
    }
  }

  // ------------------------------------------------------------ state hook for tests

  // Read-only: every call returns a fresh copy.
  Object.defineProperty(window, 'reconPlayground', {
    value: Object.freeze({
      state() {
        const curves = curveList();
        return {
          ready: module !== null,
          points: points.length,
          curves: curves.length,
          closed: curves.map((c) => c.closed),
          vertexCounts: curves.map((c) => c.count),
          error: errorText,
          k: result ? result.stats[STAT.k] : null,
          rho: result ? result.stats[STAT.rho] : null,
          delta: result ? result.stats[STAT.delta] : null,
          cell: result ? result.stats[STAT.cell] : null,
          graph: graphChoice.selectedOptions[0].textContent,
          tree: treeChoice.selectedOptions[0].textContent,
          components: result ? result.stats[STAT.components] : null,
          graphEdges: result ? result.stats[STAT.graphEdges] : null,
          treeEdges: result ? result.treeEdges.length / 2 : null,
          treeWeight: result ? result.stats[STAT.treeWeight] : null,
          counts: result ? { pushes: result.stats[STAT.pushes], pops: result.stats[STAT.pops],
            decreaseKeys: result.stats[STAT.decreaseKeys], comparisons: result.stats[STAT.comparisons],
            finds: result.stats[STAT.finds], unions: result.stats[STAT.unions], rounds: result.stats[STAT.rounds] } : null,
          countsText: countsLine.textContent,
          lastUpdateMs,
          updateCount,
          pending: dirty,  // an update is scheduled for the next frame
        };
      },
      // Where on the page (CSS pixels, as mouse events use) a world point is.
      worldToPage(x, y) {
        const box = canvas.getBoundingClientRect();
        const [cx, cy] = toCanvas(x, y);
        return { x: box.left + cx, y: box.top + cy };
      },
    }),
    writable: false,
  });

  window.createReconModule().then((instance) => {
    module = instance;
    points = presets['two-circles']();
    changed();
  });
})();
