#!/usr/bin/env python3
"""Writes the generated example scenes of scenes/ (format: /work/shared/scene-format.md).

Deterministic: a fixed seed per scene and numbers rounded to 3 decimals, so running it again
reproduces the committed files byte for byte. scenes/small-2d.json is hand-written, not generated.

    python3 scripts/make_scenes.py            # rewrites fig1-2d.json, walk-2d.json and spheres-3d.json
    python3 scripts/make_scenes.py --check    # exit 1 if the committed files differ from the output
"""
import json
import math
import random
import sys
from pathlib import Path

SCENES = Path(__file__).resolve().parent.parent / "scenes"


def r3(x):
    return round(x, 3)


def convex_polygon(rng, cx, cy, radius, n):
    """n points on a circle at sorted random angles: convex, counter-clockwise, and with
    gaps of at least 0.4 rad so that no edge is degenerate."""
    while True:
        angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(n))
        gaps = [(angles[(i + 1) % n] - angles[i]) % (2 * math.pi) for i in range(n)]
        if min(gaps) > 0.4 and max(gaps) < math.pi * 0.9:
            return [[r3(cx + radius * math.cos(a)), r3(cy + radius * math.sin(a))] for a in angles]


def far_from(points, x, y, clearance):
    return all(math.hypot(x - px, y - py) >= clearance for px, py in points)


def scatter(rng, size, counts, keep_clear, clearance, max_speed):
    """Objects spread uniformly over a size x size grid: moving circles, static boxes and static
    polygons, none starting within `clearance` of the points in keep_clear (camera positions)."""
    objects = []
    next_id = 1

    def place(margin):
        while True:
            x, y = rng.uniform(margin, size - margin), rng.uniform(margin, size - margin)
            if far_from(keep_clear, x, y, clearance + margin):
                return x, y

    for _ in range(counts["circles"]):
        r = rng.uniform(1.5, 4.0)
        x, y = place(r)
        speed = rng.uniform(0.1, max_speed)
        heading = rng.uniform(0, 2 * math.pi)
        objects.append({"id": next_id, "shape": "circle", "center": [r3(x), r3(y)], "radius": r3(r),
                        "velocity": [r3(speed * math.cos(heading)), r3(speed * math.sin(heading))]})
        next_id += 1
    for _ in range(counts["boxes"]):
        w, h = rng.uniform(3, 14), rng.uniform(3, 14)
        x, y = place(max(w, h) / 2)
        objects.append({"id": next_id, "shape": "box", "min": [r3(x - w / 2), r3(y - h / 2)],
                        "max": [r3(x + w / 2), r3(y + h / 2)], "static": True})
        next_id += 1
    for _ in range(counts["polygons"]):
        r = rng.uniform(3, 8)
        x, y = place(r)
        objects.append({"id": next_id, "shape": "polygon",
                        "points": convex_polygon(rng, x, y, r, rng.randint(3, 7)), "static": True})
        next_id += 1
    return objects


def dump(scene):
    """JSON with one object (and one camera pose) per line: readable and diff-friendly."""
    lines = ["{"]
    lines.append(f'  "dimensions": {scene["dimensions"]},')
    lines.append(f'  "grid": {json.dumps(scene["grid"])},')
    lines.append(f'  "camera": {json.dumps(scene["camera"])},')
    if "camera_path" in scene:
        lines.append('  "camera_path": [')
        poses = [f"    {json.dumps(p)}" for p in scene["camera_path"]]
        lines.append(",\n".join(poses))
        lines.append("  ],")
    lines.append('  "objects": [')
    lines.append(",\n".join(f"    {json.dumps(o)}" for o in scene["objects"]))
    lines.append("  ]")
    lines.append("}")
    return "\n".join(lines) + "\n"


def fig1():
    """The paper's Figure 1 setting: a 256 x 256 grid, 300 objects, a 90 degree view. Dense enough
    that most of the view region is hidden behind the first few objects."""
    rng = random.Random(2002)
    camera = {"position": [12.5, 128.5], "direction": [1, 0.15], "fov_deg": 90}
    objects = scatter(rng, 256, {"circles": 200, "boxes": 60, "polygons": 40},
                      keep_clear=[(12.5, 128.5)], clearance=8, max_speed=1.0)
    return {"dimensions": 2, "grid": {"origin": [0, 0], "voxel_size": 1.0, "resolution": [256, 256]},
            "camera": camera, "objects": objects}


def walk():
    """A camera walking 60 frames along an arc through a 128 x 128 grid of moving and static
    objects, turning as it goes. It moves under one voxel per frame on each axis (the 8-connected
    camera path the TBV discretization assumes), and the objects keep clear of its path at frame 0."""
    rng = random.Random(4242)
    path = []
    for t in range(60):
        # A quarter-circle arc of radius 30 below the grid centre: 47 units in 59 steps, so each step
        # moves under 0.8 on each axis.
        a = math.pi * (1.25 + 0.5 * t / 59)
        x, y = 64 + 30 * math.cos(a), 64 + 30 * math.sin(a)
        heading = a + math.pi / 2 + 0.5 * math.sin(t / 9)  # along the arc, looking around
        path.append({"position": [r3(x), r3(y)], "direction": [r3(math.cos(heading)), r3(math.sin(heading))]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 100, "far": 90}
    objects = scatter(rng, 128, {"circles": 45, "boxes": 20, "polygons": 15},
                      keep_clear=[tuple(p["position"]) for p in path], clearance=4, max_speed=0.8)
    return {"dimensions": 2, "grid": {"origin": [0, 0], "voxel_size": 1.0, "resolution": [128, 128]},
            "camera": camera, "camera_path": path, "objects": objects}


def spheres3d():
    """The paper's section 6 scene, scaled down to a file worth reading: 1,000 spheres of varying size
    in clusters, most of them moving, on a 50 x 30 x 50 grid; the camera looks along +z into it."""
    rng = random.Random(6006)
    res = [50, 30, 50]
    clusters = [(rng.uniform(8, 42), rng.uniform(6, 24), rng.uniform(14, 46)) for _ in range(12)]
    objects = []
    for i in range(1000):
        cx, cy, cz = clusters[i % len(clusters)]
        r = rng.uniform(1.0, 2.6)
        c = [min(max(v + rng.gauss(0, 5), r), hi - r) for v, hi in zip((cx, cy, cz), res)]
        o = {"id": i + 1, "shape": "sphere", "center": [r3(v) for v in c], "radius": r3(r)}
        if rng.random() < 0.8:
            v = [rng.uniform(-0.3, 0.3) for _ in range(3)]
            o["velocity"] = [r3(x) for x in v]
        objects.append(o)
    camera = {"position": [25.3, 15.2, 1.7], "direction": [0, 0, 1], "fov_deg": 60, "aspect": 1.5}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": res},
            "camera": camera, "objects": objects}


def main():
    check = "--check" in sys.argv[1:]
    stale = []
    for name, build in (("fig1-2d.json", fig1), ("walk-2d.json", walk), ("spheres-3d.json", spheres3d)):
        text = dump(build())
        target = SCENES / name
        if check:
            if not target.exists() or target.read_text() != text:
                stale.append(name)
        else:
            SCENES.mkdir(exist_ok=True)
            target.write_text(text)
            print(f"wrote {target}")
    if stale:
        print("out of date: " + ", ".join(stale), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
