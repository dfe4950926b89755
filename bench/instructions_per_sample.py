"""Instructions per sample of `quatnav bench` entries, load independent, beside VQF.

Each entry runs once on n1 and once on n2 samples of the benchmark's data (`marg_data`, the
same samples as `quatnav bench`), each in its own process under callgrind; the difference of
the two totals divided by n2 - n1 is the mean cost of a sample over the samples between: the
interpreter's start, the imports and the data's preparation cancel (to some ten million
instructions per process, so the difference should span many samples). With the ns per sample of `quatnav bench`
this gives each implementation's instruction rate (instructions per ns), so that a difference
in speed can be read as more instructions or as slower ones.

    python bench/instructions_per_sample.py --filters "QuaternionEKF f64,QuaternionEKF f32,VQF"

Needs valgrind. The entries are those of `quatnav bench` (a name or part of it, comma-separated);
the pure-Python ones are slow under callgrind (use small --n1/--n2).
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys

_CHILD = """
import sys
import numpy as np
from quatnav.evaluation import bench
e = next(e for e in bench.entries() if e.name == sys.argv[1])
d = bench.marg_data(int(sys.argv[2]), 0)
e.make(d if np.dtype(e.dtype) == np.float64 else d.astype(e.dtype))()
"""

def instructions(name: str, n: int) -> int:
    """Total instructions of one process that prepares `n` samples and runs entry `name` once."""
    cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable, "-c", _CHILD, name, str(n)]
    out = subprocess.run(cmd, capture_output=True, text=True)
    m = re.search(r"Collected : (\d+)", out.stderr)
    if out.returncode != 0 or not m:
        raise SystemExit(f"{name}: the run under callgrind failed:\n{out.stderr[-2000:]}")
    return int(m.group(1))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--filters", default="QuaternionEKF f64,QuaternionEKF f32,EulerEKF f64,EulerEKF f32,VQF",
                   help="entries of `quatnav bench` (comma-separated names or parts of names)")
    p.add_argument("--n1", type=int, default=10_000, help="samples of the first run (default 10,000)")
    p.add_argument("--n2", type=int, default=1_000_000,
                   help="samples of the second run (default 1,000,000: the cost varies along the data, so the "
                        "difference should span most of what `quatnav bench -n 1e6` runs)")
    a = p.parse_args(argv)
    if not 0 < a.n1 < a.n2:
        p.error("--n1, --n2: need 0 < n1 < n2")
    from quatnav.evaluation import bench
    # An exact name takes that entry only ("VQF" is not also "PyVQF"); a part of a name, all it matches.
    chosen = []
    for part in (x.strip() for x in a.filters.split(",") if x.strip()):
        exact = [e for e in bench.entries() if e.name == part]
        chosen += [e for e in (exact or bench.entries(part)) if e not in chosen]
    if not chosen:
        p.error(f"--filters: no entry matches {a.filters!r}")
    print(f"{'entry':26s} {'instructions/sample':>20s}   (callgrind, ({a.n2:,} - {a.n1:,}) samples)")
    for e in chosen:
        if e.requires:
            try:
                __import__(e.requires)
            except ImportError:
                print(f"{e.name:26s} {'(' + e.requires + ' not installed)':>20s}")
                continue
        per = (instructions(e.name, a.n2) - instructions(e.name, a.n1)) / (a.n2 - a.n1)
        print(f"{e.name:26s} {per:20,.0f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
