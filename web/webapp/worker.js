// The web page's worker (page.js starts it from a Blob URL): the library
// compiled to WebAssembly (webapp.cpp; build.mjs puts its module,
// createReconWebapp, before this file). The page's requests are answered
// one at a time with an 'answer' message; while a run goes, the phases,
// their counts, their layers and the program's lines are posted as they come.
//
// Files go through Emscripten's in-memory file system: the dropped bytes are
// written as /in/NAME and read by the program's reader by that name (so its
// messages name the user's file, "face.ply:12: ..."); the outputs are written
// in /out and their bytes handed to the page.
/* global createReconWebapp */
'use strict';

const post = (message, transfer = []) => postMessage(message, transfer);
// postedAt: when the worker finished, on the clock every page shares.
const answer = (fields, transfer = []) =>
  post({ type: 'answer', ...fields, postedAt: performance.timeOrigin + performance.now() }, transfer);
let finalLayers = null;
// The page's Cancel: a flag it shares, where the browser gives the page a
// SharedArrayBuffer (a server that isolates it: README.md, "In the
// browser"); read at every interruption point of the run (webapp.cpp).
let cancelFlag = null;

const moduleReady = createReconWebapp({
  print: (text) => post({ type: 'line', text }),
  printErr: (text) => post({ type: 'line', text }),
  reconPhase: (name) => post({ type: 'phase', name }),
  reconProgress: (done, total) => post({ type: 'progress', done, total }),
  reconCancelled: () => cancelFlag !== null && Atomics.load(cancelFlag, 0) === 1,
  // Phases I-II's layers go at once; the run's own go with its answer (the
  // page draws them once the worker is idle).
  reconLayers: (stage, json, arrays) => {
    if (stage === 5) finalLayers = { stage, json, arrays };
    else post({ type: 'layers', stage, json, arrays }, arrays.map((a) => a.buffer));
  },
}).then((module) => {
  module.FS.mkdir('/in');
  module.FS.mkdir('/out');
  module.FS.chdir('/in');
  return module;
});

function errorOf(module) { return module.UTF8ToString(module._webapp_error()); }

// A file name as the user's, without folders (it is written in /in).
function plainName(name) { return String(name).replace(/^.*[\\/]/, '') || 'input'; }

function load(module, m) {
  const name = plainName(m.name);
  for (const old of module.FS.readdir('/in')) if (old !== '.' && old !== '..') module.FS.unlink(`/in/${old}`);
  module.FS.writeFile(name, new Uint8Array(m.bytes));
  const failed = module.ccall('webapp_load', 'number', ['string', 'string'], [name, m.format ?? '']);
  module.FS.unlink(name);  // the cloud is read: the file's bytes are not needed again
  return failed ? { error: errorOf(module) } : { input: describe(module) };
}

function describe(module) {
  return JSON.parse(module.UTF8ToString(module._webapp_input(0, 0)));
}

// The run's answer: its statistics and final layers, its error, or that it
// was cancelled; and whether phases I-II are kept for a run from phase III.
function run(module, m) {
  finalLayers = null;
  const failed = module._webapp_run(m.from, m.method, m.k, m.rho, m.delta, m.cell, m.resolution);
  const kept = module._webapp_kept() === 1;
  if (failed === 2) return [{ cancelled: true, kept }];
  if (failed) return [{ error: errorOf(module), kept }];
  const layers = finalLayers;
  finalLayers = null;
  return [{ stats: JSON.parse(module.UTF8ToString(module._webapp_stats())), layers, kept }, layers.arrays.map((a) => a.buffer)];
}

function write(module, m) {
  const path = `/out/${plainName(m.name)}`;
  if (module.ccall('webapp_write', 'number', ['string', 'string'], [m.what, path])) return [{ error: errorOf(module) }];
  const bytes = module.FS.readFile(path);
  module.FS.unlink(path);
  return [{ bytes: bytes.buffer }, [bytes.buffer]];
}

onmessage = async (e) => {
  const module = await moduleReady;
  const m = e.data;
  try {
    if (m.type === 'load') answer(load(module, m));
    else if (m.type === 'sample') {
      const failed = module.ccall('webapp_sample', 'number', ['string', 'number', 'number'], [m.shape, m.points, 1]);
      answer(failed ? { error: errorOf(module) } : { input: describe(module) });
    } else if (m.type === 'run') answer(...run(module, m));
    else if (m.type === 'write') answer(...write(module, m));
    else if (m.type === 'limit') module._webapp_set_limit(m.bytes);
    else if (m.type === 'cancel-flag') cancelFlag = new Int32Array(m.buffer);
  } catch (error) {
    answer({ error: `the page's worker failed: ${error.message ?? error}` });
  }
};
