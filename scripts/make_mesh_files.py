#!/usr/bin/env python3
"""Writes the small mesh files of the mesh tests and example scene (scene-format.md's "shape": "mesh").

  python3 scripts/make_mesh_files.py     # rewrites tests/data/cube.{obj,gltf,glb}, scenes/meshes/house.{obj,gltf}

cube.*: the unit cube [0,1]^3 (12 triangles, outward counter-clockwise). cube.gltf puts it under a node
with translation [10, 0, 0] and scale 2 (so its placed bounds are [10,12] x [0,2] x [0,2]), split at
every face (24 vertices, as exporters write cubes with normals) and with uint16 indices; cube.glb has
the same cube without a node transform, uint8 indices.
house: a closed house (a 4 x 3 x 4 box with a gable roof up to y = 5), 10 vertices, 16 triangles.
"""
import base64, json, os, struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CUBE_V = [(0,0,0),(1,0,0),(1,1,0),(0,1,0),(0,0,1),(1,0,1),(1,1,1),(0,1,1)]
# Quads counter-clockwise seen from outside.
CUBE_Q = [(0,3,2,1),(4,5,6,7),(0,1,5,4),(2,3,7,6),(0,4,7,3),(1,2,6,5)]

HOUSE_V = [(0,0,0),(4,0,0),(4,0,4),(0,0,4),(0,3,0),(4,3,0),(4,3,4),(0,3,4),(2,5,0),(2,5,4)]
HOUSE_F = [(0,1,2,3),                  # floor (counter-clockwise seen from below)
           (0,4,5,1),(3,2,6,7),        # z = 0 wall, z = 4 wall
           (0,3,7,4),(1,5,6,2),        # x = 0, x = 4 walls
           (4,8,5),(7,6,9),            # gables (z = 0 and z = 4)
           (4,7,9,8),(5,8,9,6)]        # roof slopes

def tris(faces):
    out = []
    for f in faces:
        for k in range(1, len(f) - 1):
            out.append((f[0], f[k], f[k + 1]))
    return out

def write_obj(path, verts, faces, comment):
    with open(path, "w") as fh:
        fh.write("# " + comment + " (scripts/make_mesh_files.py)\n")
        for v in verts:
            fh.write("v %g %g %g\n" % v)
        for f in faces:
            fh.write("f " + " ".join(str(i + 1) for i in f) + "\n")

def gltf_doc(verts, triangles, index_fmt, node):
    vb = b"".join(struct.pack("<3f", *v) for v in verts)
    comp = {"B": 5121, "H": 5123, "I": 5125}[index_fmt]
    ib = b"".join(struct.pack("<" + index_fmt, i) for t in triangles for i in t)
    pad = (-len(vb)) % 4
    data = vb + b"\0" * pad + ib
    data += b"\0" * ((-len(data)) % 4)
    lo = [min(v[a] for v in verts) for a in range(3)]
    hi = [max(v[a] for v in verts) for a in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "rgvc scripts/make_mesh_files.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [dict(node, mesh=0)],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(vb), "target": 34962},
                        {"buffer": 0, "byteOffset": len(vb) + pad, "byteLength": len(ib), "target": 34963}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(verts), "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 1, "componentType": comp, "count": 3 * len(triangles), "type": "SCALAR"}],
    }
    return doc, data

def write_gltf(path, verts, triangles, index_fmt="H", node=None):
    doc, data = gltf_doc(verts, triangles, index_fmt, node or {})
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    with open(path, "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")

def write_glb(path, verts, triangles, index_fmt="B"):
    doc, data = gltf_doc(verts, triangles, index_fmt, {})
    js = json.dumps(doc).encode()
    js += b" " * ((-len(js)) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(data), 0x004E4942) + data
    with open(path, "wb") as fh:
        fh.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)

def split_cube():
    """The cube with 4 vertices per face (24), as exporters write it."""
    verts, triangles = [], []
    for q in CUBE_Q:
        base = len(verts)
        verts += [CUBE_V[i] for i in q]
        triangles += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return verts, triangles

def main():
    data = os.path.join(ROOT, "tests", "data")
    meshes = os.path.join(ROOT, "scenes", "meshes")
    os.makedirs(data, exist_ok=True)
    os.makedirs(meshes, exist_ok=True)
    write_obj(os.path.join(data, "cube.obj"), CUBE_V, CUBE_Q, "unit cube [0,1]^3, quads")
    sv, st = split_cube()
    write_gltf(os.path.join(data, "cube.gltf"), sv, st, "H", {"translation": [10, 0, 0], "scale": [2, 2, 2]})
    write_glb(os.path.join(data, "cube.glb"), CUBE_V, tris(CUBE_Q), "B")
    write_obj(os.path.join(meshes, "house.obj"), HOUSE_V, HOUSE_F, "closed house 4 x 5 x 4")
    write_gltf(os.path.join(meshes, "house.gltf"), HOUSE_V, tris(HOUSE_F), "H")

if __name__ == "__main__":
    main()
