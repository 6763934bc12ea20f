// The web page's script (index.html): input, parameters, progress and
// downloads; the reconstruction itself runs in a Web Worker (worker.js, with
// the library compiled to WebAssembly: webapp.cpp), and each stage's layers
// are drawn by the report's viewer (web/report/viewer.js), the same viewer
// as `recon reconstruct --report`. build.mjs bundles this file with the
// viewer and three.js, and inlines the worker's source (workerSource), so
// the page is one file that works from file:// with no network.
//
// For the tests (web/tests/webapp.test.mjs): document.body.dataset.state is
// idle, running, done or error; window.recon holds the last run's --stats
// JSON (stats), the input's description (input), how often each phase ran
// (runs), the views drawn (views), the error line (error), the viewer's
// handle (viewer), the frames drawn (frames.drawn) and how Cancel stops a
// run (cancels: 'at the next interruption point' or 'by ending the worker')
// and the workers started (workers).
import { fencedFrames, makeRenderer, showReport, warmUp } from '../report/viewer.js';

/* global workerSource */
const $ = (id) => document.getElementById(id);
const recon = { stats: null, input: null, error: '', viewer: null, runs: {}, lines: [], views: [] };
window.recon = recon;

// The phases as reconstruct() names them (its on_phase), with the terminal's numbering.
const phaseNames = {
  'tangent planes': 'phase I: tangent planes', orientation: 'phase II: orientation',
  'signed distance': 'phase III: signed distance', contouring: 'phase IV: contouring',
  refinement: 'phase V: refinement', simplification: 'phase VI: simplification', colours: 'colours',
};

let worker = null;
let workerHasInput = false;  // the worker holds the cloud (a fresh worker does not)
let source = null;           // { file } or { sample, points }: what to (re)load
let held = null;             // the parameters of the run whose phases I-II the worker holds
let pending = null;          // resolves the worker's answer to a request
// Cancel's flag, shared with the worker, where the page may share memory
// (window.crossOriginIsolated: served with COOP and COEP headers). From
// file:// it may not, and Cancel ends the worker instead (see cancel()).
let cancelFlag = null;

function setState(state) {
  document.body.dataset.state = state;
  $('go').disabled = state === 'running' || source === null;
  $('cancel').disabled = state !== 'running';
  for (const b of document.querySelectorAll('#downloads button')) b.disabled = state !== 'done';
}

function showError(message) {
  recon.error = message;
  $('error').textContent = message;
  setState('error');
}

// ---- the worker

function startWorker() {
  recon.workers = (recon.workers ?? 0) + 1;
  const url = URL.createObjectURL(new Blob([workerSource], { type: 'text/javascript' }));
  worker = new Worker(url);
  URL.revokeObjectURL(url);
  workerHasInput = false;
  worker.onmessage = (e) => onWorkerMessage(e.data);
  worker.onerror = (e) => { showError(`the page's worker failed: ${e.message}`); e.preventDefault(); };
  // index.html#max-memory=MB lowers the memory a run may use (2,500 MB by default).
  const limit = /max-memory=(\d+)/.exec(location.hash);
  if (limit) worker.postMessage({ type: 'limit', bytes: Number(limit[1]) * 1e6 });
  if (window.crossOriginIsolated && typeof SharedArrayBuffer === 'function') {
    cancelFlag = new Int32Array(new SharedArrayBuffer(4));
    worker.postMessage({ type: 'cancel-flag', buffer: cancelFlag.buffer });
  }
  recon.cancels = cancelFlag ? 'at the next interruption point' : 'by ending the worker';
}

// One request at a time; the answer is the worker's next 'answer' message.
function request(message, transfer = []) {
  return new Promise((resolve) => {
    pending = resolve;
    worker.postMessage(message, transfer);
  });
}

function onWorkerMessage(m) {
  switch (m.type) {
    case 'answer': { const resolve = pending; pending = null; resolve(m); break; }
    case 'phase': startPhase(m.name); break;
    case 'progress': showProgress(m.done, m.total); break;
    case 'layers': showLayers(m); break;
    case 'line': recon.lines.push(m.text); $('log').textContent += m.text + '\n'; break;
    default: break;
  }
}

// ---- progress

let phaseName = '';
function startPhase(name) {
  recon.runs[name] = (recon.runs[name] ?? 0) + 1;
  phaseName = phaseNames[name] ?? name;
  showProgress(0, 0);
}
function showProgress(done, total) {
  const fraction = total > 0 ? Math.min(1, done / total) : 0;
  $('bar').style.width = `${(100 * fraction).toFixed(1)}%`;
  $('phase').textContent = total > 0 ? `${phaseName}: ${done.toLocaleString('en-US')} of ${total.toLocaleString('en-US')}` : phaseName;
}

// ---- layers: the report's data (report.cpp), drawn by the report's viewer

// One renderer for every view, its shaders compiled while the page is idle
// (a software renderer takes a few hundred milliseconds per shader).
const renderer = makeRenderer($('canvas'), false, false);
renderer.setSize(Math.max(1, $('view').clientWidth), Math.max(1, $('view').clientHeight), false);  // (its buffers, once)
warmUp(renderer);
const frames = fencedFrames(renderer);  // drawn without holding the main thread (viewer.js)
recon.frames = frames;

// Stage 1: phase I done, 2: phase II, 4: phase IV (refined, as phase V
// starts), 5: the run. recon.views records each view: its stage, the
// layers it has, its bytes and the time it took here.
function showLayers({ stage, json, arrays }) {
  const start = performance.now();
  const data = JSON.parse(json);
  recon.viewer?.dispose();
  recon.viewer = showReport(data, (id) => arrays[id], { deferFirstFrame: true, renderer, frames });
  document.title = `recon: ${data.title}`;
  recon.views.push({ stage, at: start, ms: performance.now() - start,
    bytes: json.length + arrays.reduce((n, a) => n + a.byteLength, 0),
    layers: recon.viewer.layers.filter((l) => l.available).map((l) => l.id) });
}

// ---- input

const mib = (bytes) => `${Math.round(bytes / 1e6).toLocaleString('en-US')} MB`;

async function load() {
  $('log').textContent = '';
  const answer = source.file
    ? await request({ type: 'load', name: source.file.name, bytes: await source.file.arrayBuffer() })
    : await request({ type: 'sample', shape: source.sample, points: source.points });
  if (answer.error) throw new Error(answer.error);
  workerHasInput = true;
  recon.input = answer.input;
  const i = answer.input;
  $('estimate').textContent = `${i.points.toLocaleString('en-US')} points${i.has_colors ? ', with colours' : ''}; ` +
    `memory estimate ${mib(i.estimated_bytes)} of the page's ${mib(i.limit_bytes)}` +
    (i.estimated_bytes > i.limit_bytes ? ': too large for the page, use the program (recon reconstruct)' : '');
}

// ---- running

const number = (id) => { const v = Number($(id).value); return $(id).value !== '' && v > 0 ? v : 0; };
function parameters() {
  return {
    method: Number($('method').value), k: Math.round(number('k')), rho: number('rho'),
    delta: $('delta').value === '' ? -1 : Math.max(0, Number($('delta').value)), cell: number('cell'),
    resolution: Math.round(number('resolution')),
  };
}

// The first phase a change of parameters affects: k, rho and the method
// change phase I; delta, the cell and the resolution phases III-V. (In the
// refined method a new cell may change phase I's fits, which tell two
// sheets apart at 1.5 cells: the worker then runs phases I-II again,
// webapp.cpp.)
function firstPhaseFor(p) {
  if (!held || !workerHasInput) return 1;
  return p.method !== held.method || p.k !== held.k || p.rho !== held.rho ? 1 : 3;
}

async function run() {
  const p = parameters();
  $('error').textContent = '';
  recon.error = '';
  setState('running');
  try {
    recon.timeline = { start: performance.now() };  // (bench/webapp_bench.mjs prints it)
    if (cancelFlag) Atomics.store(cancelFlag, 0, 0);
    if (!workerHasInput) { held = null; await load(); }
    recon.timeline.loaded = performance.now();
    if (cancelFlag && Atomics.load(cancelFlag, 0) === 1) { showCancelled(); return; }  // (while the file was read)
    const from = firstPhaseFor(p);
    const answer = await request({ type: 'run', from, ...p });
    recon.timeline.answered = performance.now();
    held = answer.kept ? p : null;
    if (answer.cancelled) { showCancelled(); return; }
    if (answer.error) throw new Error(answer.error);
    recon.runEndedAt = answer.postedAt - performance.timeOrigin;  // the worker idle from here (bench/webapp_bench.mjs)
    recon.stats = answer.stats;
    showLayers(answer.layers);
    showChosen(answer.stats);
    $('bar').style.width = '100%';
    $('phase').textContent = `done in ${answer.stats.seconds_total.toFixed(2)} s`;
    setState('done');
    recon.timeline.done = performance.now();
  } catch (e) {
    showError(e.message);
  }
}

// Beside each control, the value the run used.
function showChosen(stats) {
  const format = (v) => (Number.isInteger(v) ? String(v) : String(Number(v.toPrecision(6))));
  $('chosen-method').textContent = `used: ${stats.method}`;
  $('chosen-k').textContent = `used: ${format(stats.tangent_planes.k)}`;
  $('chosen-rho').textContent = `used: ${format(stats.tangent_planes.rho)}`;
  $('chosen-delta').textContent = `used: ${format(stats.signed_distance.delta)}`;
  $('chosen-cell').textContent = `used: ${format(stats.contouring.cell)}`;
  $('chosen-resolution').textContent = `used: a lattice of ${stats.contouring.lattice_size.map(format).join(' × ')} cubes`;
}

// Cancel. The worker is busy in WebAssembly and reads no message until the
// run ends. With a shared flag, the run stops at its next interruption point
// (webapp.cpp) and the worker keeps the input, and phases I-II when they
// were done. Without one (a page opened from file://, where browsers give
// no SharedArrayBuffer), the worker is ended and a fresh one started; the
// next run reads the input again.
function cancel() {
  if (cancelFlag) {
    Atomics.store(cancelFlag, 0, 1);
    $('phase').textContent = 'cancelling…';
    return;
  }
  worker.terminate();
  pending = null;
  startWorker();
  held = null;
  showCancelled();
}
function showCancelled() {
  $('phase').textContent = 'cancelled';
  $('bar').style.width = '0';
  setState('idle');
}

function choose(newSource) {
  source = newSource;
  workerHasInput = false;
  held = null;
  run();
}

// ---- downloads, written by the program's writers in the worker

function baseName() {
  const name = source?.file ? source.file.name : source?.sample ?? 'recon';
  return name.replace(/\.[^.]*$/, '');
}
async function download(what, ext) {
  const name = `${baseName()}-${what === 'mesh' ? 'mesh' : what === 'cloud' ? 'oriented' : what}.${ext}`;
  const answer = await request({ type: 'write', what, name });
  if (answer.error) { showError(answer.error); return; }
  const url = URL.createObjectURL(new Blob([answer.bytes]));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 60000);
}

// ---- wiring

$('file').addEventListener('change', (e) => { if (e.target.files[0]) choose({ file: e.target.files[0] }); });
$('sample').addEventListener('change', (e) => {
  const points = { conics: 16000, part: 30000, torus: 20000 }[e.target.value];
  if (points) choose({ sample: e.target.value, points });
});
$('go').addEventListener('click', run);
$('cancel').addEventListener('click', cancel);
for (const b of document.querySelectorAll('#downloads button')) b.addEventListener('click', () => download(b.dataset.what, b.dataset.ext));
const view = $('view');
view.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
view.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
view.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  const file = e.dataTransfer.files[0];
  if (file && document.body.dataset.state !== 'running') choose({ file });
});

startWorker();
setState('idle');
