#!/usr/bin/env python3
"""dispersive_prisms.py FOLDER: writes scene.json and its two meshes into
FOLDER: the dispersion test scene of the bake benchmarks, built like the public glTF
dispersion test (25 transmissive prisms and blocks about 2 cm across, index
1.0-1.5, dispersion 0-5) for scripts/bench-bake-rays.sh: prisms and blocks
alternating on a 5 x 5 grid over a floor, object k of index 1 + 0.5 k / 24
and dispersion (7 k mod 26) / 5 (none at index 1), so that no two share a
light-transport table; a slanted sun.
"""
import json
import os
import sys

MESHES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "meshes")


def scaled(src, dst, s):
    with open(dst, "w") as out:
        for line in open(src):
            t = line.split()
            out.write("v %.9g %.9g %.9g\n" % tuple(float(x) * s for x in t[1:4]) if t and t[0] == "v" else line)


def main():
    out = sys.argv[1]
    scaled(os.path.join(MESHES, "prism.obj"), os.path.join(out, "prism2cm.obj"), 0.02 / 1.5)
    scaled(os.path.join(MESHES, "box.obj"), os.path.join(out, "block2cm.obj"), 0.02)
    objects = [{"name": "floor", "mesh": os.path.join(MESHES, "plane.obj"), "role": "receiver", "material": {"albedo": 1.0},
                "transform": {"scale": [0.4, 1, 0.4]}}]
    for k in range(25):
        i, j = divmod(k, 5)
        objects.append({"name": "o%02d" % k, "mesh": "prism2cm.obj" if k % 2 == 0 else "block2cm.obj", "role": "transparent",
                        "material": {"transparent": True, "ior": round(1.0 + 0.5 * k / 24, 4),
                                     "dispersion": 0 if k == 0 else round(((k * 7) % 26) / 5, 2)},
                        "transform": {"translate": [-0.1 + 0.05 * i, 0.03, -0.1 + 0.05 * j]}})
    scene = {"name": "dispersive_prisms", "objects": objects,
             "lights": [{"type": "directional", "name": "sun", "direction": [0.3, -1, 0.2], "irradiance": 1.0}]}
    with open(os.path.join(out, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)


if __name__ == "__main__":
    main()
