// The report's lab panel (recon lab --report; include/recon/report/report.h): the
// alternatives lab's runs as a chart of their times and tables of what they
// counted. Plain DOM, no three.js: viewer.js draws the lab's orientation
// graphs as layers, into the element this panel leaves for them.
//
// The runs are those of `recon lab --stats` (app/lab.cpp), as the data block
// holds them: data.lab.stats.runs, each with name, kind, seconds, and where
// they apply graph, skipped (the reason), counts {pushes, pops, ...},
// tree_weight, and for the graph runs edges, components, flips,
// agree_default and agree_truth. A counter a run does not report is 0.

export const kinds = ['search', 'queue', 'mst', 'graph'];

const counters = [
  ['pushes', 'pushes'], ['pops', 'pops'], ['decrease_keys', 'decrease-keys'], ['comparisons', 'comparisons'],
  ['finds', 'finds'], ['unions', 'unions'], ['distance_evaluations', 'distance evaluations'], ['rounds', 'rounds'],
];

const ran = (run) => !run.skipped;
// The runs, each with the label the panel shows: its name, and the graph it
// ran on where the runs of its kind ran on more than one (the mst runs:
// Prim on the Riemannian graph, Prim's array version on the complete one).
export function labelled(runs) {
  const graphs = (kind) => new Set(runs.filter((r) => r.kind === kind).map((r) => r.graph ?? '')).size;
  const label = (r) => (r.graph && r.kind !== 'graph' && graphs(r.kind) > 1 ? `${r.name} (${r.graph})` : r.name);
  return runs.map((r) => ({ ...r, label: label(r) }));
}

// 0.00042 s -> "420 µs", 0.0123 -> "12.3 ms", 4.5 -> "4.5 s".
export function formatSeconds(s) {
  if (!(s > 0)) return '0 s';
  const [value, unit] = s < 1e-3 ? [s * 1e6, 'µs'] : s < 1 ? [s * 1e3, 'ms'] : [s, 's'];
  return `${Number(value.toPrecision(3))} ${unit}`;
}
// Counts up to 9,999 in full, larger ones to 3 digits (the cell's title has
// them whole). A counter at 0 did not apply to the run (operation_counts.h).
const formatCounter = (n) => (n === 0 ? '–' : formatCount(n));
function formatCount(n) {
  if (n < 1e4) return Math.round(n).toLocaleString('en-US');
  const [value, unit] = n < 1e9 ? (n < 1e6 ? [n / 1e3, 'k'] : [n / 1e6, 'M']) : [n / 1e9, 'G'];
  return `${Number(value.toPrecision(3))} ${unit}`;
}
const formatShare = (v) => `${Number((100 * v).toPrecision(4))} %`;
const formatWeight = (v) => String(Number(v.toPrecision(4)));

function element(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}

// Each bar's length as a share of its group's longest: linear, or on a log
// scale from half the fastest run's time (so that the fastest bar shows).
export function barShares(seconds, log) {
  const max = Math.max(0, ...seconds);
  if (!(max > 0)) return seconds.map(() => 0);
  if (!log) return seconds.map((s) => Math.max(0, s) / max);
  const low = Math.min(...seconds.filter((s) => s > 0)) / 2;
  return seconds.map((s) => (s > 0 ? Math.log(s / low) / Math.log(max / low) : 0));
}

// (a) The times: a group of bars per kind, then the runs it skipped and why.
function timingGroup(kind, runs) {
  const group = element('div', 'lab-group');
  group.dataset.kind = kind;
  group.appendChild(element('div', 'lab-kind', kind));
  for (const run of runs.filter(ran)) {
    const row = element('div', 'lab-bar-row');
    row.dataset.run = run.label;
    row.dataset.seconds = String(run.seconds ?? 0);
    const track = element('span', 'lab-track');
    track.appendChild(element('span', `lab-bar lab-${kind}`));
    row.append(element('span', 'lab-name', run.label), track, element('span', 'lab-time', formatSeconds(run.seconds ?? 0)));
    row.title = `${run.label}: ${run.seconds} s`;
    group.appendChild(row);
  }
  for (const run of runs.filter((r) => !ran(r))) {
    const skipped = element('div', 'lab-skipped', `${run.label}: skipped, ${run.skipped}`);
    skipped.dataset.run = run.label;
    group.appendChild(skipped);
  }
  return group;
}

function setBars(chart, log) {
  for (const group of chart.querySelectorAll('.lab-group')) {
    const rows = [...group.querySelectorAll('.lab-bar-row')];
    const shares = barShares(rows.map((r) => Number(r.dataset.seconds)), log);
    rows.forEach((r, i) => { r.querySelector('.lab-bar').style.width = `${(100 * shares[i]).toFixed(2)}%`; });
  }
}

function timingChart(runs) {
  const chart = element('div');
  chart.id = 'lab-chart';
  for (const kind of kinds) {
    const ofKind = runs.filter((r) => r.kind === kind);
    if (ofKind.length > 0) chart.appendChild(timingGroup(kind, ofKind));
  }
  return chart;
}

// (b) The columns a kind's table needs: the counters some run of it used,
// the tree's weight where one was grown, and the graph runs' figures.
function columns(kind, runs) {
  const used = (key) => runs.some((r) => (r.counts?.[key] ?? 0) !== 0);
  const given = (key) => runs.some((r) => typeof r[key] === 'number');
  const figure = (key, title, format) => ({ key, title, value: (r) => r[key], format });
  const out = counters.filter(([key]) => used(key))
    .map(([key, title]) => ({ key, title, value: (r) => r.counts?.[key] ?? 0, format: formatCounter }));
  if (given('tree_weight')) out.push(figure('tree_weight', 'tree weight', formatWeight));
  if (kind !== 'graph') return out;
  out.push(figure('edges', 'edges', formatCount), figure('components', 'pieces', formatCount),
    figure('flips', 'flips', formatCount), figure('agree_default', 'agrees with default', formatShare));
  if (given('agree_truth')) out.push(figure('agree_truth', 'agrees with truth', formatShare));
  return out;
}

function countsTable(kind, runs) {
  const table = element('table', 'lab-counts');
  table.dataset.kind = kind;
  const cols = columns(kind, runs);
  const head = element('tr');
  head.appendChild(element('th', 'key', kind));
  for (const c of cols) head.appendChild(element('th', 'value', c.title)).dataset.key = c.key;
  table.appendChild(head);
  for (const run of runs) {
    const tr = element('tr');
    tr.dataset.run = run.label;
    tr.appendChild(element('td', 'key', run.label));
    for (const c of cols) {
      const v = c.value(run);
      const td = element('td', 'value', typeof v === 'number' ? c.format(v) : '–');
      td.dataset.key = c.key;
      td.dataset.value = JSON.stringify(v ?? null);
      if (typeof v === 'number') td.title = String(v);
      tr.appendChild(td);
    }
    table.appendChild(tr);
  }
  return table;
}

function countsTables(runs) {
  const div = element('div');
  div.id = 'lab-tables';
  for (const kind of kinds) {
    const ofKind = runs.filter((r) => r.kind === kind && ran(r));
    if (ofKind.length > 0) div.appendChild(countsTable(kind, ofKind));
  }
  return div;
}

// Fills `section` (hidden until now) with the panel; returns the element
// the graphs' layer toggles go into.
export function labPanel(lab, section) {
  const runs = labelled(Array.isArray(lab.stats?.runs) ? lab.stats.runs : []);
  const skipped = runs.filter((r) => !ran(r)).length;
  section.appendChild(element('div', 'note', `${runs.length - skipped} runs ran` +
    (skipped > 0 ? `, ${skipped} were skipped` : '') + '; each kind\'s bars have a scale of their own'));
  const heading = element('h3', null, 'Time ');
  const toggle = element('label', 'lab-log');
  toggle.innerHTML = '<input type="checkbox" id="lab-log"> log scale';
  heading.appendChild(toggle);
  const chart = timingChart(runs);
  section.append(heading, chart);
  setBars(chart, false);
  toggle.querySelector('input').addEventListener('change', (e) => setBars(chart, e.target.checked));
  section.append(element('h3', null, 'Counts'), countsTables(runs), element('h3', null, 'Orientation graphs'));
  const layers = element('div');
  layers.id = 'lab-layers';
  section.appendChild(layers);
  section.hidden = false;
  return layers;
}
