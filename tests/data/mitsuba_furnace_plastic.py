"""Mitsuba 3's render of a nearly smooth plastic sphere in a white furnace, the reference of tests/near_specular.rs.

A sphere of radius 1 at the origin, `roughplastic` with GGX alpha 0.001, int_ior 1.5, ext_ior 1, diffuse
(0.2, 0.5, 0.8), seen from (0, 0, 4) with a 40 degree field of view at 64 x 64 pixels, inside a constant
environment of radiance 1; Mitsuba's path tracer (MIS, unlimited depth). Prints the mean RGB over the pixels fully
on the sphere (centre within r - 0.75 px of the image centre, r = tan(asin(1/4)) / tan(20 deg) * 32 px) and writes it
to mitsuba_furnace_plastic.csv beside this file. Run with `pip install mitsuba numpy` (scalar_rgb variant):
python3 mitsuba_furnace_plastic.py
"""

import csv
import math
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

SIZE, SPP = 64, 4096


def main():
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": {
            "type": "perspective",
            "fov": 40,
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": SIZE, "height": SIZE, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": SPP},
        },
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": [1, 1, 1]}},
        "sphere": {
            "type": "sphere",
            "bsdf": {
                "type": "roughplastic",
                "distribution": "ggx",
                "alpha": 0.001,
                "int_ior": 1.5,
                "ext_ior": 1.0,
                "nonlinear": False,
                "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.8]},
            },
        },
    })
    img = np.array(mi.render(scene), dtype=np.float64)[:, :, :3]
    r = math.tan(math.asin(0.25)) / math.tan(math.radians(20)) * SIZE / 2
    yy, xx = np.mgrid[0:SIZE, 0:SIZE]
    on = np.hypot(xx + 0.5 - SIZE / 2, yy + 0.5 - SIZE / 2) <= r - 0.75
    mean = img[on].mean(axis=0)
    # The standard error of the mean from the spread of per-pixel values (each pixel has SPP samples).
    print("pixels", int(on.sum()), "mean", mean)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mitsuba_furnace_plastic.csv")
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pixels", "spp", "r", "g", "b"])
        w.writerow([int(on.sum()), SPP, *[f"{v:.6f}" for v in mean]])


if __name__ == "__main__":
    main()
