#!/usr/bin/env python3
"""twelve_balls.py [FOLDER [MESH]]: writes twelve_balls.gltf into FOLDER
(default: the current one), its balls assets/meshes/MESH (default
sphere.obj; sphere_fine.obj for a scan-like 8 k-vertex ball):
a TransmissionTest-like scene for the shared-work benchmark
(scripts/bench-shared-work.sh) -- twelve copies of one glass ball over a
floor and a back wall, exported the way a DCC tool writes duplicated (not
instanced) objects: each ball its own glTF mesh with its own copy of the
vertex data, in one of three glass materials that differ only in colour
(KHR_materials_transmission + KHR_materials_ior 1.5 + KHR_materials_volume),
each node turned differently, lit by a directional sun.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "gltf"))
from generate import Gltf, look_at_quaternion  # noqa: E402

MESHES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "meshes")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    sphere = sys.argv[2] if len(sys.argv) > 2 else "sphere.obj"
    g = Gltf()
    for ext in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_lights_punctual"):
        g.doc.setdefault("extensionsUsed", []).append(ext)
    white = g.push("materials", {"name": "backdrop", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 0.0}})
    glass = []
    for name, colour in (("clear", [1, 1, 1, 1]), ("amber", [1.0, 0.8, 0.5, 1]), ("teal", [0.6, 0.95, 0.9, 1])):
        glass.append(g.push("materials", {"name": name, "pbrMetallicRoughness": {"baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.0},
                                           "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                                          "KHR_materials_ior": {"ior": 1.5},
                                                          "KHR_materials_volume": {"thicknessFactor": 0.2}}}))
    floor = g.mesh(os.path.join(MESHES, "plane.obj"), white)
    wall = g.mesh(os.path.join(MESHES, "plane.obj"), white)
    nodes = [g.push("nodes", {"name": "floor", "mesh": floor, "scale": [4, 1, 2]}),
             g.push("nodes", {"name": "wall", "mesh": wall, "translation": [0, 1, -1], "scale": [4, 1, 1],
                              "rotation": [math.sqrt(0.5), 0, 0, math.sqrt(0.5)]})]
    for k in range(12):
        ball = g.mesh(os.path.join(MESHES, sphere), glass[k % 3])  # a copy of the data per ball
        x, z = -1.65 + 0.3 * k, 0.35 * ((k % 2) * 2 - 1)
        a = 0.5 * k  # each ball turned about its own axis
        rot = [math.sin(a / 2) * 0.6, math.sin(a / 2) * 0.8, 0.0, math.cos(a / 2)]
        nodes.append(g.push("nodes", {"name": "ball%02d" % k, "mesh": ball, "translation": [x, 0.25, z],
                                      "rotation": rot, "scale": [0.12, 0.12, 0.12]}))
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"name": "sun", "type": "directional", "intensity": 683.0}]}}
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(40), "znear": 0.05, "zfar": 100.0}}]
    tilt = math.radians(-70) / 2
    nodes.append(g.push("nodes", {"name": "sun", "rotation": [math.sin(tilt), 0, 0, math.cos(tilt)],
                                  "extensions": {"KHR_lights_punctual": {"light": 0}}}))
    eye = [0.0, 1.6, 3.2]
    nodes.append(g.push("nodes", {"name": "camera", "camera": 0, "translation": eye,
                                  "rotation": look_at_quaternion(eye, [0, 0.2, 0])}))
    g.doc["scenes"] = [{"name": "twelve_balls", "nodes": nodes}]
    g.doc["scene"] = 0
    g.write(os.path.join(out, "twelve_balls.gltf"))


if __name__ == "__main__":
    main()
