// Builds the web page into ONE file: index.html with the report's style and
// this page's, page.js bundled with the report's viewer and three.js
// (esbuild, as web/report/build.mjs bundles the report), and the worker's
// source (the Emscripten module, its WebAssembly inlined, then worker.js)
// as a string the page starts its worker from. Run by CMake
// (web/webapp/CMakeLists.txt) from web/:
//   node webapp/build.mjs MODULE.js OUT.html
import { bundleScript } from '../report/bundle.mjs';
import { readFileSync, writeFileSync, renameSync, mkdirSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const here = dirname(fileURLToPath(import.meta.url));
const [moduleFile, out] = process.argv.slice(2);
if (!moduleFile || !out) {
  console.error('usage: node webapp/build.mjs MODULE.js OUT.html');
  process.exit(2);
}

const workerSource = readFileSync(moduleFile, 'utf8') + '\n' + readFileSync(join(here, 'worker.js'), 'utf8');
const script = await bundleScript(join(here, 'page.js'), { workerSource: JSON.stringify(workerSource) });
const page = readFileSync(join(here, 'index.html'), 'utf8')
  .replace('/*RECON_STYLE*/', () => readFileSync(join(here, '..', 'report', 'style.css'), 'utf8'))
  .replace('/*WEBAPP_STYLE*/', () => readFileSync(join(here, 'style.css'), 'utf8'))
  .replace('/*WEBAPP_SCRIPT*/', () => script);
mkdirSync(dirname(out), { recursive: true });
writeFileSync(out + '.tmp', page);
renameSync(out + '.tmp', out);
console.log(`web page: ${out} (${(page.length / 1e6).toFixed(1)} MB, the module ${(workerSource.length / 1e6).toFixed(1)} MB)`);
