"""The harness's arithmetic and tables: the time at which Prism's (time, error) curve reaches the peer's error,
the equal-error ratio with its bootstrap interval and per-repetition range, the peer at its best, and the Markdown
and CSV summaries of a run (or of an earlier run's raw CSV, `--summarize`). See mitsuba_compare.py.
"""
import json
import statistics
import sys

from peer_setup import REFS, log


def time_to_error(points, target):
    """Time at which the (time, error) curve reaches `target`, interpolated in log-log between the first pair of
    points (in time order) that brackets it, as crates/lab/src/converge.rs::time_to_error; outside the curve's range,
    extrapolated from the nearest segment. Returns (time, extrapolated) or (None, False)."""
    import math
    pts = sorted((t, e) for t, e in points if t > 0 and e > 0)
    if not pts or not target > 0:
        return None, False

    def along(p0, p1):
        (t0, e0), (t1, e1) = p0, p1
        if e0 == e1:
            return t0
        a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
        return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))

    for p0, p1 in zip(pts, pts[1:]):
        if p0[1] >= target >= p1[1]:
            return along(p0, p1), False
    if len(pts) < 2:
        return None, False
    seg = (pts[-2], pts[-1]) if target < pts[-1][1] else (pts[0], pts[1])
    if seg[1][1] >= seg[0][1]:  # the segment does not fall: no meaningful extrapolation
        return None, False
    return along(*seg), True


def noise_of(name):
    j = REFS / f"{name}.json"
    return json.loads(j.read_text()).get("noise_rmse_estimate") if j.exists() else None


def corrected(e, noise):
    return (max(e * e - noise * noise, (0.05 * e) ** 2)) ** 0.5


def spread(vals):
    return f"{statistics.median(vals):.3g} ({min(vals):.3g}-{max(vals):.3g})" if vals else "-"


def read_raw(path):
    """The rows of a mitsuba_compare_raw.csv, as `measure` returns them."""
    import csv
    try:
        with open(path, newline="") as f:
            return [dict(scene=r["scene"], renderer=r["renderer"], spp=int(r["spp"]), rep=int(r["rep"]),
                         seed=int(r["seed"]), seconds=float(r["seconds"]), wall=float(r["wall_seconds"]),
                         rmse=float(r["rmse"]), msps=float(r["msamples_per_s"])) for r in csv.DictReader(f)]
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f"error: {path}: not a mitsuba_compare_raw.csv ({e})")


def summarize(a, rows, versions):
    raw = ["scene,renderer,spp,rep,seed,seconds,wall_seconds,rmse,msamples_per_s"]
    raw += [f"{r['scene']},{r['renderer']},{r['spp']},{r['rep']},{r['seed']},{r['seconds']:.4f},{r['wall']:.4f},"
            f"{r['rmse']:.6g},{r['msps']:.4f}" for r in rows]
    (a.out / "mitsuba_compare_raw.csv").write_text("\n".join(raw) + "\n")
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    md = [f"Prism vs {', '.join(sorted(versions))}; Prism {a.threads} threads; {a.reps} repetition(s), "
          f"interleaved; time: median (min-max), RMSE: mean over repetitions.", "",
          "| scene | renderer | spp | time s | Prism wall s | RMSE | Msamples/s |", "|---|---|---:|---:|---:|---:|---:|"]
    curves = {}  # (scene, renderer) -> {spp: [rows]}
    for r in rows:
        curves.setdefault((r["scene"], r["renderer"]), {}).setdefault(r["spp"], []).append(r)
    for (scene, rend), by_spp in curves.items():
        for spp, rs in sorted(by_spp.items()):
            t = [x["seconds"] for x in rs]
            wall = spread([x["wall"] for x in rs]) if rend.startswith("prism") else ""
            md.append(f"| {scene} | {rend} | {spp} | {spread(t)} | {wall} | "
                      f"{statistics.mean(x['rmse'] for x in rs):.5f} | "
                      f"{statistics.median(x['msps'] for x in rs):.3f} |")
    md += ["", "Equal-error time ratio, Prism / Mitsuba (< 1: Prism reaches the peer's error sooner): the peer's "
           "mean RMSE at its spp is the target; Prism's time to it interpolated in log-log (`~`: extrapolated). "
           "Bootstrap 95%: the headline ratio recomputed over repetitions drawn with replacement (each draw keeps a "
           "repetition's Prism and peer renders together, as they ran side by side). Per-repetition range: min-max of "
           "the ratio from each repetition's own points alone (it need not contain the headline, which interpolates "
           "the pooled points).", "",
           "| scene | Prism | peer | peer spp | target RMSE | peer s | Prism s | ratio [bootstrap 95%] | "
           "per-repetition range | ratio, Prism wall time | ratio, reference noise removed |",
           "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    ratios_csv = ["scene,prism,peer,peer_spp,target_rmse,peer_seconds,prism_seconds,ratio,ratio_boot_lo,"
                  "ratio_boot_hi,ratio_min,ratio_max,ratio_wall,ratio_noise_corrected,extrapolated"]
    found = []  # (scene, prism, peer, spp, ratio, bootstrap interval or None)
    for scene in scenes:
        noise = noise_of(scene)
        prisms = [k[1] for k in curves if k[0] == scene and k[1].startswith("prism")]
        peers = sorted({k[1] for k in curves if k[0] == scene and k[1].startswith("mitsuba")},
                       key=lambda k: (k != "mitsuba-ldsampler", k != "mitsuba-independent", k))
        for peer in peers:
            pc = curves.get((scene, peer), {})
            for p in prisms:
                cc = curves[(scene, p)]
                med = [(statistics.median(x["seconds"] for x in rs), statistics.mean(x["rmse"] for x in rs),
                        statistics.median(x["wall"] for x in rs)) for rs in cc.values()]
                for spp, prs in sorted(pc.items()):
                    target = statistics.mean(x["rmse"] for x in prs)
                    peer_t = statistics.median(x["seconds"] for x in prs)
                    tp, ex = time_to_error([(t, e) for t, e, _ in med], target)
                    tw, exw = time_to_error([(wl, e) for _, e, wl in med], target)
                    per_rep = []
                    for x in prs:
                        mine = [(r["seconds"], r["rmse"]) for rs in cc.values() for r in rs if r["rep"] == x["rep"]]
                        t_rep, _ = time_to_error(mine, x["rmse"])
                        if t_rep:
                            per_rep.append(t_rep / x["seconds"])
                    boot = headline_bootstrap(cc, pc, spp)
                    tn = None
                    if noise:
                        tn, _ = time_to_error([(t, corrected(e, noise)) for t, e, _ in med], corrected(target, noise))
                    mark = "~" if ex else ""
                    ratio = tp / peer_t if tp else None
                    cells = [scene, p, peer, str(spp), f"{target:.5f}", f"{peer_t:.3f}",
                             f"{mark}{tp:.3f}" if tp else "-",
                             f"**{mark}{ratio:.2f}**" + (f" [{boot[0]:.2f}-{boot[1]:.2f}]" if boot else "")
                             if ratio else "-",
                             f"{min(per_rep):.2f}-{max(per_rep):.2f}" if per_rep else "-",
                             f"{'~' if exw else ''}{tw / peer_t:.2f}" if tw else "-",
                             f"{tn / peer_t:.2f}" if tn else "-"]
                    md.append("| " + " | ".join(cells) + " |")
                    if ratio:
                        found.append((scene, p, peer, spp, ratio, boot, ex))
                    ratios_csv.append(",".join([scene, p, peer, str(spp), f"{target:.6g}", f"{peer_t:.4f}",
                                                f"{tp:.4f}" if tp else "", f"{ratio:.4f}" if ratio else "",
                                                f"{boot[0]:.4f}" if boot else "", f"{boot[1]:.4f}" if boot else "",
                                                f"{min(per_rep):.4f}" if per_rep else "",
                                                f"{max(per_rep):.4f}" if per_rep else "",
                                                f"{tw / peer_t:.4f}" if tw else "",
                                                f"{tn / peer_t:.4f}" if tn else "", str(int(ex))]))
    md += best_peer_table(found)
    (a.out / "mitsuba_compare_ratios.csv").write_text("\n".join(ratios_csv) + "\n")
    text = "\n".join(md)
    (a.out / "mitsuba_compare.md").write_text(text + "\n")
    print(text)
    log(f"wrote {a.out}/mitsuba_compare.md, mitsuba_compare_raw.csv, mitsuba_compare_ratios.csv")


def best_peer_table(found):
    """Markdown lines: for each (scene, Prism configuration, spp) the ratio against the Mitsuba configuration Prism does
    worst against (the largest ratio over every peer but `independent`), that is the peer at its best."""
    best = {}
    for scene, p, peer, spp, ratio, boot, ex in found:
        if peer == "mitsuba-independent":
            continue
        key = (scene, p, spp)
        if key not in best or ratio > best[key][1]:
            best[key] = (peer, ratio, boot, ex)
    if not best:
        return []
    md = ["", "Against the peer at its best: for each scene, Prism configuration and spp, the largest ratio over the "
          "Mitsuba configurations timed (every sampler but `independent`, every `rr_depth`), and which one it is.", "",
          "| scene | Prism | spp | ratio [bootstrap 95%] | the peer at its best |", "|---|---|---:|---:|---|"]
    for (scene, p, spp), (peer, ratio, boot, ex) in best.items():
        interval = f" [{boot[0]:.2f}-{boot[1]:.2f}]" if boot else ""
        md.append(f"| {scene} | {p} | {spp} | **{'~' if ex else ''}{ratio:.2f}**{interval} | {peer} |")
    return md


def headline_ratio(cc, pc, spp, reps):
    """The headline equal-error ratio at the peer's `spp` from the repetitions `reps` (a list, repeats allowed):
    Prism's curve of (median time, mean RMSE) per spp and the peer's mean RMSE and median time, all over `reps`."""
    def pick(rs):
        return [r for k in reps for r in rs if r["rep"] == k]
    med = []
    for rs in cc.values():
        chosen = pick(rs)
        if chosen:
            med.append((statistics.median(x["seconds"] for x in chosen), statistics.mean(x["rmse"] for x in chosen)))
    prs = pick(pc.get(spp, []))
    if not prs:
        return None
    tp, _ = time_to_error(med, statistics.mean(x["rmse"] for x in prs))
    return tp / statistics.median(x["seconds"] for x in prs) if tp else None


def headline_bootstrap(cc, pc, spp, draws=2000):
    """A 95% percentile-bootstrap interval of the headline ratio at the peer's `spp`: repetitions drawn with
    replacement (a fixed seed, so the same rows give the same interval); None with fewer than two repetitions."""
    import random
    reps = sorted({r["rep"] for r in pc.get(spp, [])})
    if len(reps) < 2:
        return None
    rng = random.Random(12345)
    vals = sorted(v for v in (headline_ratio(cc, pc, spp, [rng.choice(reps) for _ in reps]) for _ in range(draws))
                  if v is not None)
    if len(vals) < draws // 2:
        return None
    return vals[int(0.025 * (len(vals) - 1))], vals[int(0.975 * (len(vals) - 1))]
