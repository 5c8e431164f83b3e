#!/usr/bin/env python3
"""Prism against Mitsuba 3 at equal error: side by side, interleaved, on the scenes of ../shared/refs/.

The full measurement (run it on a quiet machine; about 10 minutes per Cornell-sized scene):

    python3 benches/peer/mitsuba_compare.py --spp 16,64,256 --reps 3

A quick check that everything works (under a minute after the one-time set-up):

    python3 benches/peer/mitsuba_compare.py --scenes cornell --spp 4,16 --reps 1 --prism-extra-spp ''

Beside this file: peer_setup.py (the set-up below, run by the system Python) and equal_error.py (the ratios, their
intervals and the tables, also behind `--summarize`).

Set-up (automatic, once; everything under target/peer/, which git ignores): a venv with `mitsuba==3.9.1` (the
references' version) and numpy from PyPI; Debian's `libllvm19` fetched with `apt-get download` and unpacked with
`dpkg -x` (Mitsuba's `llvm_ad_rgb` variant loads it through DRJIT_LIBLLVM_PATH); Prism built with `cargo build
--release`. The script then re-runs itself with the venv's Python.

For each scene (default: every reference with a Mitsuba dict and a Prism scene; a missing Prism scene is skipped
with a message):
  - Mitsuba 3.9.1 `llvm_ad_rgb`, path tracer with the reference's max_depth, 2 threads (dr.set_thread_count),
    with each sampler of `--peer-samplers` (default `ldsampler`, low-discrepancy, only 4^k spp; `independent`; and
    `multijitter`, correlated multi-jittered, square spp only, which on the Cornell box reaches a lower error than
    `ldsampler`: 6% less squared error at 64 spp and 15% at 256; `stratified` and `orthogonal` may be added). A
    sampler is skipped at an spp it would round. Each (sampler, spp) gets one untimed warm-up render (JIT
    compilation); a timed render is `mi.render(scene, spp=N, seed=s)` plus the conversion of the image to numpy (as
    ../shared/refs/curves2.md measured).
  - With `--peer-rr-depth 1,2,3`: each low-discrepancy sampler (`ldsampler`, `multijitter`) also with the path
    tracer's `rr_depth` at each of these (peers `mitsuba-SAMPLER-rrD`), so that a ratio can be read against the peer
    at its best Russian roulette (Prism's `envlight` plays it from the first bounce by default, Mitsuba from the
    fifth).
  - The peer at its best: after the full table, for each scene, Prism configuration and spp, the ratio against the
    Mitsuba configuration Prism does worst against (the largest ratio over every peer but `independent`), named.
  - Prism: `prism render SCENE --spp N --threads 2 --seed s --checkpoint 0 -o x.exr` plus the config's arguments
    (default two configs: `--integrator "envlight(max_depth: D)"`, D the reference's, and the same with
    `--adaptive`); time = the render time Prism prints
    (set-up excluded, like Mitsuba's load), and the process's wall time too. Also at --prism-extra-spp (default 4x
    the largest spp, so that Prism's curve reaches the peer's lowest error without extrapolation, and 5/8 and 3/4
    of each spp, where Prism's adaptive renders reach the peer's error: the time to it is then interpolated over a
    step of 1.2-1.6x in spp instead of the 4x between two of the peer's counts).
  - For each repetition and each spp the renderers run back to back, the order alternating, so a machine whose
    speed drifts slows all alike. Seeds differ per repetition. Each Prism run executes a fresh copy of the binary
    (the same bytes run from two files differed by up to 15%: where the page cache put the executable).
  - RMSE = sqrt(mean over pixels and RGB of (img - ref)^2) against ../shared/refs/NAME.exr.

Output (stdout and target/peer/results/): per scene, renderer and spp the median time (min-max), the mean RMSE
and Msamples/s; and the equal-error time ratio Prism / Mitsuba-ldsampler (and / Mitsuba-independent) at each
of the peer's spp: the peer's mean RMSE there is the target, Prism's (median time, mean RMSE) points are
interpolated in log-log to the time they reach it (as crates/lab/src/converge.rs::time_to_error does; `~` marks a value
extrapolated from the nearest segment), divided by the peer's median time. Beside it, a 95% bootstrap interval
(the same ratio over repetitions drawn with replacement, each keeping its Prism and peer renders together) and the
per-repetition range (min-max of the ratio from each repetition's own points alone, which need not contain the
headline). Where NAME.json gives the reference's own noise, a ratio with
both errors corrected for it (sqrt(rmse^2 - noise^2)) is shown too.

The profile-guided build (`--pgo`; slower than the plain one, docs/decisions/0018-pgo-not-default.md): every Prism configuration is run twice, by the plain `cargo build --release`
binary and by the profile-guided build of benches/pgo/build.sh (target/pgo/prism, built first when it is missing or
was built from other sources, by a hash of them kept beside it; labels ending in `-pgo`), interleaved like the rest.
With --cost-by-depth, --pgo times the profile-guided binary instead of the plain one.

Where along a path each renderer spends its time (`--cost-by-depth`): both path tracers (Mitsuba with `ldsampler`,
Prism uniform) at each given max_depth and the first --spp, interleaved, median of --reps; nanoseconds per sample
and thread, and what each extra depth adds (max_depth 1: camera rays and emitters seen directly; 2: plus direct
lighting and the first bounce ray; ...). Output mitsuba_cost_by_depth.md:

    python3 benches/peer/mitsuba_compare.py --scenes cornell --spp 64 --reps 3 --cost-by-depth 1,2,3,8
"""
import argparse
import math
import os
import re
import shlex
import shutil
import sys
import tempfile
import time
from pathlib import Path

# The set-up (system Python) and the ratios and tables live beside this file.
from equal_error import read_raw, summarize
from peer_setup import PEER, PGO_BINARY, PLAIN_BINARY, REFS, ROOT, bootstrap, log, run

# Mitsuba 3's samplers the harness can time, and those of them `--peer-rr-depth` applies to (the low-discrepancy ones).
PEER_SAMPLERS = ("ldsampler", "independent", "multijitter", "stratified", "orthogonal")
RR_SAMPLERS = ("ldsampler", "multijitter")

# name: (Prism scene, path max_depth of the reference (Mitsuba semantics: segments; -1 unlimited))
SCENES = {
    "cornell": ("scenes/cornell_box.ron", 8),
    "cornell_caustic": ("scenes/cornell_caustic.ron", 12),
    "cornell_rough": ("scenes/cornell_rough.ron", 8),
    "dof": ("scenes/dof.ron", 8),
    "textured": ("scenes/textured.ron", 8),
    "furnace": ("scenes/furnace.ron", -1),
}


# ---------------------------------------------------------------- Mitsuba (inside the venv)

def mitsuba_dict(name, mi):
    """The Mitsuba 3.9.1 dict of ../shared/refs/NAME.md (transcribed from its "Mitsuba dict" section; `cornell`
    and `furnace` from mitsuba_scenes.py there)."""
    sys.path.insert(0, str(REFS))
    import mitsuba_scenes  # noqa: E402 (needs the variant set)
    T = mi.ScalarTransform4f
    if name in ("cornell", "furnace"):
        return mitsuba_scenes.build(name)
    d = mi.cornell_box()
    d["sensor"]["film"]["rfilter"] = {"type": "box"}
    if name == "cornell_caustic":
        d["integrator"] = {"type": "path", "max_depth": 12}
        del d["small-box"], d["large-box"]
        d["glass-sphere"] = {"type": "sphere", "center": [0.1, -0.6, 0.1], "radius": 0.4,
                             "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}}
    elif name == "cornell_rough":
        d["integrator"] = {"type": "path", "max_depth": 8}
        del d["small-box"], d["large-box"]
        d["conductor-sphere"] = {
            "type": "sphere", "center": [-0.42, -0.65, -0.35], "radius": 0.35,
            "bsdf": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.2, "material": "Au"}}
        d["dielectric-sphere"] = {
            "type": "sphere", "center": [0.42, -0.65, 0.30], "radius": 0.35,
            "bsdf": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.15, "int_ior": 1.5,
                     "ext_ior": 1.0}}
    elif name == "dof":
        d["integrator"] = {"type": "path", "max_depth": 8}
        d["sensor"]["type"] = "thinlens"
        d["sensor"]["aperture_radius"] = 0.06
        d["sensor"]["focus_distance"] = 3.4
    elif name == "textured":
        tex = str(REFS / "textures")
        c = d
        d = {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 8},
            "sensor": c["sensor"], "white": c["white"], "light": c["light"],
            "env": {"type": "constant", "radiance": {"type": "rgb", "value": [0.05, 0.05, 0.05]}},
            "back": {
                "type": "rectangle", "to_world": T().translate([0.0, 0.0, -1.0]),
                "bsdf": {"type": "diffuse",
                         "reflectance": {"type": "bitmap", "filename": f"{tex}/checker_f.png",
                                         "filter_type": "bilinear", "wrap_mode": "repeat", "raw": False}}},
            "floor": {
                "type": "rectangle", "to_world": T().translate([0.0, -1.0, 0.0]).rotate([1, 0, 0], -90),
                "bsdf": {"type": "normalmap",
                         "normalmap": {"type": "bitmap", "filename": f"{tex}/bumps_u.png",
                                       "filter_type": "bilinear", "wrap_mode": "repeat", "raw": True},
                         "flip_invalid_normals": True, "use_shadowing_function": False,
                         "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}}}},
        }
    else:
        raise KeyError(name)
    return d


class Mitsuba:
    """One scene loaded once per sampler; renders timed as curves2.md describes."""

    def __init__(self, name, threads, samplers=("ldsampler", "independent"), rr_depths=()):
        """`rr_depths` apply to the low-discrepancy samplers among `samplers` (scenes `SAMPLER-rrD`)."""
        import drjit as dr
        import mitsuba as mi
        import numpy as np
        mi.set_variant("llvm_ad_rgb")
        dr.set_thread_count(threads)
        self.mi, self.np = mi, np
        self.scenes = {}
        for sampler in samplers:
            d = mitsuba_dict(name, mi)
            d["sensor"]["sampler"] = {"type": sampler, "sample_count": 4}
            self.scenes[sampler] = mi.load_dict(d)
        for sampler in (s for s in samplers if s in RR_SAMPLERS):
            for rr in rr_depths:  # the path tracer's Russian roulette from depth `rr` (its default: 5)
                d = mitsuba_dict(name, mi)
                d["sensor"]["sampler"] = {"type": sampler, "sample_count": 4}
                d["integrator"]["rr_depth"] = rr
                self.scenes[f"{sampler}-rr{rr}"] = mi.load_dict(d)
        self.version = f"Mitsuba {mi.__version__} llvm_ad_rgb, {dr.thread_count()} threads"

    def render(self, sampler, spp, seed):
        t0 = time.perf_counter()
        img = self.np.array(self.mi.render(self.scenes[sampler], spp=spp, seed=seed))
        return time.perf_counter() - t0, img


# ---------------------------------------------------------------- Prism, errors, interpolation

def fresh_copy(binary):
    """A new copy of `binary` under target/peer/tmp, to run once and delete: the same bytes run from different files
    differed by up to 15% (the page cache's placement of the executable; docs/decisions/0029-measure-interleaved-fresh-copies.md), so every Prism run
    executes a fresh copy and that bias becomes noise that the repetitions average, instead of a constant offset."""
    tmp = PEER / "tmp"
    tmp.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix="prism-", suffix=".bin", dir=tmp)
    os.close(fd)
    shutil.copy2(binary, name)
    return Path(name)


def prism_render(prism, scene, spp, seed, threads, extra, out):
    copy = fresh_copy(prism)
    try:
        return prism_render_with(copy, scene, spp, seed, threads, extra, out)
    finally:
        copy.unlink()


def prism_render_with(prism, scene, spp, seed, threads, extra, out):
    cmd = [str(prism), "render", str(scene), "--spp", str(spp), "--threads", str(threads), "--seed", str(seed),
           "--checkpoint", "0", "-o", str(out), *extra]
    t0 = time.perf_counter()
    r = run(cmd, cwd=ROOT)
    wall = time.perf_counter() - t0
    m = re.search(r" in ([0-9.]+) s render", r.stderr)
    if not m:
        sys.exit(f"error: no render time in the output of {' '.join(cmd)}:\n{r.stderr}")
    return float(m.group(1)), wall


def read_exr(path):
    import mitsuba as mi
    import numpy as np
    a = np.array(mi.Bitmap(str(path)), dtype=np.float64)
    return a[..., :3] if a.ndim == 3 else a


def rmse(img, ref):
    import numpy as np
    if img.shape != ref.shape:
        sys.exit(f"error: image {img.shape} and reference {ref.shape} differ in size")
    return float(np.sqrt(np.mean((np.asarray(img, dtype=np.float64) - ref) ** 2)))


# ---------------------------------------------------------------- the measurement

def parse_args():
    ap = argparse.ArgumentParser(description="Prism vs Mitsuba 3 at equal error (see the file's header).")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated reference names (default: all)")
    ap.add_argument("--spp", default="16,64,256", help="spp list for both renderers (ldsampler: 4^k only)")
    ap.add_argument("--prism-extra-spp", default="auto",
                    help="extra spp for Prism only, to bracket the peer's errors closely (default: 4x the largest "
                         "--spp, and 5/8 and 3/4 of each; '' for none)")
    ap.add_argument("--reps", type=int, default=3, help="repetitions (default 3)")
    ap.add_argument("--threads", type=int, default=2, help="threads for both renderers (default 2)")
    ap.add_argument("--prism", action="append", metavar="LABEL=ARGS",
                    help="a Prism configuration: a label and extra `prism render` arguments, `{max_depth}` replaced "
                         "by the reference's (repeatable; default: the path tracer with uniform and with adaptive "
                         "sampling, \"envlight=--integrator 'envlight(max_depth: {max_depth})'\" and "
                         "\"adaptive=--integrator 'envlight(max_depth: {max_depth})' --adaptive\"; ARGS is split as "
                         "a shell would)")
    ap.add_argument("--peer-samplers", default="ldsampler,independent,multijitter", metavar="S1,S2,...",
                    help="Mitsuba's samplers to time (default ldsampler,independent,multijitter; also stratified, "
                         "orthogonal); each skips the spp it would round")
    ap.add_argument("--peer-rr-depth", default="", metavar="D1,D2,...",
                    help="also time Mitsuba's low-discrepancy samplers (ldsampler, multijitter) with the path "
                         "tracer's rr_depth set to each of these (its default is 5; Prism's envlight plays roulette "
                         "from the first bounce), as further peers `mitsuba-SAMPLER-rrD`: the peer at its best "
                         "Russian roulette, not only at its default")
    ap.add_argument("--ppm", action="store_true",
                    help="also Prism's `ppm` on the caustic and rough boxes, cornell_caustic and cornell_rough "
                         "(--integrator \"ppm(max_depth: D)\" with the reference's max_depth)")
    ap.add_argument("--cost-by-depth", metavar="D1,D2,...", default="",
                    help="instead of the equal-error comparison: time both renderers' path tracers (Mitsuba with "
                         "ldsampler) with each max_depth at the first --spp, interleaved, and print the cost per "
                         "sample and thread (where each renderer spends its time along a path), e.g. 1,2,3,8")
    ap.add_argument("--pgo", action="store_true",
                    help="also run every Prism configuration with the profile-guided binary (benches/pgo/build.sh, "
                         "target/pgo/prism; labels ending in -pgo); with --cost-by-depth, time that binary instead")
    ap.add_argument("--summarize", type=Path, metavar="RAW_CSV",
                    help="render nothing: summarize the rows of an earlier run's mitsuba_compare_raw.csv again (its "
                         "tables, bootstrap intervals included) into --out")
    ap.add_argument("-o", "--out", type=Path, default=PEER / "results", help="output directory")
    a = ap.parse_args()
    a.scenes = [s for s in a.scenes.split(",") if s]
    for s in a.scenes:
        if s not in SCENES:
            sys.exit(f"error: unknown scene '{s}' (known: {', '.join(SCENES)})")
    try:
        a.spp = sorted({int(s) for s in a.spp.split(",") if s})
        extra = a.prism_extra_spp
        if extra == "auto":
            between = {max(1, round(s * f)) for s in a.spp for f in (0.625, 0.75)}
            a.prism_extra_spp = sorted(({4 * a.spp[-1]} | between) - set(a.spp))
        else:
            a.prism_extra_spp = sorted({int(s) for s in extra.split(",") if s})
    except (ValueError, IndexError):
        sys.exit("error: --spp and --prism-extra-spp take comma-separated positive integers")
    if not a.spp or min(a.spp) < 1 or a.reps < 1 or a.threads < 1:
        sys.exit("error: --spp, --reps and --threads must be positive")
    try:
        a.cost_by_depth = [int(d) for d in a.cost_by_depth.split(",") if d]
    except ValueError:
        sys.exit("error: --cost-by-depth takes comma-separated integers (max_depth values, -1 unlimited)")
    try:
        a.peer_rr_depth = [int(d) for d in a.peer_rr_depth.split(",") if d]
    except ValueError:
        sys.exit("error: --peer-rr-depth takes comma-separated positive integers")
    if any(d < 1 for d in a.peer_rr_depth):
        sys.exit("error: --peer-rr-depth: each rr_depth must be at least 1")
    a.peer_samplers = list(dict.fromkeys(x for x in a.peer_samplers.split(",") if x))
    for x in a.peer_samplers:
        if x not in PEER_SAMPLERS:
            sys.exit(f"error: --peer-samplers: unknown sampler '{x}' (known: {', '.join(PEER_SAMPLERS)})")
    if not a.peer_samplers:
        sys.exit("error: --peer-samplers: give at least one sampler")
    if any(d == 0 or d < -1 for d in a.cost_by_depth):
        sys.exit("error: --cost-by-depth: each max_depth must be -1 (unlimited) or at least 1")
    if a.cost_by_depth and not is_ld(a.spp[0]):
        sys.exit(f"error: --cost-by-depth renders at the first --spp, {a.spp[0]}, which ldsampler does not take (4^k)")
    configs = a.prism or [
        "envlight=--integrator 'envlight(max_depth: {max_depth})'",
        "adaptive=--integrator 'envlight(max_depth: {max_depth})' --adaptive",
    ]
    a.configs = []
    for c in configs:
        label, _, args = c.partition("=")
        if not label:
            sys.exit(f"error: --prism '{c}': expected LABEL=ARGS")
        a.configs.append((label, args, PLAIN_BINARY))
        if a.pgo:
            a.configs.append((f"{label}-pgo", args, PGO_BINARY))
    return a


def is_ld(spp):
    """ldsampler takes squares of powers of two >= 4, i.e. 4^k."""
    n = spp
    while n > 1 and n % 4 == 0:
        n //= 4
    return spp >= 4 and n == 1


def takes(sampler, spp):
    """Whether Mitsuba's `sampler` (a scene key, `-rrD` suffix allowed) renders `spp` samples as asked: ldsampler
    4^k, multijitter and stratified squares, orthogonal squares of primes; other counts it rounds, so they are
    skipped."""
    base = sampler.split("-rr")[0]
    root = math.isqrt(spp)
    if base == "ldsampler":
        return is_ld(spp)
    if base in ("multijitter", "stratified"):
        return root * root == spp
    if base == "orthogonal":
        return root * root == spp and root > 1 and all(root % k for k in range(2, math.isqrt(root) + 1))
    return True


def measure(a):
    import numpy as np
    a.out.mkdir(parents=True, exist_ok=True)
    tmp = PEER / "tmp"
    tmp.mkdir(exist_ok=True)
    rows = []  # dicts: scene, renderer, spp, rep, seed, seconds, wall, rmse, msps
    versions = set()
    for name in a.scenes:
        scene_file, max_depth = SCENES[name]
        if not (ROOT / scene_file).exists():
            log(f"{name}: skipped: no Prism scene {scene_file} yet")
            continue
        ref = read_exr(REFS / f"{name}.exr")
        h, w = ref.shape[:2]
        mts = Mitsuba(name, a.threads, samplers=a.peer_samplers, rr_depths=a.peer_rr_depth)
        versions.add(mts.version)
        configs = [(lb, shlex.split(args.replace("{max_depth}", str(max_depth))), binary)
                   for lb, args, binary in a.configs]
        if a.ppm and name in ("cornell_caustic", "cornell_rough"):
            ppm = ["--integrator", f"ppm(max_depth: {max_depth})"]
            configs.append(("ppm", ppm, PLAIN_BINARY))
            if a.pgo:
                configs.append(("ppm-pgo", ppm, PGO_BINARY))
        peers = [(f"mitsuba-{s}", s) for s in mts.scenes]
        for sampler in a.peer_samplers:
            skipped = [spp for spp in a.spp if not takes(sampler, spp)]
            if skipped:
                log(f"note: Mitsuba's {sampler} skips spp {skipped} (it would round them)")
        log(f"{name}: warming up Mitsuba's JIT ...")
        for label, sampler in peers:
            for spp in a.spp:
                if takes(sampler, spp):
                    mts.render(sampler, spp, 0)
        for binary in dict.fromkeys(c[2] for c in configs):
            prism_render(binary, ROOT / scene_file, min(a.spp), 0, a.threads, configs[0][1], tmp / "warmup.exr")
        prism_spp = sorted(set(a.spp) | set(a.prism_extra_spp))
        for rep in range(a.reps):
            for i, spp in enumerate(prism_spp):
                seed = 1 + rep * 1000 + i
                jobs = []
                if spp in a.spp:
                    jobs += [(lb, s, None) for lb, s in peers if takes(s, spp)]
                jobs += [(f"prism-{lb}", args, binary) for lb, args, binary in configs]
                if (rep + i) % 2:
                    jobs.reverse()
                for label, what, binary in jobs:
                    if label.startswith("mitsuba"):
                        secs, img = mts.render(what, spp, seed)
                        wall = secs
                    else:
                        out = tmp / f"{name}.exr"
                        secs, wall = prism_render(binary, ROOT / scene_file, spp, seed, a.threads, what, out)
                        img = read_exr(out)
                    e = rmse(np.asarray(img)[..., :3], ref)
                    rows.append(dict(scene=name, renderer=label, spp=spp, rep=rep, seed=seed, seconds=secs,
                                     wall=wall, rmse=e, msps=spp * w * h / secs / 1e6))
                    log(f"{name} rep {rep + 1}/{a.reps} {spp:5d} spp {label:22s} {secs:8.3f} s  RMSE {e:.5f}")
        del mts
    return rows, versions


def cost_by_depth(a):
    """Nanoseconds per sample and thread of each path tracer with each max_depth: where along a path the time goes."""
    import numpy as np
    prism = PGO_BINARY if a.pgo else PLAIN_BINARY
    a.out.mkdir(parents=True, exist_ok=True)
    tmp = PEER / "tmp"
    tmp.mkdir(exist_ok=True)
    spp = a.spp[0]
    md = [f"Cost per sample and thread by max_depth, {spp} spp, {a.threads} threads, median of {a.reps} interleaved "
          "repetitions (Mitsuba `ldsampler`, Prism `envlight`, uniform sampling).", "",
          "| scene | max_depth | Mitsuba ns | Prism ns | Prism / Mitsuba | Mitsuba ns added by this depth | Prism ns added |",
          "|---|---:|---:|---:|---:|---:|---:|"]
    import mitsuba as mi
    for name in a.scenes:
        scene_file, _ = SCENES[name]
        if not (ROOT / scene_file).exists():
            log(f"{name}: skipped: no Prism scene {scene_file} yet")
            continue
        h, w = read_exr(REFS / f"{name}.exr").shape[:2]
        mts = Mitsuba(name, a.threads, samplers=())  # one scene per depth is loaded below
        prev = None
        for depth in a.cost_by_depth:
            d = mitsuba_dict(name, mi)
            d["integrator"] = {"type": "path", "max_depth": depth}
            d["sensor"]["sampler"] = {"type": "ldsampler", "sample_count": 4}
            mts.scenes["ldsampler"] = mi.load_dict(d)
            mts.render("ldsampler", spp, 0)  # JIT warm-up
            args = ["--integrator", f"envlight(max_depth: {depth})"]
            prism_render(prism, ROOT / scene_file, spp, 0, a.threads, args, tmp / "warmup.exr")
            times = {"mitsuba": [], "prism": []}
            for rep in range(a.reps):
                order = ["mitsuba", "prism"] if rep % 2 == 0 else ["prism", "mitsuba"]
                for who in order:
                    if who == "mitsuba":
                        times[who].append(mts.render("ldsampler", spp, 1 + rep)[0])
                    else:
                        times[who].append(prism_render(prism, ROOT / scene_file, spp, 1 + rep, a.threads, args,
                                                       tmp / "depth.exr")[0])
            ns = {k: float(np.median(v)) / (w * h * spp) * 1e9 * a.threads for k, v in times.items()}
            added = ("", "") if prev is None else (f"{ns['mitsuba'] - prev['mitsuba']:.0f}",
                                                   f"{ns['prism'] - prev['prism']:.0f}")
            md.append(f"| {name} | {depth} | {ns['mitsuba']:.0f} | {ns['prism']:.0f} | "
                      f"{ns['prism'] / ns['mitsuba']:.2f} | {added[0]} | {added[1]} |")
            log(md[-1])
            prev = ns
    text = "\n".join(md)
    (a.out / "mitsuba_cost_by_depth.md").write_text(text + "\n")
    print(text)
    log(f"wrote {a.out}/mitsuba_cost_by_depth.md")


def main():
    a = parse_args()
    if a.summarize:
        rows = read_raw(a.summarize)
        a.out.mkdir(parents=True, exist_ok=True)
        if a.out.resolve() == a.summarize.resolve().parent:
            sys.exit(f"error: --summarize would overwrite {a.summarize}; give another --out")
        summarize(a, rows, {f"Mitsuba (rows of {a.summarize})"})
        return
    if os.environ.get("PRISM_PEER_IN_VENV") != "1":
        bootstrap(Path(__file__).resolve())  # does not return
    if a.cost_by_depth:
        cost_by_depth(a)
        return
    t0 = time.time()
    rows, versions = measure(a)
    if not rows:
        sys.exit("error: nothing measured (no scene had a Prism scene file)")
    summarize(a, rows, versions)
    log(f"measured in {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
