"""The Python peers' "step NAME SECONDS s" lines, as steps.h prints them for
the C++ peers (bench/peers.sh reads them into its report).

printer() -> step(name): each call prints the seconds since the previous call
(the first: since printer() was called).
"""

import time


def printer():
    last = time.perf_counter()

    def step(name):
        nonlocal last
        now = time.perf_counter()
        print(f"step {name:<16} {now - last:9.3f} s", flush=True)
        last = now

    return step
