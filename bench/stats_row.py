#!/usr/bin/env python3
"""One table row from a `recon reconstruct --stats` file, for the side-by-side
benchmarks (methods.sh, two_builds.sh):

    | LABEL | RUN | wall s | I s | II s | III s | IV s | V s | peak MiB | LAST |

LAST is given on the command line, or the mesh's triangle count.
Usage: stats_row.py STATS LABEL RUN [LAST]
"""
import json
import sys

stats_path, label, run = sys.argv[1:4]
s = json.load(open(stats_path))


def total(section, keys):
    d = s.get(section, {})
    return sum(d.get(k, 0.0) for k in keys)


planes = total("tangent_planes", ["seconds_tree", "seconds_knn_pca", "seconds_spacing"])
planes += s["tangent_planes"].get("quadrics", {}).get("seconds", 0.0)
last = sys.argv[4] if len(sys.argv) > 4 else str(s["mesh"]["faces"])
print("| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %s |" % (
    label, run, s["seconds_total"], planes,
    total("orientation", ["seconds_emst", "seconds_graph", "seconds_mst"]),
    total("signed_distance", ["seconds"]), total("contouring", ["seconds"]), total("refinement", ["seconds"]),
    s["memory"]["peak_mib_total"], last))
