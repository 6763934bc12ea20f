#!/usr/bin/env python3
"""What the Python package costs over the library: one cloud, side by side.

For each repetition, in this order, each in a fresh process:
  library  `recon reconstruct` on the cloud's PLY file: the library's own
           time is its --stats "seconds_total" less reading and writing;
  python   `recon.reconstruct(points)` on the same cloud as a numpy array
           (the array built before timing): the wall time of the call, and
           the library's time inside it (stats["seconds_total"]);
and the peak resident memory of each process (ru_maxrss), less the same
process's memory before the run (the interpreter and numpy; for the
program, nothing). Prints one line per run and a summary.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py \
        [--points 1000000] [--reps 3] [--threads N]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def python_run(cloud: str, threads: int) -> dict:
    """One recon.reconstruct call in a fresh interpreter."""
    code = f"""
import json, resource, time, numpy as np, recon
points = np.ascontiguousarray(recon.read_points({cloud!r}).points)  # the input, owned by numpy
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
started = time.perf_counter()
mesh = recon.reconstruct(points, threads={threads})
wall = time.perf_counter() - started
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({{"wall": wall, "inside": mesh.stats["seconds_total"], "faces": len(mesh.faces),
                  "before_mib": before / 1024, "peak_mib": peak / 1024,
                  "input_mib": points.nbytes / 2**20}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def interrupt_latency(cloud: str, threads: int, count: int) -> dict:
    """Ctrl-C during recon.reconstruct, `count` times at spread-out moments
    of the run, in a fresh interpreter: seconds from the signal to the
    KeyboardInterrupt."""
    code = f"""
import _thread, json, threading, time, numpy as np, recon
points = np.ascontiguousarray(recon.read_points({cloud!r}).points)
started = time.perf_counter(); recon.reconstruct(points, threads={threads}); whole = time.perf_counter() - started
latencies = []
for i in range({count}):
    sent = []
    def interrupt():
        time.sleep(whole * (i + 0.5) / {count})
        sent.append(time.perf_counter())
        _thread.interrupt_main()
    threading.Thread(target=interrupt).start()
    try:
        recon.reconstruct(points, threads={threads})
        time.sleep(whole)  # the signal came after the run: let it land here
    except KeyboardInterrupt:
        latencies.append(time.perf_counter() - sent[0])
print(json.dumps({{"whole": whole, "latencies": latencies}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def program_run(program: str, cloud: str, folder: str, threads: int) -> dict:
    stats = os.path.join(folder, "stats.json")
    mesh = os.path.join(folder, "mesh.ply")
    subprocess.run([program, "--threads", str(threads), "reconstruct", cloud, "-o", mesh, "--stats", stats,
                    "--quiet"], check=True)
    s = json.loads(Path(stats).read_text())
    library = s["seconds_total"] - s["input"]["seconds"] - s["output"]["seconds"]
    return {"library": library, "peak_mib": s["memory"]["peak_mib_total"],
            "faces": s["mesh"]["faces"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--program", default=str(ROOT / "build/release/app/recon"))
    parser.add_argument("--interrupts", type=int, default=8, help="Ctrl-C latency samples (0: none)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        cloud = os.path.join(folder, "torus.ply")
        subprocess.run([args.program, "generate", "torus", "-n", str(args.points), "-o", cloud, "--quiet"],
                       check=True)
        print(f"torus, {args.points} points, {args.threads} threads, {args.reps} repetitions")
        best_program, best_python = None, None
        for rep in range(args.reps):
            p = program_run(args.program, cloud, folder, args.threads)
            q = python_run(cloud, args.threads)
            assert p["faces"] == q["faces"], (p["faces"], q["faces"])
            overhead = q["wall"] - q["inside"]
            print(f"rep {rep}: program library {p['library']:.3f} s, peak {p['peak_mib']:.0f} MiB | "
                  f"python call {q['wall']:.3f} s, inside {q['inside']:.3f} s, outside {1000 * overhead:.1f} ms "
                  f"({100 * overhead / q['inside']:.2f} %), peak {q['peak_mib']:.0f} MiB of which "
                  f"{q['before_mib']:.0f} before the call (input {q['input_mib']:.0f} MiB)")
            if best_program is None or p["library"] < best_program["library"]:
                best_program = p
            if best_python is None or q["wall"] < best_python["wall"]:
                best_python = q
        q, p = best_python, best_program
        print(f"fastest: program's library time {p['library']:.3f} s; python call {q['wall']:.3f} s "
              f"({100 * (q['wall'] / p['library'] - 1):+.1f} % over the program's library time; "
              f"{100 * (q['wall'] - q['inside']) / q['inside']:.2f} % outside the library); "
              f"memory during the call {q['peak_mib'] - q['before_mib']:.0f} MiB over what the process held "
              f"before (the program's whole peak: {p['peak_mib']:.0f} MiB, including its own copy of the input)")
        if args.interrupts > 0:
            r = interrupt_latency(cloud, args.threads, args.interrupts)
            lat = sorted(r["latencies"])
            print(f"Ctrl-C at {args.interrupts} moments spread over a {r['whole']:.2f} s run: "
                  f"KeyboardInterrupt after {1000 * lat[len(lat) // 2]:.0f} ms (median), {1000 * lat[-1]:.0f} ms "
                  f"(longest) [{', '.join(f'{1000 * x:.0f}' for x in lat)}]")


if __name__ == "__main__":
    main()
