#!/usr/bin/env python3
"""scan_blob.py OUT.obj [LEVELS] [--scene SCENE.json]: a closed, scan-like glass
mesh for the bake benchmarks (scripts/bench-bake-rays.sh,
bench-ltt-zstd.sh): an icosahedron split LEVELS
times (default 6: 40 962 vertices, 81 920 triangles, what a decimated
photogrammetry scan of a small object has), each vertex pushed along its
direction by a fixed sum of sine bumps (up to 12 % of the 0.1 m radius), so
that the surface is curved everywhere, concave in places and irregular like
a scan, with no two triangles alike. Written without normals (computed by
the importer, as for most scans). --scene also writes a scene of it: glass
of index 1.5 15 cm over the repository's floor plane, lit by a sun.
"""
import argparse
import json
import math
import os


def write_scene(path, mesh):
    floor = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "meshes", "plane.obj")
    scene = {"name": "scan",
             "objects": [{"name": "floor", "mesh": os.path.abspath(floor), "role": "receiver", "material": {"albedo": 1.0}},
                         {"name": "scan", "mesh": os.path.relpath(os.path.abspath(mesh), os.path.dirname(os.path.abspath(path))),
                          "role": "transparent", "material": {"transparent": True, "ior": 1.5},
                          "transform": {"translate": [0, 0.15, 0]}}],
             "lights": [{"type": "directional", "name": "sun", "direction": [0.2, -1, 0.1], "irradiance": 1.0}]}
    with open(path, "w") as o:
        json.dump(scene, o, indent=2)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("levels", nargs="?", type=int, default=6)
    ap.add_argument("--scene")
    args = ap.parse_args()
    out, levels = args.out, args.levels
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
         (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
                n = math.sqrt(sum(c * c for c in p))
                v.append(tuple(c / n for c in p))
                mid[key] = len(v) - 1
            return mid[key]
        nf = []
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    bumps = [((0.3, 0.8, -0.5), 7.0, 0.05), ((-0.7, 0.1, 0.7), 11.0, 0.03), ((0.5, -0.6, 0.6), 17.0, 0.02), ((0.1, 0.2, 0.97), 29.0, 0.01)]
    with open(out, "w") as o:
        o.write("# scan_blob.py: a closed scan-like blob, %d vertices, %d triangles\n" % (len(v), len(f)))
        for p in v:
            r = 1.0
            for axis, freq, amp in bumps:
                r += amp * math.sin(freq * sum(a * c for a, c in zip(axis, p)))
            o.write("v %.7f %.7f %.7f\n" % tuple(0.1 * r * c for c in p))
        for a, b, c in f:
            o.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    if args.scene:
        write_scene(args.scene, out)


if __name__ == "__main__":
    main()
