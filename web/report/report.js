// The report's script: the viewer (viewer.js) on the data block recon wrote
// into the page (src/report.cpp). Its handle is window.reconReport for the
// browser tests (web/tests/report.test.mjs) and scripts/phase-pictures.
import { showReport } from './viewer.js';

const data = JSON.parse(document.getElementById('recon-data').textContent);
window.reconReport = showReport(data, (id) => document.getElementById(`recon-array-${id}`).textContent);
