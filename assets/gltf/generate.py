#!/usr/bin/env python3
"""Writes glass_ball.gltf in this folder (committed; re-run to regenerate):
the canonical glass_ball scene (assets/scenes/glass_ball.json) as a glTF 2.0
exporter writes it, for `caustix-bake glass_ball.gltf` and the tests that
check that both routes bake the same scene (tests/gltf_import_test.cpp).

  floor  ../meshes/plane.obj, node scale 4, base colour white
  ball   ../meshes/sphere.obj, node translation (0, 0.75, 0), scale 0.5,
         KHR_materials_transmission 1 + KHR_materials_ior 1.5 +
         KHR_materials_volume (a solid; without it glTF's glass is thin-walled)
  sun    KHR_lights_punctual directional, 683 lux (E0 = 1 W/m^2 at
         683 lm/W), pointing straight down (node turned -90 deg about x)
  camera perspective, 45 deg, at (1.9, 2.3, 2.6) looking at (0, 0.35, 0)

Buffers are embedded as base64 data URIs; vertices are the OBJ's (v, vn)
pairs in order of first use, so the meshes are the OBJ importer's.
"""
import base64
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def read_obj(path):
    v, vn, corners = [], [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            v.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == "vn":
            vn.append(tuple(float(x) for x in t[1:4]))
        elif t[0] == "f":
            face = []
            for c in t[1:]:
                parts = c.split("/")
                face.append((int(parts[0]) - 1, int(parts[2]) - 1 if len(parts) > 2 and parts[2] else None))
            for k in range(1, len(face) - 1):  # the OBJs here are convex polygons
                corners += [face[0], face[k], face[k + 1]]
    index, pos, nrm, tri = {}, [], [], []
    for c in corners:
        if c not in index:
            index[c] = len(pos)
            pos.append(v[c[0]])
            nrm.append(vn[c[1]] if c[1] is not None else None)
        tri.append(index[c])
    return pos, (nrm if all(n is not None for n in nrm) else None), tri


class Gltf:
    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "caustix assets/gltf/generate.py"}}
        self.bin = bytearray()

    def push(self, key, value):
        self.doc.setdefault(key, []).append(value)
        return len(self.doc[key]) - 1

    def accessor(self, fmt, values, ctype, atype, count, extra=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        data = struct.pack("<" + fmt * len(values), *values)
        view = self.push("bufferViews", {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        a = {"bufferView": view, "componentType": ctype, "count": count, "type": atype}
        a.update(extra or {})
        return self.push("accessors", a)

    def mesh(self, path, material):
        pos, nrm, tri = read_obj(path)
        flat = [c for p in pos for c in p]
        lo = [min(p[k] for p in pos) for k in range(3)]
        hi = [max(p[k] for p in pos) for k in range(3)]
        attrs = {"POSITION": self.accessor("f", flat, 5126, "VEC3", len(pos), {"min": lo, "max": hi})}
        if nrm:
            attrs["NORMAL"] = self.accessor("f", [c for n in nrm for c in n], 5126, "VEC3", len(nrm))
        ind = self.accessor("I", tri, 5125, "SCALAR", len(tri))
        return self.push("meshes", {"name": os.path.splitext(os.path.basename(path))[0],
                                    "primitives": [{"attributes": attrs, "indices": ind, "material": material}]})

    def write(self, path):
        self.doc["buffers"] = [{"byteLength": len(self.bin),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")


def look_at_quaternion(eye, target, up=(0.0, 1.0, 0.0)):
    """The rotation taking the camera's -z to eye -> target and +y near up."""
    def norm(a):
        n = math.sqrt(sum(x * x for x in a))
        return [x / n for x in a]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    back = norm([e - t for e, t in zip(eye, target)])
    right = norm(cross(up, back))
    upv = cross(back, right)
    m = [right, upv, back]  # columns
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return [(m[1][2] - m[2][1]) / s, (m[2][0] - m[0][2]) / s, (m[0][1] - m[1][0]) / s, 0.25 * s]
    raise ValueError("camera orientation not handled")


def main():
    g = Gltf()
    for ext in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_lights_punctual"):
        g.doc.setdefault("extensionsUsed", []).append(ext)
    white = g.push("materials", {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0}})
    glass = g.push("materials", {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
                                 "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                                "KHR_materials_ior": {"ior": 1.5},
                                                "KHR_materials_volume": {"thicknessFactor": 1.0}}})
    plane = g.mesh(os.path.join(HERE, "..", "meshes", "plane.obj"), white)
    sphere = g.mesh(os.path.join(HERE, "..", "meshes", "sphere.obj"), glass)
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"name": "sun", "type": "directional", "intensity": 683.0}]}}
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(45), "znear": 0.05, "zfar": 100.0}}]
    s = math.sqrt(0.5)
    nodes = [
        g.push("nodes", {"name": "floor", "mesh": plane, "scale": [4, 1, 4]}),
        g.push("nodes", {"name": "ball", "mesh": sphere, "translation": [0, 0.75, 0], "scale": [0.5, 0.5, 0.5]}),
        g.push("nodes", {"name": "sun", "rotation": [-s, 0, 0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}),
        g.push("nodes", {"name": "camera", "camera": 0, "translation": [1.9, 2.3, 2.6],
                         "rotation": look_at_quaternion([1.9, 2.3, 2.6], [0, 0.35, 0])}),
    ]
    g.doc["scenes"] = [{"name": "glass_ball", "nodes": nodes}]
    g.doc["scene"] = 0
    g.write(os.path.join(HERE, "glass_ball.gltf"))


if __name__ == "__main__":
    main()
