#!/usr/bin/env python3
"""Prism's BVH against Embree on the same rays: closest-hit and occlusion throughput, one thread each.

Command (from the repository root; the full measurement, about 3 minutes on an idle 2-core machine):

    python3 benches/embree/embree_compare.py --rounds 5 --seconds 1

Quick check that everything works (about 20 s):

    python3 benches/embree/embree_compare.py --rounds 1 --seconds 0.2

What it does:
  1. Installs Debian's `libembree-dev` with apt-get if neither <embree3/rtcore.h> nor <embree4/rtcore.h> is there
     (root; `apt-get update` first), builds `benches/embree/embree_rays.c` with gcc into `target/embree/` and
     Prism with `cargo build --release` (a no-op when up to date). Nothing is written outside `target/` except the
     Debian package.
  2. For each scene (default: the dragon 100k, the Stanford bunny 69k, the 6.837 bunny_40k and the teapot in a
     stadium, `teapot_in_stadium.ron` beside this script, and the 36-triangle Cornell box of the equal-error
     comparison with Mitsuba, `scenes/cornell_box.ron`) and each round: runs `prism bench SCENE --accel bvh
     --threads 1 --seconds S --export-rays target/embree/rays/ROUND` and `embree_rays FILE --seconds S` on the file
     of round 0, alternating which goes first from round to round. Every round's export must be byte-identical to
     round 0's (the ray sets are deterministic), so both engines trace exactly the same rays; `embree_rays`
     also checks that Embree's answer (closest primitive or t, occlusion) agrees with Prism's on every ray, and
     sorts disagreements into Embree self-hits (rays that leave a surface, on which Embree, queried from
     tnear = 0, finds that surface again within 1e-4 of the origin) and others.
  3. Prints and writes (`target/embree/embree_compare.csv`, `.md`) Mrays/s per ray kind (camera and bounce rays:
     closest hit; shadow rays: occlusion) for both engines, median over rounds, and the ratio Prism/Embree
     (median of the per-round ratios, with its min-max). Each engine's number in a round is its fastest pass over
     the set (both time passes the same way: interleaved rounds over the three sets until each had S seconds).

Embree: the scene is one triangle geometry built with RTC_BUILD_QUALITY_HIGH on a device with threads=1, queried
with single-ray rtcIntersect1 / rtcOccluded1 in a plain loop (no ray packets or streams); `--robust` adds
RTC_SCENE_FLAG_ROBUST (watertight, like Prism's triangle test). Debian builds Embree with run-time ISA dispatch
(SSE2 to AVX2/AVX-512), while Prism is built for the baseline target unless RUSTFLAGS says otherwise.
"""
import argparse
import hashlib
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
SHARED = ROOT.parent / "shared" / "data"
DEFAULT_SCENES = [
    SHARED / "meshes" / "dragon_100k.obj",
    SHARED / "meshes" / "stanford-bunny.obj",
    SHARED / "mit6837" / "assignment5" / "bunny_40k.obj",
    HERE / "teapot_in_stadium.ron",
    ROOT / "scenes" / "cornell_box.ron",
]
KINDS = ["camera", "bounce", "shadow"]


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"error: {' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stderr.strip()}")
    return r


def ensure_embree(out):
    """Install libembree-dev if needed; build embree_rays; return its path."""
    major = next((m for m in (4, 3) if Path(f"/usr/include/embree{m}/rtcore.h").exists()), None)
    if major is None:
        log("installing Debian's libembree-dev (apt-get) ...")
        run(["apt-get", "update"])
        run(["apt-get", "install", "-y", "--no-install-recommends", "libembree-dev"])
        major = next((m for m in (4, 3) if Path(f"/usr/include/embree{m}/rtcore.h").exists()), None)
        if major is None:
            sys.exit("error: libembree-dev installed no <embree3/rtcore.h> or <embree4/rtcore.h>")
    src, exe = HERE / "embree_rays.c", out / "embree_rays"
    if not exe.exists() or exe.stat().st_mtime < src.stat().st_mtime:
        shown = exe.relative_to(ROOT) if exe.is_relative_to(ROOT) else exe  # `-o` may lie outside the repository
        log(f"building {shown} against Embree {major} ...")
        flags = ["-DEMBREE4"] if major == 4 else []
        run(["gcc", "-O2", "-Wall", *flags, "-o", str(exe), str(src), f"-lembree{major}", "-lm"])
    return exe


def ensure_prism():
    log("cargo build --release ...")
    run(["cargo", "build", "--release", "--quiet"], cwd=ROOT)
    return ROOT / "target" / "release" / "prism"


def prism_bench(prism, scene, seconds, export_dir):
    """Mrays/s (camera, bounce, shadow) of Prism's BVH, one thread; exports the rays into export_dir. Runs a fresh
    copy of the binary: the same bytes run from two files differed by up to 15% (where the page cache put the
    executable; docs/decisions/0029-measure-interleaved-fresh-copies.md), so each round gets its own placement and the rounds average it out."""
    fd, name = tempfile.mkstemp(prefix="prism-", suffix=".bin", dir=export_dir.parent)
    os.close(fd)
    copy = Path(name)
    shutil.copy2(prism, copy)
    try:
        return prism_bench_with(copy, scene, seconds, export_dir)
    finally:
        copy.unlink()


def prism_bench_with(prism, scene, seconds, export_dir):
    r = run([str(prism), "bench", str(scene), "--accel", "bvh", "--threads", "1", "--seconds", str(seconds),
             "--export-rays", str(export_dir)])
    for line in r.stdout.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 9 and cells[2] == "bvh":
            return [float(cells[6]), float(cells[7]), float(cells[8])]
    sys.exit(f"error: no bvh row in the output of prism bench {scene}:\n{r.stdout}")


def embree_bench(exe, rays_file, seconds, robust):
    cmd = [str(exe), str(rays_file), "--seconds", str(seconds)] + (["--robust"] if robust else [])
    res = json.loads(run(cmd).stdout)
    for s in res["sets"]:
        if s["agree"] != s["checked"]:
            other = s["checked"] - s["agree"] - s.get("self_hits", 0)
            log(f"note: {rays_file.name}: Embree and Prism disagree on {s['checked'] - s['agree']} of "
                f"{s['checked']} {s['kind']} rays: {s.get('self_hits', 0)} Embree self-hits (a hit within 1e-4 of "
                f"the origin, on the surface the ray leaves), {other} other")
    return res


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def fmt_range(vals):
    return f"{statistics.median(vals):.2f} ({min(vals):.2f}-{max(vals):.2f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", type=Path, help="scene files (default: dragon, Stanford bunny, bunny_40k, "
                    "teapot in a stadium)")
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds (default 5)")
    ap.add_argument("--seconds", type=float, default=1.0, help="minimum timing per ray set per run (default 1)")
    ap.add_argument("--robust", action="store_true", help="Embree with RTC_SCENE_FLAG_ROBUST")
    ap.add_argument("-o", "--out", type=Path, default=ROOT / "target" / "embree", help="output directory")
    a = ap.parse_args()
    if a.rounds < 1 or not a.seconds > 0:
        sys.exit("error: --rounds must be >= 1 and --seconds > 0")
    scenes = a.scenes or DEFAULT_SCENES
    for s in scenes:
        if not s.exists():
            sys.exit(f"error: {s}: no such scene")
    a.out.mkdir(parents=True, exist_ok=True)
    exe = ensure_embree(a.out)
    prism = ensure_prism()
    rays_dir = a.out / "rays"
    shutil.rmtree(rays_dir, ignore_errors=True)
    # results[scene][engine][kind] = list over rounds
    results = {s: {"prism": [[], [], []], "embree": [[], [], []]} for s in scenes}
    info = {}
    # Round 0's export is the reference rays; write it before the first timed round (also warms the file cache).
    for s in scenes:
        log(f"{s.name}: exporting rays ...")
        run([str(prism), "bench", str(s), "--accel", "bvh", "--threads", "1", "--seconds", "0.01",
             "--export-rays", str(rays_dir / "ref")])
    t_start = time.time()
    for rnd in range(a.rounds):
        for s in scenes:
            ref = rays_dir / "ref" / f"{s.stem}.prism-rays"
            order = ["prism", "embree"] if (rnd + scenes.index(s)) % 2 == 0 else ["embree", "prism"]
            for engine in order:
                if engine == "prism":
                    mr = prism_bench(prism, s, a.seconds, rays_dir / f"round{rnd}")
                    again = rays_dir / f"round{rnd}" / f"{s.stem}.prism-rays"
                    if digest(again) != digest(ref):
                        sys.exit(f"error: {s.name}: round {rnd}'s rays differ from round 0's (not deterministic)")
                    again.unlink()
                else:
                    res = embree_bench(exe, ref, a.seconds, a.robust)
                    mr = [st["mrays"] for st in res["sets"]]
                    info[s] = res
                for k in range(3):
                    results[s][engine][k].append(mr[k])
            p, e = results[s]["prism"], results[s]["embree"]
            log(f"round {rnd + 1}/{a.rounds} {s.name}: " + ", ".join(
                f"{KINDS[k]} {p[k][-1]:.2f} vs {e[k][-1]:.2f}" for k in range(3)) + " Mrays/s (Prism vs Embree)")
    log(f"measured in {time.time() - t_start:.0f} s")

    csv = ["scene,triangles,kind,round,prism_mrays,embree_mrays,ratio"]
    md = [f"Prism BVH vs Embree {next(iter(info.values()))['embree']}"
          f"{' (robust)' if a.robust else ''}, one thread, single rays, the rays of `prism bench` "
          f"({a.rounds} interleaved rounds, median (min-max)).", "",
          "| scene | triangles | rays (camera / bounce / shadow) | Prism camera | Embree camera | ratio | "
          "Prism bounce | Embree bounce | ratio | Prism shadow | Embree shadow | ratio |",
          "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for s in scenes:
        res = info[s]
        row = [s.name, str(res["tris"]), " / ".join(str(st["rays"]) for st in res["sets"])]
        for k in range(3):
            p, e = results[s]["prism"][k], results[s]["embree"][k]
            ratios = [pp / ee for pp, ee in zip(p, e) if ee > 0]
            for rnd, (pp, ee) in enumerate(zip(p, e)):
                csv.append(f"{s.name},{res['tris']},{KINDS[k]},{rnd},{pp:.4f},{ee:.4f},{pp / ee if ee else 0:.4f}")
            row += [f"{statistics.median(p):.2f}", f"{statistics.median(e):.2f}",
                    fmt_range(ratios) if ratios else "-"]
        md.append("| " + " | ".join(row) + " |")
    md.append("")
    md.append("Mrays/s; ratio = Prism / Embree (> 1: Prism faster). Closest hit for camera and bounce rays, "
              "occlusion for shadow rays.")
    text = "\n".join(md)
    (a.out / "embree_compare.csv").write_text("\n".join(csv) + "\n")
    (a.out / "embree_compare.md").write_text(text + "\n")
    print(text)
    log(f"wrote {a.out / 'embree_compare.csv'} and {a.out / 'embree_compare.md'}")


if __name__ == "__main__":
    main()
