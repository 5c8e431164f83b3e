#!/usr/bin/env python3
"""Thread scaling, 1 -> N threads, of each integrator, measured by alternating runs on a noisy machine.

    python3 benches/thread_scaling.py [BINARY] [--scene scenes/cornell_box.ron] [--spp 16] [--rounds 12]
                                      [--threads 2] [--integrators envlight,phong,ppm] [-- EXTRA PRISM ARGS...]

BINARY defaults to target/release/prism. Each round renders the scene once per integrator on one thread and on N,
alternating which goes first, each run from a fresh copy of the binary (see `ab_render.py`, whose timing this
shares: the render time Prism prints, set-up excluded). Printed per integrator: the speed-up as the ratio of the
one-thread and N-thread runs' fastest-80% means with a bootstrap 95% interval, and the median and range of the
rounds' paired ratios (each round's two runs ran back to back, so a slow spell of the machine cancels in them).
The issue's target is a speed-up of at least 1.85 from one thread to two. Standard library only.
"""

import argparse
import random
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ab_render import fast_mean, render_time  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary", type=Path, nargs="?", default=Path("target/release/prism"))
    ap.add_argument("--scene", type=Path, default=Path("scenes/cornell_box.ron"))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--integrators", default="envlight,phong,ppm")
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    a = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    integrators = [i for i in a.integrators.split(",") if i]
    if a.rounds < 2 or a.spp < 1 or a.threads < 2 or not integrators:
        sys.exit("error: --rounds and --threads must be at least 2, --spp at least 1, and one integrator named")
    if not a.binary.is_file():
        sys.exit(f"error: no binary at {a.binary} (build it with `cargo build --release`)")
    times = {(i, t): [] for i in integrators for t in (1, a.threads)}
    with tempfile.TemporaryDirectory(prefix="prism-scaling-") as tmp:
        tmp = Path(tmp)
        for r in range(a.rounds):
            for i in integrators:
                order = [1, a.threads] if r % 2 == 0 else [a.threads, 1]
                for t in order:
                    copy = tmp / f"prism-{r}-{i}-{t}"
                    shutil.copy2(a.binary, copy)
                    args = ["--integrator", i, *extra]
                    times[(i, t)].append(render_time(copy, a.scene, a.spp, t, args, tmp / "out.exr"))
                    copy.unlink()
                one, many = times[(i, 1)][-1], times[(i, a.threads)][-1]
                print(f"round {r + 1}/{a.rounds} {i}: 1 thread {one:.3f} s, {a.threads} threads {many:.3f} s "
                      f"({one / many:.2f}x)", file=sys.stderr)
    rng = random.Random(1)
    for i in integrators:
        one, many = times[(i, 1)], times[(i, a.threads)]
        boot = sorted(fast_mean(rng.choices(one, k=a.rounds)) / fast_mean(rng.choices(many, k=a.rounds))
                      for _ in range(2000))
        paired = [o / m for o, m in zip(one, many)]
        print(f"{i}: 1 -> {a.threads} threads {fast_mean(one) / fast_mean(many):.2f}x "
              f"(bootstrap 95% interval {boot[49]:.2f}-{boot[1949]:.2f}); paired rounds median "
              f"{statistics.median(paired):.2f}x, range {min(paired):.2f}-{max(paired):.2f} ({a.rounds} rounds)")


if __name__ == "__main__":
    main()
