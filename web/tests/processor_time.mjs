// Processor time of the browser, for tests that time a page on a machine
// they share (Linux only: it reads /proc).
//
// A page's wall time depends on what else the machine runs: another
// tenant of the host (the hypervisor's "steal") or another program can take
// the processor away for seconds. The processor time the browser's
// processes consumed hardly does: it is the work the page needed. On an idle
// machine of the same speed the wall time would be at most that work plus
// the waits for the disk (none worth counting for a file in the page
// cache), since running the browser's threads side by side can only make
// the wall time shorter than their sum.

import { execFileSync } from 'node:child_process';
import { readdirSync, readFileSync } from 'node:fs';

const ticksPerSecond = Number(execFileSync('getconf', ['CLK_TCK'], { encoding: 'utf8' }).trim()) || 100;

// Every process's parent and its processor time in seconds (user + system,
// and that of its children it has waited for, so that a browser process
// that ends between two readings keeps counting through its parent).
function processTable() {
  const table = new Map();
  for (const name of readdirSync('/proc')) {
    if (!/^\d+$/.test(name)) continue;
    let stat;
    try { stat = readFileSync(`/proc/${name}/stat`, 'utf8'); } catch { continue; }  // ended meanwhile
    // After "pid (comm) ": state, ppid, ..., utime (14th field), stime, cutime, cstime.
    const f = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
    table.set(Number(name), { parent: Number(f[1]), seconds: (Number(f[11]) + Number(f[12]) + Number(f[13]) + Number(f[14])) / ticksPerSecond });
  }
  return table;
}

/// Processor seconds used so far by the processes descending from this one
/// (the browser that playwright started, with its renderer and GPU processes).
export function descendantsProcessorSeconds() {
  const table = processTable();
  let total = 0;
  for (const [pid, { seconds }] of table) {
    if (pid === process.pid) continue;
    let p = table.get(pid).parent;
    while (p !== undefined && p !== process.pid && p > 1) p = table.get(p)?.parent;
    if (p === process.pid) total += seconds;
  }
  return total;
}

/// The whole machine's processor time so far, in seconds summed over its
/// cores: busy (any process) and stolen by the hypervisor.
export function machineSeconds() {
  const f = readFileSync('/proc/stat', 'utf8').split('\n')[0].trim().split(/\s+/).slice(1).map(Number);
  const [user, nice, system, , , irq, softirq, steal = 0] = f;  // (idle and iowait skipped)
  return { busy: (user + nice + system + irq + softirq) / ticksPerSecond, steal: steal / ticksPerSecond };
}
