// The report's script: the viewer (viewer.js) on the data block recon wrote
// into the page (src/report/report.cpp): the JSON in #recon-data, each array
// base64-encoded in #recon-array-N. Its handle is window.reconReport for the
// browser tests (web/tests/report.test.mjs) and scripts/phase-pictures.
import { showReport } from './viewer.js';

function arrayBytes(id) {
  const b64 = document.getElementById(`recon-array-${id}`).textContent;
  if (typeof Uint8Array.fromBase64 === 'function') return Uint8Array.fromBase64(b64);
  const text = atob(b64);
  const out = new Uint8Array(text.length);
  for (let i = 0; i < text.length; ++i) out[i] = text.charCodeAt(i);
  return out;
}

const data = JSON.parse(document.getElementById('recon-data').textContent);
window.reconReport = showReport(data, arrayBytes);
