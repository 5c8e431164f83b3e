#!/usr/bin/env python3
"""Two Prism binaries timed against each other on one scene, for machines whose speed is too noisy for a few runs.

    python3 benches/ab_render.py OLD_BINARY NEW_BINARY [--scene scenes/cornell_box.ron] [--spp 16] [--rounds 80]
                                 [--threads 2] [-- EXTRA PRISM ARGS...]

Each round renders the scene once with each binary, alternating which goes first, each run from a fresh copy of its
binary (the same bytes run from different files differed by up to 15% on one machine: the page cache's placement of
the executable), and reads the render time Prism prints (set-up excluded). Noise on a shared machine only ever adds
time, so the estimate is the mean of each binary's fastest 80% of runs, and the ratio NEW / OLD comes with a
bootstrap 95% interval (2000 resamples of each binary's runs). Also printed: plain means, medians and minima.
Standard library only; nothing is written outside a temporary directory.
"""

import argparse
import random
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def render_time(binary, scene, spp, threads, extra, out):
    r = subprocess.run([str(binary), "render", str(scene), "--spp", str(spp), "--threads", str(threads),
                        "--checkpoint", "0", "-o", str(out), *extra], capture_output=True, text=True)
    m = re.search(r" in ([0-9.]+) s render", r.stderr)
    if r.returncode != 0 or not m:
        sys.exit(f"error: {binary} render failed (exit {r.returncode}):\n{r.stderr}")
    return float(m.group(1))


def fast_mean(v, keep=0.8):
    v = sorted(v)
    return statistics.mean(v[:max(1, int(len(v) * keep))])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--scene", type=Path, default=Path("scenes/cornell_box.ron"))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=80)
    ap.add_argument("--threads", type=int, default=2)
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    a = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    a.extra = extra
    if a.rounds < 2 or a.spp < 1 or a.threads < 1:
        sys.exit("error: --rounds must be at least 2, --spp and --threads at least 1")
    for b in (a.old, a.new):
        if not b.is_file():
            sys.exit(f"error: no binary at {b}")
    times = {"old": [], "new": []}
    with tempfile.TemporaryDirectory(prefix="prism-ab-") as tmp:
        tmp = Path(tmp)
        for r in range(a.rounds):
            order = [("old", a.old), ("new", a.new)]
            if r % 2:
                order.reverse()
            for name, binary in order:
                copy = tmp / f"{name}-{r}"
                shutil.copy2(binary, copy)
                times[name].append(render_time(copy, a.scene, a.spp, a.threads, a.extra, tmp / "out.exr"))
                copy.unlink()
            print(f"round {r + 1}/{a.rounds}: old {times['old'][-1]:.3f} s, new {times['new'][-1]:.3f} s",
                  file=sys.stderr)
    for name in ("old", "new"):
        v = times[name]
        print(f"{name}: fastest-80% mean {fast_mean(v):.4f} s, mean {statistics.mean(v):.4f}, "
              f"median {statistics.median(v):.4f}, min {min(v):.4f} ({len(v)} runs)")
    rng = random.Random(1)
    boot = sorted(fast_mean(rng.choices(times["new"], k=a.rounds)) / fast_mean(rng.choices(times["old"], k=a.rounds))
                  for _ in range(2000))
    ratio = fast_mean(times["new"]) / fast_mean(times["old"])
    print(f"new / old: {ratio:.3f} (bootstrap 95% interval {boot[49]:.3f}-{boot[1949]:.3f})")


if __name__ == "__main__":
    main()
