"""Mitsuba 3's `roughplastic` BRDF at fixed directions, the reference of tests/microfacet.rs's rough-plastic test.

Writes mitsuba_roughplastic.csv beside this file: alpha, int_ior, spec (specular_reflectance, 0 isolates the
diffuse base), wi and wo (local frame, z the normal) and the BRDF f(wi, wo) per RGB channel (Mitsuba's eval
divided by cos(theta_o)). Run with `pip install mitsuba` (scalar_rgb variant): python3 mitsuba_roughplastic.py
"""

import csv
import math
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")

DIFFUSE = [0.8, 0.5, 0.2]


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def main():
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mitsuba_roughplastic.csv")
    pairs = [((0, 0), (0, 0)), ((30, 0), (30, 180)), ((60, 0), (45, 90)), ((80, 0), (10, 200)), ((45, 0), (75, 30))]
    rows = []
    for alpha in [0.05, 0.3, 0.7]:
        for ior in [1.33, 1.5, 2.0]:
            for spec in [0.0, 1.0]:
                bsdf = mi.load_dict({
                    "type": "roughplastic",
                    "distribution": "ggx",
                    "alpha": alpha,
                    "int_ior": ior,
                    "ext_ior": 1.0,
                    "nonlinear": False,
                    "diffuse_reflectance": {"type": "rgb", "value": DIFFUSE},
                    "specular_reflectance": {"type": "rgb", "value": [spec] * 3},
                })
                for (ti, pi), (to, po) in pairs:
                    si = mi.SurfaceInteraction3f()
                    si.n = mi.Normal3f(0, 0, 1)
                    si.sh_frame = mi.Frame3f(si.n)
                    wi, wo = direction(ti, pi), direction(to, po)
                    si.wi = mi.Vector3f(wi)
                    f = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(wo))
                    c = wo[2]
                    rows.append([alpha, ior, spec, *wi, *wo, f[0] / c, f[1] / c, f[2] / c])
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["alpha", "int_ior", "spec", "wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z", "f_r", "f_g", "f_b"])
        for r in rows:
            w.writerow([f"{v:.9g}" for v in r])


if __name__ == "__main__":
    main()
