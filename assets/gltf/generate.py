#!/usr/bin/env python3
"""Writes glass_ball.gltf and materials.gltf in this folder (committed; re-run
to regenerate).

glass_ball.gltf:
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

materials.gltf: a material sheet as a viewer's test scene has it, with no
lights (viewers light such files with an environment; caustix gives them
its default rig), for the gallery (docs/gallery.md) and the tools' tests:

  floor    plane.obj, scale 6, grey rough dielectric (metallic 0)
  metals   four spheres (radius 0.3) along x at z = 0, metallic 1,
           roughness 0.25, 0.5, 0.75, 1, base colours gold, copper,
           silver, iron
  plastics four spheres at z = 0.9, metallic 0, roughness 0, 0.33,
           0.67, 1, red, green, blue, white
  amber    a solid glass ball (radius 0.4) at (0.4, 0.4, -1) with
           KHR_materials_volume attenuationColor (1, 0.55, 0.15) over
           0.3 m: orange through its volume, casting an orange caustic
  panel    an upright 1.2 x 0.6 m quad at (-1.2, 0.5, -1.2) facing +z,
           emissiveFactor (1, 0.6, 0.3) x KHR_materials_emissive_strength 2
  camera   perspective, 40 deg, at (0.4, 2.6, 4.4) looking at (0, 0.25, -0.2)

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


def materials():
    g = Gltf()
    for ext in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_emissive_strength"):
        g.doc.setdefault("extensionsUsed", []).append(ext)
    plane_obj = os.path.join(HERE, "..", "meshes", "plane.obj")
    sphere_obj = os.path.join(HERE, "..", "meshes", "sphere.obj")

    def material(name, base, metallic, roughness, extra=None):
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(base) + [1.0], "metallicFactor": metallic,
                                                    "roughnessFactor": roughness}}
        m.update(extra or {})
        return g.push("materials", m)

    nodes = [g.push("nodes", {"name": "floor", "mesh": g.mesh(plane_obj, material("floor", (0.5, 0.5, 0.5), 0.0, 0.8)),
                              "scale": [6, 1, 6]})]
    metals = [("gold", (1.0, 0.77, 0.34)), ("copper", (0.95, 0.64, 0.54)), ("silver", (0.97, 0.96, 0.91)), ("iron", (0.56, 0.57, 0.58))]
    for k, (name, base) in enumerate(metals):
        mesh = g.mesh(sphere_obj, material(name, base, 1.0, 0.25 * (k + 1)))
        nodes.append(g.push("nodes", {"name": name, "mesh": mesh, "translation": [-1.2 + 0.8 * k, 0.3, 0.0], "scale": [0.3] * 3}))
    plastics = [("red", (0.8, 0.05, 0.05)), ("green", (0.05, 0.6, 0.1)), ("blue", (0.05, 0.1, 0.8)), ("white", (0.9, 0.9, 0.9))]
    for k, (name, base) in enumerate(plastics):
        mesh = g.mesh(sphere_obj, material(name + " plastic", base, 0.0, k / 3.0))
        nodes.append(g.push("nodes", {"name": name, "mesh": mesh, "translation": [-1.2 + 0.8 * k, 0.3, 0.9], "scale": [0.3] * 3}))
    amber = material("amber", (1.0, 1.0, 1.0), 0.0, 0.0,
                     {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.54},
                                     "KHR_materials_volume": {"thicknessFactor": 0.8, "attenuationDistance": 0.3,
                                                              "attenuationColor": [1.0, 0.55, 0.15]}}})
    nodes.append(g.push("nodes", {"name": "amber", "mesh": g.mesh(sphere_obj, amber), "translation": [0.4, 0.4, -1.0], "scale": [0.4] * 3}))
    panel = material("panel", (0.0, 0.0, 0.0), 0.0, 1.0,
                     {"emissiveFactor": [1.0, 0.6, 0.3], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}})
    s = math.sqrt(0.5)
    nodes.append(g.push("nodes", {"name": "panel", "mesh": g.mesh(plane_obj, panel), "translation": [-1.2, 0.5, -1.2],
                                  "rotation": [s, 0, 0, s], "scale": [1.2, 1, 0.6]}))
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(40), "znear": 0.05, "zfar": 100.0}}]
    nodes.append(g.push("nodes", {"name": "camera", "camera": 0, "translation": [0.4, 2.6, 4.4],
                                  "rotation": look_at_quaternion([0.4, 2.6, 4.4], [0, 0.25, -0.2])}))
    g.doc["scenes"] = [{"name": "materials", "nodes": nodes}]
    g.doc["scene"] = 0
    g.write(os.path.join(HERE, "materials.gltf"))


if __name__ == "__main__":
    main()
    materials()
