#!/usr/bin/env python3
"""Writes a large 3D scene in the spirit of the paper's section 6 benchmark for `rgvc cull`: N moving
spheres (radius 0.3-3, log-uniform; 8 clusters plus 20 % scattered; speed up to 0.5 unit per frame) in a
100 x 60 x 100 grid of 1-unit voxels, and a camera that walks a Lissajous curve looking along its path
(fov 60, aspect 16:9). The README's `rgvc cull` figures use these files; they are generated, not kept
(each is about 0.6 MB).

    python3 scripts/make_sphere_walk.py OUT.json [--spheres N] [--seed S] [--loop FRAMES | --static]

--loop FRAMES: the camera goes once around its curve in FRAMES frames (100: a camera jumping 2-5 voxels
a frame; 1000: a slowly moving one); --static: no camera_path (the camera of frame 0 for every frame).
"""
import argparse
import json
import math
import random


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--spheres", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--loop", type=int, default=100)
    ap.add_argument("--static", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    res = [100, 60, 100]
    centres = [[rng.uniform(0.1, 0.9) * r for r in res] for _ in range(8)]
    spreads = [rng.uniform(0.03, 0.12) * 60 + 2 for _ in range(8)]
    objects = []
    for i in range(a.spheres):
        radius = math.exp(rng.uniform(math.log(0.3), math.log(3)))
        if rng.random() < 0.2:
            c = [rng.uniform(0, r) for r in res]
        else:
            k = rng.randrange(8)
            c = [centres[k][ax] + (rng.random() + rng.random() + rng.random() - 1.5) * spreads[k] for ax in range(3)]
        c = [min(max(c[ax], radius), res[ax] - radius) for ax in range(3)]
        v = [rng.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in v))
        speed = rng.uniform(0.2, 1.0) * 0.5
        objects.append({"id": i, "shape": "sphere", "center": [round(x, 3) for x in c], "radius": round(radius, 3),
                        "velocity": [round(x / n * speed, 4) for x in v]})
    path = []
    for f in range(max(a.loop, 1)):
        t = 2 * math.pi * f / max(a.loop, 1)
        pos = [50 + 40 * math.sin(t), 30 + 12 * math.sin(3 * t), 50 + 40 * math.sin(2 * t + 0.3)]
        direction = [40 * math.cos(t), -6.0, 80 * math.cos(2 * t + 0.3)]
        path.append({"position": [round(x, 4) for x in pos], "direction": [round(x, 4) for x in direction]})
    scene = {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": res},
             "camera": {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60,
                        "aspect": 16 / 9},
             "objects": objects}
    if not a.static:
        scene["camera_path"] = path
    with open(a.out, "w") as f:
        json.dump(scene, f)


if __name__ == "__main__":
    main()
