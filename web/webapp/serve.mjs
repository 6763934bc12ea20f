// Serves the web page from this machine (loopback only), with the two
// headers that make a page cross-origin isolated (COOP and COEP): the
// browser then gives it shared memory, and Cancel stops a run at its next
// interruption point, keeping the input and phases I-II (page.js). Opened
// from file:// the page works the same, but Cancel ends the worker instead.
//   node web/webapp/serve.mjs [build/webapp/index.html] [port, 8000]
// then open http://127.0.0.1:8000/. The page's browser tests
// (web/tests/webapp.test.mjs) serve it with isolatedServer().
import { createServer } from 'node:http';
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

// Serves `page` (the page's bytes) at / on 127.0.0.1:port (0: any free
// port); resolves to { server, origin } once listening.
export function isolatedServer(page, port = 0) {
  const server = createServer((request, response) => {
    const found = ['GET', 'HEAD'].includes(request.method) && (request.url === '/' || request.url === '/index.html');
    response.writeHead(found ? 200 : 404, {
      'Content-Type': found ? 'text/html; charset=utf-8' : 'text/plain; charset=utf-8',
      'Cross-Origin-Opener-Policy': 'same-origin',
      'Cross-Origin-Embedder-Policy': 'require-corp',
      'Cache-Control': 'no-store',
    });
    response.end(found ? page : 'not found: the page is at /\n');
  });
  return new Promise((done, failed) => {
    server.once('error', failed);
    server.listen(port, '127.0.0.1', () => done({ server, origin: `http://127.0.0.1:${server.address().port}` }));
  });
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const path = resolve(process.argv[2] ?? 'build/webapp/index.html');
  let page;
  try {
    page = readFileSync(path);
  } catch (e) {
    console.error(`serve.mjs: cannot read the page ${path}: ${e.code ?? e.message} (build it with scripts/webapp)`);
    process.exit(1);
  }
  const port = Number(process.argv[3] ?? 8000);
  isolatedServer(page, port).then(({ origin }) => console.log(`the page, isolated: ${origin}/ (Ctrl-C stops)`),
    (e) => { console.error(`serve.mjs: cannot listen on 127.0.0.1:${port}: ${e.code ?? e.message}`); process.exit(1); });
}
