#!/usr/bin/python3
"""The markdown tables of bench/peers.sh, from the files its runs left.

    report.py RUN_DIR...   (one directory per point count; markdown on stdout)

Each RUN_DIR holds `points` and `limit` (the point count, the time limit in
seconds) and runs.tsv, one row per program:
    name  label  kind  reference  threads  status
kind is `normals` or `mesh`; reference names the recon run its time is
divided by; status is ok, stopped, or failed. Beside them, per program:
NAME.time (GNU time: wall seconds, peak RSS KiB, user s, system s),
NAME.normals.json and NAME.mesh.json (compare_normals.py), NAME.log.
"""

import json
import os
import sys


def read_json(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def read_time(path):
    """(wall s, peak MiB, cpu s) or None. GNU time may put a 'Command exited' line first."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    if not lines or len(lines[-1]) != 4:
        return None
    wall, rss_kib, user, system = (float(x) for x in lines[-1])
    return wall, rss_kib / 1024.0, user + system


def length(x):
    return f"{x:.1e}" if x < 1e-3 else f"{x:.4f}"


def percent(figures, key):
    return "–" if not figures or key not in figures else f"{100.0 * figures[key]:.2f}"


def section(run_dir):
    rows = []
    with open(os.path.join(run_dir, "runs.tsv")) as f:
        for line in f:
            name, label, kind, reference, threads, status = line.rstrip("\n").split("\t")
            rows.append(dict(name=name, label=label, kind=kind, reference=reference, threads=threads,
                             status=status, time=read_time(os.path.join(run_dir, name + ".time")),
                             normals=read_json(os.path.join(run_dir, name + ".normals.json")),
                             mesh=read_json(os.path.join(run_dir, name + ".mesh.json"))))
    walls = {r["name"]: r["time"][0] for r in rows if r["status"] == "ok" and r["time"]}
    with open(os.path.join(run_dir, "points")) as f:
        points = int(f.read())
    limit = 600
    if os.path.exists(os.path.join(run_dir, "limit")):
        with open(os.path.join(run_dir, "limit")) as f:
            limit = int(f.read())
    stopped = f"stopped after {limit // 60} min" if limit % 60 == 0 else f"stopped after {limit} s"

    out = [f"### {points:,} points".replace(",", " "), ""]
    out.append("| program | threads | wall s | ÷ recon | CPU/wall | peak MiB "
               "| outward % | consistent % | \\|dot\\| > 0.9 % | undefined / unoriented "
               "| mesh vertices (unique) | triangles | dist. to torus RMS / max |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        if r["status"] == "ok" and r["time"]:
            wall, mib, cpu = r["time"]
            # recon resets the kernel's peak between its steps (for the
            # per-step figures of --stats), so GNU time's maximum RSS would be
            # the last step's: its own --stats gives the true peak.
            stats = read_json(os.path.join(run_dir, r["name"] + ".stats.json"))
            if stats and "memory" in stats:
                mib = stats["memory"]["peak_mib_total"]
            ref = walls.get(r["reference"])
            ratio = f"{wall / ref:.2f}" if ref else "–"
            timing = [f"{wall:.2f}", ratio, f"{cpu / wall:.2f}" if wall > 0 else "–", f"{mib:.0f}"]
        elif r["status"] == "stopped":
            timing = [stopped, "–", "–", "–"]
        else:
            timing = [r["status"], "–", "–", "–"]
        n = r["normals"]
        bad = "–"
        if n:
            bad = str(n["undefined"])
            if "unoriented" in n:
                bad += f" / {n['unoriented']}"
        m = r["mesh"]
        if m:
            vertices = f"{m['vertices']} ({m['unique_vertices']})" \
                if m["unique_vertices"] != m["vertices"] else str(m["vertices"])
            mesh = [vertices, str(m["faces"]),
                    f"{length(m['torus_rms'])} / {length(m['torus_max'])}" if "torus_rms" in m else "–"]
        else:
            mesh = ["–", "–", "–"]
        out.append("| " + " | ".join([r["label"], r["threads"], *timing, percent(n, "outward"),
                                      percent(n, "consistent"), percent(n, "line_0.9"), bad, *mesh]) + " |")
    out.append("")

    out.append("<details><summary>Each program's own report (steps and timings)</summary>")
    out.append("")
    out.append("```")
    for r in rows:
        path = os.path.join(run_dir, r["name"] + ".log")
        if not os.path.exists(path):
            continue
        with open(path, errors="replace") as f:
            lines = [line.rstrip() for line in f if line.strip()]
        out.append(f"== {r['label']}")
        out.extend(lines[-20:])  # the end holds the steps; a failure's message too
    out.append("```")
    out.append("</details>")
    out.append("")
    return "\n".join(out)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print("\n".join(section(d) for d in sys.argv[1:]))


if __name__ == "__main__":
    main()
