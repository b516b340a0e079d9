#!/usr/bin/env python3
"""Writes the generated example scenes of scenes/ (format: /work/shared/scene-format.md).

Deterministic: a fixed seed per scene and numbers rounded to 3 decimals, so running it again
reproduces the committed files byte for byte. scenes/small-2d.json is hand-written, not generated.

    python3 scripts/make_scenes.py            # rewrites every generated scene (the list in SCENE_BUILDERS)
    python3 scripts/make_scenes.py --check    # exit 1 if the committed files differ from the output

The named scenes of issue 12 (used by rgvc_sweep, the apps and the tests; each has a camera_path, so
`rgvc cull SCENE --frames N` runs up to its path's length, and moving objects with velocities):
    city-2d, city-3d        box city blocks, movers in the streets, a camera walking the streets
    clusters-3d             spheres and boxes in bell-shaped clusters, a camera circling them
    maze-2d, maze-3d        an indoor maze (walls; 3D: floor and ceiling too), a camera walking its corridors
    open-2d, open-3d        a sparse open field: few objects far apart, a long walk / flight
    paper-walk-3d           the paper's walkthrough (seed 004 section 6): 5,000 spheres in 100 x 60 x 100,
                            200 moving and 4,800 static, a camera walking a Lissajous loop
Moving objects follow the format's motion (straight lines, reflected at the grid bounds): they may pass
through walls and buildings, which the format allows (visibility is that of the union at each frame).
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


def clear_spot(rng, size, clear, margin):
    """A point drawn uniformly in [margin, size - margin]^2 (x first), drawn again until it is margin + 3
    from every point of `clear` (the camera's path): where open2d and open3d place an object of that
    margin."""
    while True:
        x, y = rng.uniform(margin, size - margin), rng.uniform(margin, size - margin)
        if far_from(clear, x, y, margin + 3):
            return x, y


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


# ---------------------------------------------------------------------------------------------------
# The named scenes of issue 12. Each builder is deterministic (its own random.Random(seed)).


def street_walk(a, b, s):
    """A point on the closed square walk along street centre lines with corners (a, a) and (b, b), at arc
    length s (the same walk rgvc_bench_classes' city scenes use)."""
    side = b - a
    s = s % (4 * side)
    if s < side:
        return a + s, a
    if s < 2 * side:
        return b, a + (s - side)
    if s < 3 * side:
        return b - (s - 2 * side), b
    return a, b - (s - 3 * side)


def overlaps(box, boxes, margin=0.0):
    (x0, y0), (x1, y1) = box
    return any(x0 < bx1 + margin and x1 > bx0 - margin and y0 < by1 + margin and y1 > by0 - margin
               for (bx0, by0), (bx1, by1) in boxes)


def heading2(rng, lo, hi):
    a, v = rng.uniform(0, 2 * math.pi), rng.uniform(lo, hi)
    return [r3(v * math.cos(a)), r3(v * math.sin(a))]


def city2d():
    """128 x 128: 8 x 8 blocks of 12 x 12 with 4-wide streets, each block four abutting 6 x 6 buildings
    (256 static boxes); 200 small circles moving in the streets; the camera walks the streets (0.75 per
    frame, 300 frames, looking a little left and right), fov 90."""
    rng = random.Random(1201)
    objects, blocks = [], []
    for bx in range(8):
        for bz in range(8):
            for q in range(4):
                x0, z0 = 16 * bx + 4 + (6 if q & 1 else 0), 16 * bz + 4 + (6 if q & 2 else 0)
                objects.append({"id": len(objects), "shape": "box", "min": [x0, z0], "max": [x0 + 6, z0 + 6],
                                "static": True})
            blocks.append(((16 * bx + 4, 16 * bz + 4), (16 * bx + 16, 16 * bz + 16)))
    while len(objects) < 256 + 200:
        r = r3(math.exp(rng.uniform(math.log(0.3), math.log(0.8))))
        x, y = rng.uniform(r, 128 - r), rng.uniform(r, 128 - r)
        if overlaps(((x - r, y - r), (x + r, y + r)), blocks):
            continue
        objects.append({"id": len(objects), "shape": "circle", "center": [r3(x), r3(y)], "radius": r,
                        "velocity": heading2(rng, 0.05, 0.3)})
    path = []
    for t in range(300):
        s = 40 + 0.75 * t
        (px, py), (qx, qy) = street_walk(18, 98, s), street_walk(18, 98, s + 4)
        w = 0.2 * math.sin(t / 7)
        dx, dy = qx - px, qy - py
        path.append({"position": [r3(px), r3(py)], "direction": [r3(dx - w * dy), r3(dy + w * dx)]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 90}
    return {"dimensions": 2, "grid": {"origin": [0, 0], "voxel_size": 1.0, "resolution": [128, 128]},
            "camera": camera, "camera_path": path, "objects": objects}


def city3d():
    """96 x 24 x 96: a ground slab and 8 x 8 blocks of four abutting 4.5 x 4.5 buildings 6-20 high
    (streets 3 wide); 300 small spheres moving level in the streets at 1.2-4 above the ground; the camera
    walks the streets at eye height 1.5 (0.75 per frame, 300 frames), fov 60, aspect 16:9."""
    rng = random.Random(1202)
    objects = [{"id": 0, "shape": "box", "min": [0, 0, 0], "max": [96, 1, 96], "static": True}]
    foot = []
    for bx in range(8):
        for bz in range(8):
            for q in range(4):
                x0, z0 = 12 * bx + 3 + (4.5 if q & 1 else 0), 12 * bz + 3 + (4.5 if q & 2 else 0)
                objects.append({"id": len(objects), "shape": "box", "min": [x0, 1, z0],
                                "max": [x0 + 4.5, 1 + rng.randint(6, 20), z0 + 4.5], "static": True})
            foot.append(((12 * bx + 3, 12 * bz + 3), (12 * bx + 12, 12 * bz + 12)))
    while len(objects) < 257 + 300:
        r = r3(math.exp(rng.uniform(math.log(0.2), math.log(0.6))))
        x, z = rng.uniform(r, 96 - r), rng.uniform(r, 96 - r)
        if overlaps(((x - r, z - r), (x + r, z + r)), foot):
            continue
        vx, vz = heading2(rng, 0.05, 0.3)
        objects.append({"id": len(objects), "shape": "sphere", "center": [r3(x), r3(rng.uniform(1.2, 4) + r), r3(z)],
                        "radius": r, "velocity": [vx, 0, vz]})
    path = []
    for t in range(300):
        s = 30 + 0.75 * t
        (px, pz), (qx, qz) = street_walk(13.5, 73.5, s), street_walk(13.5, 73.5, s + 4)
        w = 0.15 * math.sin(t / 7)
        dx, dz = qx - px, qz - pz
        path.append({"position": [r3(px), 1.5, r3(pz)],
                     "direction": [r3(dx - w * dz), r3(-0.05 * math.hypot(dx, dz)), r3(dz + w * dx)]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60,
              "aspect": 1.778}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": [96, 24, 96]},
            "camera": camera, "camera_path": path, "objects": objects}


def clusters3d():
    """100 x 60 x 100: 2,000 spheres (60 %) and boxes in 8 bell-shaped clusters plus 5 % scattered, sizes
    0.3-2 (log-uniform), 30 % of them moving at 0.1-0.5; the camera circles the world looking inward
    (1 unit per frame, 300 frames), fov 60, aspect 16:9."""
    rng = random.Random(1203)
    res = [100, 60, 100]
    centres = [[rng.uniform(25, 75), rng.uniform(15, 45), rng.uniform(25, 75)] for _ in range(8)]
    spreads = [rng.uniform(4, 9) for _ in range(8)]
    objects = []
    for i in range(2000):
        if rng.random() < 0.05:
            c = [rng.uniform(0, r) for r in res]
        else:
            k = rng.randrange(8)
            c = [centres[k][a] + (rng.random() + rng.random() + rng.random() - 1.5) * spreads[k] for a in range(3)]
        if rng.random() < 0.6:
            r = math.exp(rng.uniform(math.log(0.3), math.log(2)))
            c = [min(max(c[a], r), res[a] - r) for a in range(3)]
            o = {"id": i, "shape": "sphere", "center": [r3(v) for v in c], "radius": r3(r)}
        else:
            h = [math.exp(rng.uniform(math.log(0.25), math.log(2))) for _ in range(3)]
            c = [min(max(c[a], h[a]), res[a] - h[a]) for a in range(3)]
            o = {"id": i, "shape": "box", "min": [r3(c[a] - h[a]) for a in range(3)],
                 "max": [r3(c[a] + h[a]) for a in range(3)]}
        if rng.random() < 0.3:
            v = [rng.gauss(0, 1) for _ in range(3)]
            n = math.sqrt(sum(x * x for x in v)) or 1
            speed = rng.uniform(0.1, 0.5)
            o["velocity"] = [r3(x / n * speed) for x in v]
        else:
            o["static"] = True
        objects.append(o)
    path = []
    for t in range(300):
        a = 0.3 + t / 45
        p = [50 + 45 * math.cos(a), 30 + 8 * math.sin(2 * a), 50 + 45 * math.sin(a)]
        path.append({"position": [r3(x) for x in p], "direction": [r3(50 - p[0]), r3(25 - p[1]), r3(50 - p[2])]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60, "aspect": 1.778}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": res},
            "camera": camera, "camera_path": path, "objects": objects}


MAZE_CELLS, MAZE_CELL = 16, 8  # 16 x 16 cells of 8 units; walls 1 thick centred on the lines 1 + 8 i


def maze_layout(seed):
    """A perfect maze (randomized depth-first search) on MAZE_CELLS^2 cells: the wall boxes in 2D (merged
    runs along each line), and the corridor walk from cell (0, 0) to the cell farthest from it, as a list of
    cell centres."""
    rng = random.Random(seed)
    n = MAZE_CELLS
    open_e = [[False] * n for _ in range(n)]  # open_e[i][j]: no wall between (i, j) and (i + 1, j)
    open_n = [[False] * n for _ in range(n)]  # open_n[i][j]: no wall between (i, j) and (i, j + 1)
    parent = {(0, 0): None}
    stack = [(0, 0)]
    while stack:
        i, j = stack[-1]
        nbrs = [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di < n and 0 <= j + dj < n and (i + di, j + dj) not in parent]
        if not nbrs:
            stack.pop()
            continue
        a, b = rng.choice(nbrs)
        if a != i:
            open_e[min(a, i)][j] = True
        else:
            open_n[i][min(b, j)] = True
        parent[(a, b)] = (i, j)
        stack.append((a, b))

    def depth(c):
        d = 0
        while parent[c] is not None:
            c, d = parent[c], d + 1
        return d
    far = max(parent, key=depth)
    cells = []
    while far is not None:
        cells.append(far)
        far = parent[far]
    cells.reverse()

    line = lambda k: 1 + MAZE_CELL * k
    walls = []
    # Walls on the vertical lines x = line(k), k = 0..n: between cells (k - 1, j) and (k, j); runs merged.
    for k in range(n + 1):
        j = 0
        while j < n:
            if 0 < k < n and open_e[k - 1][j]:
                j += 1
                continue
            j0 = j
            while j < n and not (0 < k < n and open_e[k - 1][j]):
                j += 1
            walls.append(((line(k) - 0.5, line(j0) - 0.5), (line(k) + 0.5, line(j) + 0.5)))
    for k in range(n + 1):
        i = 0
        while i < n:
            if 0 < k < n and open_n[i][k - 1]:
                i += 1
                continue
            i0 = i
            while i < n and not (0 < k < n and open_n[i][k - 1]):
                i += 1
            walls.append(((line(i0) - 0.5, line(k) - 0.5), (line(i) + 0.5, line(k) + 0.5)))
    centres = [(line(i) + MAZE_CELL / 2, line(j) + MAZE_CELL / 2) for i, j in cells]
    return walls, centres


def polyline_walk(points, step, frames, look_ahead):
    """Positions every `step` units along the polyline and directions towards the point `look_ahead`
    further on (so the view turns before a corner), for `frames` frames (the walk stops at the end)."""
    seg = [math.dist(points[k], points[k + 1]) for k in range(len(points) - 1)]
    total = sum(seg)

    def at(s):
        s = min(max(s, 0), total)
        for k, L in enumerate(seg):
            if s <= L or k == len(seg) - 1:
                f = 0 if L == 0 else min(s / L, 1)
                return (points[k][0] + f * (points[k + 1][0] - points[k][0]),
                        points[k][1] + f * (points[k + 1][1] - points[k][1]))
            s -= L
    out = []
    for t in range(frames):
        s = min(step * t, total - look_ahead)
        p, q = at(s), at(s + look_ahead)
        out.append((p, (q[0] - p[0], q[1] - p[1])))
    return out


def maze_movers(rng, count, dims):
    """`count` movers in the maze's cells (centres within 2 units of a cell centre), moving along a corridor
    axis at 0.05-0.25 per frame."""
    out = []
    for _ in range(count):
        i, j = rng.randrange(MAZE_CELLS), rng.randrange(MAZE_CELLS)
        x = 1 + MAZE_CELL * i + MAZE_CELL / 2 + rng.uniform(-2, 2)
        z = 1 + MAZE_CELL * j + MAZE_CELL / 2 + rng.uniform(-2, 2)
        r = r3(rng.uniform(0.3, 0.9))
        v = r3(rng.choice((-1, 1)) * rng.uniform(0.05, 0.25))
        vel = [v, 0] if rng.random() < 0.5 else [0, v]
        out.append((x, z, r, vel))
    return out


def maze2d():
    """An indoor maze on 130 x 130: 16 x 16 cells of 8 units, walls 1 thick (a perfect maze from a seeded
    depth-first search, walls merged into runs); 150 circles moving along the corridors; the camera walks
    from the entrance cell towards the farthest cell (0.5 per frame, 400 frames), fov 90."""
    rng = random.Random(1204)
    walls, centres = maze_layout(1204)
    objects = [{"id": k, "shape": "box", "min": [a[0], a[1]], "max": [b[0], b[1]], "static": True}
               for k, (a, b) in enumerate(walls)]
    for x, z, r, vel in maze_movers(rng, 150, 2):
        objects.append({"id": len(objects), "shape": "circle", "center": [r3(x), r3(z)], "radius": r, "velocity": vel})
    path = [{"position": [r3(p[0]), r3(p[1])], "direction": [r3(d[0]), r3(d[1])]}
            for p, d in polyline_walk(centres, 0.5, 400, 3)]
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 90}
    return {"dimensions": 2, "grid": {"origin": [0, 0], "voxel_size": 1.0, "resolution": [130, 130]},
            "camera": camera, "camera_path": path, "objects": objects}


def maze3d():
    """The same maze (maze2d's layout and seed) indoors in 3D, 130 x 8 x 130: a floor slab (y 0-1), the
    walls (y 1-7) and a ceiling (y 7-8); 150 spheres moving along the corridors; the camera walks the
    same corridors at eye height 3 (0.5 per frame, 400 frames), fov 60, aspect 16:9."""
    rng = random.Random(1204)
    walls, centres = maze_layout(1204)
    objects = [{"id": 0, "shape": "box", "min": [0, 0, 0], "max": [130, 1, 130], "static": True},
               {"id": 1, "shape": "box", "min": [0, 7, 0], "max": [130, 8, 130], "static": True}]
    for a, b in walls:
        objects.append({"id": len(objects), "shape": "box", "min": [a[0], 1, a[1]], "max": [b[0], 7, b[1]],
                        "static": True})
    for x, z, r, vel in maze_movers(rng, 150, 3):
        objects.append({"id": len(objects), "shape": "sphere", "center": [r3(x), r3(rng.uniform(1 + r, 7 - r)), r3(z)],
                        "radius": r, "velocity": [vel[0], 0, vel[1]]})
    path = [{"position": [r3(p[0]), 3, r3(p[1])], "direction": [r3(d[0]), -0.1, r3(d[1])]}
            for p, d in polyline_walk(centres, 0.5, 400, 3)]
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60, "aspect": 1.778}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": [130, 8, 130]},
            "camera": camera, "camera_path": path, "objects": objects}


def open2d():
    """A sparse open field, 512 x 512: 40 static trees (circles), 12 rocks (convex polygons) and 8 huts
    (boxes) far apart, and 60 circles moving at 0.1-0.6; the camera walks a long gentle curve across it
    (0.8 per frame, 400 frames), fov 90, far 200."""
    rng = random.Random(1205)
    path = []
    for t in range(400):
        a = t / 399
        p = (40 + 430 * a, 256 + 150 * math.sin(2.5 * a))
        d = (430, 150 * 2.5 * math.cos(2.5 * a))
        path.append({"position": [r3(p[0]), r3(p[1])],
                     "direction": [r3(d[0] + 100 * math.sin(t / 15)), r3(d[1] - 0 * 0)]})
    clear = [tuple(p["position"]) for p in path[::4]]
    objects = []

    def spot(margin):
        return clear_spot(rng, 512, clear, margin)
    for _ in range(40):
        r = rng.uniform(1, 3)
        x, y = spot(r)
        objects.append({"id": len(objects), "shape": "circle", "center": [r3(x), r3(y)], "radius": r3(r),
                        "static": True})
    for _ in range(12):
        r = rng.uniform(2, 5)
        x, y = spot(r)
        objects.append({"id": len(objects), "shape": "polygon", "points": convex_polygon(rng, x, y, r, rng.randint(4, 7)),
                        "static": True})
    for _ in range(8):
        w, h = rng.uniform(4, 10), rng.uniform(4, 10)
        x, y = spot(max(w, h) / 2 + 1)
        objects.append({"id": len(objects), "shape": "box", "min": [r3(x - w / 2), r3(y - h / 2)],
                        "max": [r3(x + w / 2), r3(y + h / 2)], "static": True})
    for _ in range(60):
        r = rng.uniform(0.5, 1.5)
        x, y = spot(r)
        objects.append({"id": len(objects), "shape": "circle", "center": [r3(x), r3(y)], "radius": r3(r),
                        "velocity": heading2(rng, 0.1, 0.6)})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 90, "far": 200}
    return {"dimensions": 2, "grid": {"origin": [0, 0], "voxel_size": 1.0, "resolution": [512, 512]},
            "camera": camera, "camera_path": path, "objects": objects}


def open3d():
    """A sparse open field in 3D, 256 x 32 x 256: a ground slab, 60 static trees (spheres on 'trunk' boxes)
    and 6 huts (boxes) far apart, and 50 spheres moving level at 0.1-0.5; the camera flies a long curve at
    2-8 above the ground (0.6 per frame, 400 frames), fov 60, aspect 16:9."""
    rng = random.Random(1206)
    path = []
    for t in range(400):
        a = t / 399
        p = (20 + 216 * a, 5 + 3 * math.sin(6 * a), 128 + 80 * math.sin(3 * a))
        d = (216, 18 * math.cos(6 * a) - 20, 240 * math.cos(3 * a))
        path.append({"position": [r3(x) for x in p], "direction": [r3(x) for x in d]})
    clear = [(p["position"][0], p["position"][2]) for p in path[::4]]
    objects = [{"id": 0, "shape": "box", "min": [0, 0, 0], "max": [256, 1, 256], "static": True}]

    def spot(margin):
        return clear_spot(rng, 256, clear, margin)
    for _ in range(60):
        r = rng.uniform(1.5, 3.5)
        x, z = spot(r)
        trunk = rng.uniform(2, 5)
        objects.append({"id": len(objects), "shape": "box", "min": [r3(x - 0.3), 1, r3(z - 0.3)],
                        "max": [r3(x + 0.3), r3(1 + trunk), r3(z + 0.3)], "static": True})
        objects.append({"id": len(objects), "shape": "sphere", "center": [r3(x), r3(1 + trunk + r * 0.8), r3(z)],
                        "radius": r3(r), "static": True})
    for _ in range(6):
        w, d, h = rng.uniform(6, 14), rng.uniform(6, 14), rng.uniform(4, 10)
        x, z = spot(max(w, d) / 2 + 1)
        objects.append({"id": len(objects), "shape": "box", "min": [r3(x - w / 2), 1, r3(z - d / 2)],
                        "max": [r3(x + w / 2), r3(1 + h), r3(z + d / 2)], "static": True})
    for _ in range(50):
        r = rng.uniform(0.4, 1.2)
        x, z = spot(r)
        vx, vz = heading2(rng, 0.1, 0.5)
        objects.append({"id": len(objects), "shape": "sphere", "center": [r3(x), r3(1 + r + rng.uniform(0, 4)), r3(z)],
                        "radius": r3(r), "velocity": [vx, 0, vz]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60, "aspect": 1.778}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": [256, 32, 256]},
            "camera": camera, "camera_path": path, "objects": objects}


def paper_walk3d():
    """The paper's walkthrough (seed 004 section 6, Figure 5 (b)): 5,000 spheres of radius 0.3-3
    (log-uniform) in 8 clusters plus 20 % scattered over 100 x 60 x 100, the first 4,800 static and 200
    moving at up to 0.5 per frame; the camera walks a Lissajous loop looking along it (300 frames),
    fov 60, aspect 16:9. The distribution is the one reference::movingSpheres3D and
    scripts/make_sphere_walk.py use; radii and centres rounded to 2 decimals to keep the file small."""
    rng = random.Random(1207)
    res = [100, 60, 100]
    centres = [[rng.uniform(0.1, 0.9) * r for r in res] for _ in range(8)]
    spreads = [rng.uniform(0.03, 0.12) * 60 + 2 for _ in range(8)]
    objects = []
    for i in range(5000):
        radius = round(math.exp(rng.uniform(math.log(0.3), math.log(3))), 2)
        if rng.random() < 0.2:
            c = [rng.uniform(0, r) for r in res]
        else:
            k = rng.randrange(8)
            c = [centres[k][a] + (rng.random() + rng.random() + rng.random() - 1.5) * spreads[k] for a in range(3)]
        c = [round(min(max(c[a], radius), res[a] - radius), 2) for a in range(3)]
        o = {"id": i, "shape": "sphere", "center": c, "radius": radius}
        if i >= 4800:
            v = [rng.gauss(0, 1) for _ in range(3)]
            n = math.sqrt(sum(x * x for x in v)) or 1
            speed = rng.uniform(0.2, 1.0) * 0.5
            o["velocity"] = [r3(x / n * speed) for x in v]
        objects.append(o)
    path = []
    for f in range(300):
        t = 2 * math.pi * f / 300
        pos = [50 + 40 * math.sin(t), 30 + 12 * math.sin(3 * t), 50 + 40 * math.sin(2 * t + 0.3)]
        d = [40 * math.cos(t), -6.0, 80 * math.cos(2 * t + 0.3)]
        path.append({"position": [r3(x) for x in pos], "direction": [r3(x) for x in d]})
    camera = {"position": path[0]["position"], "direction": path[0]["direction"], "fov_deg": 60, "aspect": 1.778}
    return {"dimensions": 3, "grid": {"origin": [0, 0, 0], "voxel_size": 1.0, "resolution": res},
            "camera": camera, "camera_path": path, "objects": objects}


SCENE_BUILDERS = (("fig1-2d.json", fig1), ("walk-2d.json", walk), ("spheres-3d.json", spheres3d),
                  ("city-2d.json", city2d), ("city-3d.json", city3d), ("clusters-3d.json", clusters3d),
                  ("maze-2d.json", maze2d), ("maze-3d.json", maze3d), ("open-2d.json", open2d),
                  ("open-3d.json", open3d), ("paper-walk-3d.json", paper_walk3d))

def main():
    check = "--check" in sys.argv[1:]
    stale = []
    for name, build in SCENE_BUILDERS:
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
