#!/usr/bin/env python3
"""Writes glass_ball.gltf, materials.gltf and textured.gltf in this folder
(committed; re-run to regenerate).

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
  insect   a dark brown box (0.22 x 0.05 x 0.08 m) inside the amber
  panel    an upright 1.2 x 0.6 m quad at (-1.2, 0.5, -1.2) facing +z,
           emissiveFactor (1, 0.6, 0.3) x KHR_materials_emissive_strength 2
  camera   perspective, 40 deg, at (0.4, 2.6, 4.4) looking at (0, 0.25, -0.2)

textured.gltf: glTF's textures as an exporter writes them (PNG images in
buffer views, one TEXCOORD_0 set, an ORM texture shared by the
metallic-roughness and occlusion slots), with no lights:

  floor    a 4 x 4 m quad of 8 x 8 tiles (KHR_texture_transform scale 2):
           base colour, tangent-space normal map (bevelled tile edges) and
           ORM (occlusion and roughness in the grout, roughness 0.35 on
           the tiles)
  sign     an upright 1.6 x 0.8 m quad at the back, black, its emissive
           texture an orange ring (emissiveFactor 1)
  fence    an upright 1.2 x 1.2 m quad on the left, alphaMode MASK
           (cut-off 0.5): a green lattice with round holes in its alpha
  plate    an upright 1 x 1 m quad on the right, metallic 1, roughness 1,
           its metallic-roughness texture half polished metal, half
           rough paint
  pane     an upright 1 x 0.8 m quad in front, alphaMode BLEND, blue at
           alpha 0.35
  ball     a solid glass ball (radius 0.35) on the tiles, for its caustic
  camera   perspective, 45 deg, at (0, 2.2, 4.2) looking at (0, 0.4, 0)

Buffers are embedded as base64 data URIs; vertices are the OBJ's (v, vn)
pairs in order of first use, so the meshes are the OBJ importer's.
"""
import base64
import json
import math
import os
import struct
import zlib

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
    insect = material("insect", (0.12, 0.06, 0.02), 0.0, 0.5)
    nodes.append(g.push("nodes", {"name": "insect", "mesh": g.mesh(os.path.join(HERE, "..", "meshes", "box.obj"), insect),
                                  "translation": [0.4, 0.42, -1.0], "scale": [0.22, 0.05, 0.08],
                                  "rotation": [0, math.sin(math.radians(15)), 0, math.cos(math.radians(15))]}))
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


def png(width, height, pixel):
    """An 8-bit RGB or RGBA PNG of pixel(x, y) -> tuple of 0..1 floats (y = 0
    the top row)."""
    channels = len(pixel(0, 0))
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows += bytes(max(0, min(255, round(c * 255))) for c in pixel(x, y))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", width, height, 8, 6 if channels == 4 else 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b"")


def textured():
    g = Gltf()
    for ext in ("KHR_texture_transform", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"):
        g.doc.setdefault("extensionsUsed", []).append(ext)

    def image(name, data):
        while len(g.bin) % 4:
            g.bin.append(0)
        view = g.push("bufferViews", {"buffer": 0, "byteOffset": len(g.bin), "byteLength": len(data)})
        g.bin += data
        return g.push("textures", {"source": g.push("images", {"name": name, "bufferView": view, "mimeType": "image/png"}), "sampler": 0})
    g.doc["samplers"] = [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}]

    def quad(material, upright=False):
        """A unit quad, centred, facing +y (upright: facing +z), UV (0, 0) at
        its far (upright: top) left corner."""
        corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
        pos = [(x, -z, 0.0) if upright else (x, 0.0, z) for x, z in corners]
        nrm = [(0.0, 0.0, 1.0) if upright else (0.0, 1.0, 0.0)] * 4
        uv = [(x + 0.5, z + 0.5) for x, z in corners]
        attrs = {"POSITION": g.accessor("f", [c for p in pos for c in p], 5126, "VEC3", 4,
                                        {"min": [min(p[k] for p in pos) for k in range(3)], "max": [max(p[k] for p in pos) for k in range(3)]}),
                 "NORMAL": g.accessor("f", [c for n in nrm for c in n], 5126, "VEC3", 4),
                 "TEXCOORD_0": g.accessor("f", [c for t in uv for c in t], 5126, "VEC2", 4)}
        ind = g.accessor("H", [0, 2, 1, 0, 3, 2], 5123, "SCALAR", 6)
        return g.push("meshes", {"primitives": [{"attributes": attrs, "indices": ind, "material": material}]})

    n = 128
    tile = n // 4  # 4 x 4 tiles an image
    grout, bevel = 2, 5

    def in_tile(x, y):
        """Position within its tile from the grout's edge, and the distance to
        the nearest grout."""
        u, v = x % tile - grout, y % tile - grout
        size = tile - 2 * grout
        return u, v, size, min(u, v, size - 1 - u, size - 1 - v)

    def tiles_colour(x, y):
        u, v, size, d = in_tile(x, y)
        if d < 0:
            return (0.35, 0.33, 0.3)
        return (0.72, 0.36, 0.22) if (x // tile + y // tile) % 2 else (0.86, 0.8, 0.68)

    def tiles_normal(x, y):
        u, v, size, d = in_tile(x, y)
        tx = ty = 0.0
        if 0 <= d < bevel:  # the tile's edge slopes down to the grout at 45 degrees
            if d == u:
                tx = -0.7
            elif d == size - 1 - u:
                tx = 0.7
            elif d == v:
                ty = 0.7   # +y of the map is up the image (decreasing v)
            else:
                ty = -0.7
        tz = math.sqrt(max(0.0, 1 - tx * tx - ty * ty))
        return (0.5 + 0.5 * tx, 0.5 + 0.5 * ty, 0.5 + 0.5 * tz)

    def tiles_orm(x, y):
        u, v, size, d = in_tile(x, y)
        return (0.45, 0.9, 0.0) if d < 0 else (1.0, 0.35, 0.0)

    def ring(x, y):
        r = math.hypot(x - 63.5, (y - 31.5) * 2)
        return (1.0, 0.55, 0.15) if 34 < r < 48 else (0.0, 0.0, 0.0)

    def lattice(x, y):
        hole = math.hypot(x % 32 - 15.5, y % 32 - 15.5) < 11
        return (0.25, 0.55, 0.2, 0.0 if hole else 1.0)

    def plate(x, y):
        metal = x < 64
        return (1.0, 0.15 if metal else 0.8, 1.0 if metal else 0.0)

    t_colour, t_normal, t_orm = image("tiles_colour", png(n, n, tiles_colour)), image("tiles_normal", png(n, n, tiles_normal)), image("tiles_orm", png(n, n, tiles_orm))
    scale2 = {"KHR_texture_transform": {"scale": [2, 2]}}
    floor = g.push("materials", {"name": "tiles", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": t_colour, "extensions": scale2}, "metallicFactor": 1.0, "roughnessFactor": 1.0,
        "metallicRoughnessTexture": {"index": t_orm, "extensions": scale2}},
        "normalTexture": {"index": t_normal, "extensions": scale2}, "occlusionTexture": {"index": t_orm, "extensions": scale2}})
    sign = g.push("materials", {"name": "sign", "pbrMetallicRoughness": {"baseColorFactor": [0.02, 0.02, 0.02, 1], "metallicFactor": 0.0},
                                "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": image("sign_emissive", png(n, 64, ring))}})
    fence = g.push("materials", {"name": "fence", "alphaMode": "MASK", "doubleSided": True,
                                 "pbrMetallicRoughness": {"baseColorTexture": {"index": image("fence", png(64, 64, lattice))}, "metallicFactor": 0.0}})
    plate_m = g.push("materials", {"name": "plate", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.92, 1], "metallicFactor": 1.0, "roughnessFactor": 1.0,
                                                                           "metallicRoughnessTexture": {"index": image("plate_mr", png(n, n, plate))}}})
    pane = g.push("materials", {"name": "pane", "alphaMode": "BLEND", "doubleSided": True,
                                "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 1.0, 0.35], "metallicFactor": 0.0, "roughnessFactor": 0.2}})
    glass = g.push("materials", {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
                                 "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5},
                                                "KHR_materials_volume": {"thicknessFactor": 0.7}}})
    sphere_obj = os.path.join(HERE, "..", "meshes", "sphere.obj")
    nodes = [
        g.push("nodes", {"name": "floor", "mesh": quad(floor), "scale": [4, 1, 4]}),
        g.push("nodes", {"name": "sign", "mesh": quad(sign, True), "translation": [0, 0.6, -1.6], "scale": [1.6, 0.8, 1]}),
        g.push("nodes", {"name": "fence", "mesh": quad(fence, True), "translation": [-1.4, 0.6, -0.4], "scale": [1.2, 1.2, 1],
                         "rotation": [0, math.sin(math.radians(20)), 0, math.cos(math.radians(20))]}),
        g.push("nodes", {"name": "plate", "mesh": quad(plate_m, True), "translation": [1.4, 0.55, -0.4], "scale": [1, 1, 1],
                         "rotation": [0, -math.sin(math.radians(20)), 0, math.cos(math.radians(20))]}),
        g.push("nodes", {"name": "pane", "mesh": quad(pane, True), "translation": [-0.6, 0.4, 1.0], "scale": [1, 0.8, 1]}),
        g.push("nodes", {"name": "ball", "mesh": g.mesh(sphere_obj, glass), "translation": [0.35, 0.35, 0.1], "scale": [0.35] * 3}),
    ]
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(45), "znear": 0.05, "zfar": 100.0}}]
    nodes.append(g.push("nodes", {"name": "camera", "camera": 0, "translation": [0, 2.2, 4.2],
                                  "rotation": look_at_quaternion([0, 2.2, 4.2], [0, 0.4, 0])}))
    g.doc["scenes"] = [{"name": "textured", "nodes": nodes}]
    g.doc["scene"] = 0
    g.write(os.path.join(HERE, "textured.gltf"))


if __name__ == "__main__":
    main()
    materials()
    textured()
