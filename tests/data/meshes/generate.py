#!/usr/bin/env python3
"""Writes the mesh-import corpus: files shaped like the ones users
bring from other tools -- comments where each format allows them, colours and
normals per vertex, polygons of any size (non-convex too), binary and ASCII,
shuffled element order, extra properties and elements, huge coordinates,
duplicated and isolated vertices, non-manifold edges, zero-area faces, point
clouds -- and broken ones. Committed together with expectations.json, which
says for each file what the importer and the baker must do:

  expect        "bakes" or "refused"
  triangles     triangles after import (bakes)
  area          total surface area after triangulation, in file units: a
                non-convex polygon triangulated wrongly (a fan) covers more
  volume        signed enclosed volume of closed meshes (outward winding > 0)
  closed        a closed, consistently wound solid: it must also bake as a
                transparent object; open or miswound ones must be refused
                there with the edge census message
  normals_from_file, warning, message: what the import reports

Re-run to regenerate (the output is deterministic): python3 generate.py
"""
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
EXPECT = []


# ---------------------------------------------------------------- shapes

def cube_grid(n=3, size=1.0):
    """Closed cube [-s/2, s/2]^3, each face n x n quads, vertices shared
    (welded), outward counter-clockwise."""
    h = size / 2
    index, verts, faces = {}, [], []

    def vid(p):
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]

    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (-1, 1):
            def at(i, k):
                p = [0.0, 0.0, 0.0]
                p[axis] = side * h
                p[u] = -h + size * i / n
                p[v] = -h + size * k / n
                return vid(tuple(p))
            for i in range(n):
                for k in range(n):
                    q = [at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)]
                    faces.append(q if side > 0 else q[::-1])
    return verts, faces


def cylinder(seg=24, radius=0.5, height=1.0):
    """Closed cylinder along y with one convex seg-gon per cap."""
    verts, faces = [], []
    for y in (0.0, height):
        for s in range(seg):
            a = 2 * math.pi * s / seg
            verts.append((radius * math.cos(a), y, radius * math.sin(a)))
    for s in range(seg):
        t = (s + 1) % seg
        faces.append([s, seg + s, seg + t, t])
    faces.append(list(range(seg)))                       # bottom, seen from -y: counter-clockwise
    faces.append([seg + s for s in reversed(range(seg))])  # top, seen from +y
    return verts, faces


def star(points=5, outer=0.5, inner=0.2):
    pts = []
    for i in range(2 * points):
        r = outer if i % 2 == 0 else inner
        a = math.pi * i / points
        pts.append((r * math.cos(a), r * math.sin(a)))
    return pts


def star_prism(points=5, depth=0.3):
    """A star extruded along y: two non-convex 2*points-gon caps, quad sides.
    star() runs counter-clockwise in (x, z), which is clockwise seen from +y
    (x right, z towards the viewer): the bottom cap keeps that order."""
    s = star(points)
    n = len(s)
    verts = [(x, 0.0, z) for x, z in s] + [(x, depth, z) for x, z in s]
    faces = [list(range(n)), [n + i for i in reversed(range(n))]]
    for i in range(n):
        j = (i + 1) % n
        faces.append([i, n + i, n + j, j])
    return verts, faces


def terrain(n=6, size=2.0):
    """Open height field (a scan-like patch), quads, normal roughly +y."""
    verts, faces = [], []
    for j in range(n + 1):
        for i in range(n + 1):
            x, z = size * (i / n - 0.5), size * (j / n - 0.5)
            verts.append((x, 0.1 * math.sin(3 * x) * math.cos(2 * z), z))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            faces.append([a, a + n + 1, a + n + 2, a + 1])
    return verts, faces


def l_shape():
    """One planar non-convex hexagon in y = 0, front +y (an L, area 3)."""
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]  # CCW in (x, z)
    verts = [(float(x), 0.0, float(z)) for x, z in pts]
    return verts, [list(reversed(range(6)))]  # reversed: CCW seen from +y


# ---------------------------------------------------------------- measures

def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def polygon_area(verts, face):
    """Area of a planar polygon (Newell's vector)."""
    n = [0.0, 0.0, 0.0]
    for i in range(len(face)):
        p, q = verts[face[i]], verts[face[(i + 1) % len(face)]]
        c = cross(p, q)
        n = [n[k] + c[k] for k in range(3)]
    return 0.5 * math.sqrt(dot(n, n))


def area(verts, faces):
    """What the importer's triangles cover: a planar polygon's own area
    (however it is triangulated inside its outline); a non-planar one's fan
    from its first corner (how the importer splits a convex outline)."""
    total = 0.0
    for f in faces:
        nrm = [0.0, 0.0, 0.0]
        for i in range(len(f)):
            c = cross(verts[f[i]], verts[f[(i + 1) % len(f)]])
            nrm = [nrm[k] + c[k] for k in range(3)]
        ln = math.sqrt(dot(nrm, nrm))
        planar = all(abs(dot(nrm, sub(verts[k], verts[f[0]]))) <= 1e-9 * ln for k in f) if ln > 0 else True
        if planar:
            total += polygon_area(verts, f)
        else:
            for i in range(1, len(f) - 1):
                c = cross(sub(verts[f[i]], verts[f[0]]), sub(verts[f[i + 1]], verts[f[0]]))
                total += 0.5 * math.sqrt(dot(c, c))
    return total


def volume(verts, faces):
    v = 0.0
    for f in faces:
        for i in range(1, len(f) - 1):
            v += dot(verts[f[0]], cross(verts[f[i]], verts[f[i + 1]])) / 6
    return v


def triangles(faces):
    return sum(len(f) - 2 for f in faces)


def vertex_normals(verts, faces):
    acc = [[0.0, 0.0, 0.0] for _ in verts]
    for f in faces:
        n = [0.0, 0.0, 0.0]
        for i in range(len(f)):
            c = cross(verts[f[i]], verts[f[(i + 1) % len(f)]])
            n = [n[k] + c[k] for k in range(3)]
        for i in f:
            acc[i] = [acc[i][k] + n[k] for k in range(3)]
    out = []
    for a in acc:
        ln = math.sqrt(dot(a, a)) or 1.0
        out.append(tuple(c / ln for c in a))
    return out


def expect(name, verts, faces, closed, **kw):
    if closed:
        assert volume(verts, faces) > 0, name + ": wound inside out"
    entry = {"file": name, "expect": "bakes", "triangles": triangles(faces),
             "area": round(area(verts, faces), 9), "closed": closed}
    if closed:
        entry["volume"] = round(volume(verts, faces), 9)
    entry.update(kw)
    EXPECT.append(entry)


def refused(name, message, **kw):
    entry = {"file": name, "expect": "refused", "message": message}
    entry.update(kw)
    EXPECT.append(entry)


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(HERE, name), mode, **({} if mode == "wb" else {"newline": ""})) as f:
        f.write(data)


def g(x):
    return "%.9g" % x


# ---------------------------------------------------------------- OFF

def off_text(verts, faces, head="OFF", vertex_extra=None, face_extra=None, comments=False, counts_line=None,
             nl="\n"):
    out = [head]
    out.append(counts_line if counts_line is not None else f"{len(verts)} {len(faces)} 0")
    for i, v in enumerate(verts):
        line = " ".join(g(c) for c in v)
        if vertex_extra:
            line += " " + vertex_extra(i)
        if comments and i % 7 == 0:
            line += f"  # vertex {i}"
        out.append(line)
    for i, f in enumerate(faces):
        line = f"{len(f)} " + " ".join(str(k) for k in f)
        if face_extra:
            line += " " + face_extra(i)
        out.append(line)
    return nl.join(out) + nl


def off_corpus():
    cv, cf = cube_grid(3)
    write("off_plain_closed.off", off_text(cv, cf))
    expect("off_plain_closed.off", cv, cf, True)

    write("off_comment_before_header.off",
          "# Exported by a scanner's software\n# units: metres\n\n" + off_text(cv, cf))
    expect("off_comment_before_header.off", cv, cf, True)

    text = off_text(cv, cf).split("\n")
    text.insert(1, "# vertices faces edges")
    text.insert(2, "")
    write("off_comment_after_header.off", "\n".join(text))
    expect("off_comment_after_header.off", cv, cf, True)

    text = off_text(cv, cf, comments=True).split("\n")
    text.insert(2 + len(cv), "# faces follow")  # a comment line between vertices and faces
    text.insert(5, "# a comment among the vertices")
    write("off_comments_inline.off", "\n".join(text))
    expect("off_comments_inline.off", cv, cf, True)

    t = off_text(cv, cf).split("\n", 2)
    write("off_counts_on_header_line.off", f"OFF {len(cv)} {len(cf)} 0\n" + t[2])
    expect("off_counts_on_header_line.off", cv, cf, True)

    yv, yf = cylinder(24)
    write("coff_rgba_int.off", off_text(yv, yf, "COFF", vertex_extra=lambda i: f"{(i * 37) % 256} 128 {255 - i % 256} 255"))
    expect("coff_rgba_int.off", yv, yf, True)
    write("coff_rgb_float.off", off_text(yv, yf, "COFF", vertex_extra=lambda i: f"0.25 {i / len(yv):.3f} 0.75"))
    expect("coff_rgb_float.off", yv, yf, True)

    sv, sf = star_prism()
    nv = vertex_normals(sv, sf)
    write("noff_normals.off", off_text(sv, sf, "NOFF", vertex_extra=lambda i: " ".join(g(c) for c in nv[i])))
    expect("noff_normals.off", sv, sf, True, normals_from_file=True)
    write("cnoff_normals_colours.off",
          off_text(sv, sf, "CNOFF", vertex_extra=lambda i: " ".join(g(c) for c in nv[i]) + " 200 100 50 255"))
    expect("cnoff_normals_colours.off", sv, sf, True, normals_from_file=True)

    # Homogeneous coordinates: every point written as (2x, 2y, 2z, 2).
    hv = [tuple(2 * c for c in v) for v in cv]
    write("4off_homogeneous.off", off_text(hv, cf, "4OFF", vertex_extra=lambda i: "2"))
    expect("4off_homogeneous.off", cv, cf, True)

    lv, lf = l_shape()
    write("off_nonconvex_polygon.off", off_text(lv, lf))
    expect("off_nonconvex_polygon.off", lv, lf, False)

    write("off_star_prism_polygons.off", off_text(sv, sf))
    expect("off_star_prism_polygons.off", sv, sf, True)

    write("off_face_colours.off", off_text(yv, yf, face_extra=lambda i: "0.8 0.2 0.2 1.0" if i % 2 else "255 0 0"))
    expect("off_face_colours.off", yv, yf, True)

    write("off_crlf_trailing_spaces.off", off_text(cv, cf, nl="  \r\n"))
    expect("off_crlf_trailing_spaces.off", cv, cf, True)

    text = off_text(cv, cf).replace(" ", "\t").split("\n")
    text = [line + ("\n" if i % 5 == 0 else "") for i, line in enumerate(text)]
    write("off_tabs_blank_lines.off", "\n".join(text))
    expect("off_tabs_blank_lines.off", cv, cf, True)

    # Geomview binary OFF: big-endian int32 counts, float32 coordinates, and
    # per face int32 size, int32 indices, int32 colour-value count (0).
    b = bytearray(b"OFF BINARY\n")
    b += struct.pack(">iii", len(yv), len(yf), 0)
    for v in yv:
        b += struct.pack(">fff", *v)
    for f in yf:
        b += struct.pack(">i", len(f)) + struct.pack(">%di" % len(f), *f) + struct.pack(">i", 0)
    write("off_binary.off", bytes(b))
    expect("off_binary.off", yv, yf, True)

    # Huge coordinates: a 2 m cube 1000 km from the origin (float spacing
    # 6 cm there: the baker warns; the mesh still imports and bakes).
    fv = [(c[0] * 2 + 1.0e6, c[1] * 2, c[2] * 2 - 1.0e6) for c in cv]
    write("off_huge_coordinates.off", off_text(fv, cf))
    e = {"file": "off_huge_coordinates.off", "expect": "bakes", "triangles": triangles(cf), "closed": True,
         "area": round(area(fv, cf), 3)}
    EXPECT.append(e)

    # Split seams: every face has its own vertices (a soup closed by position).
    dv, df = [], []
    for f in cf:
        df.append([len(dv) + k for k in range(len(f))])
        dv.extend(cv[k] for k in f)
    write("off_duplicated_vertices.off", off_text(dv, df))
    expect("off_duplicated_vertices.off", dv, df, True)

    iv = cv + [(5.0, 5.0, 5.0), (-7.0, 0.0, 1.0)]  # two vertices no face uses
    write("off_isolated_vertices.off", off_text(iv, cf))
    expect("off_isolated_vertices.off", cv, cf, True)

    # A fin: a third face on one edge of the cube (non-manifold edge).
    a, b2 = cf[0][0], cf[0][1]
    nvx = cv + [(2.0, 0.0, 0.0)]
    nf = cf + [[a, b2, len(cv)]]
    write("off_nonmanifold_fin.off", off_text(nvx, nf))
    expect("off_nonmanifold_fin.off", nvx, nf, False, transparent_message="non-manifold")

    # Zero-area faces: a collinear triangle and a quad with a repeated corner.
    zv = cv + [(0.0, 0.0, 0.0), (0.25, 0.0, 0.0), (0.5, 0.0, 0.0)]
    k = len(cv)
    zf = cf + [[k, k + 1, k + 2], [cf[3][0], cf[3][1], cf[3][1], cf[3][2]]]
    write("off_zero_area_faces.off", off_text(zv, zf))
    e = {"file": "off_zero_area_faces.off", "expect": "bakes", "triangles": triangles(cf) + 1, "closed": False,
         "area": round(area(cv, cf) + polygon_area(cv, [cf[3][0], cf[3][1], cf[3][2]]), 9),
         "warning": "degenerate", "transparent_message": "non-manifold",
         # closed but non-manifold: as glass, refused (a solid was meant), not thin-walled
         "as_glass": "refused"}
    EXPECT.append(e)

    # Broken files.
    write("off_lying_counts.off", off_text(cv, cf, counts_line=f"{len(cv)} {len(cf) + 40} 0"))
    refused("off_lying_counts.off", "the header declares")
    write("off_count_overflow.off", off_text(cv, cf, counts_line="4000000000 4000000000 0"))
    refused("off_count_overflow.off", "OFF header")
    bad = [list(f) for f in cf]
    bad[7][2] = len(cv) + 3
    write("off_index_out_of_range.off", off_text(cv, bad))
    refused("off_index_out_of_range.off", "face 7")
    t = off_text(cv, cf)
    write("off_truncated.off", t[: len(t) * 2 // 3])
    refused("off_truncated.off", "line")
    nanv = list(cv)
    nanv[4] = (float("nan"), 0.0, 0.0)
    write("off_nan_coordinate.off", off_text(nanv, cf).replace("nan", "nan"))
    refused("off_nan_coordinate.off", "vertex 4")
    write("off_point_cloud.off", off_text(cv, []))
    refused("off_point_cloud.off", "no faces")
    write("off_not_off.off", "This is not a mesh.\n1 2 3\n")
    refused("off_not_off.off", "OFF")


# ---------------------------------------------------------------- PLY

PLY_TYPES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f",
             "double": "d", "int8": "b", "uint8": "B", "int32": "i", "uint32": "I", "float32": "f", "float64": "d"}


def ply_file(fmt, elements, comments=(), nl="\n"):
    """elements: list of (name, [(prop_name, type) or (prop_name, ('list', count_t, item_t))], rows)."""
    head = ["ply", f"format {fmt} 1.0"] + [f"comment {c}" for c in comments]
    for name, props, rows in elements:
        head.append(f"element {name} {len(rows)}")
        for pname, ptype in props:
            if isinstance(ptype, tuple):
                head.append(f"property list {ptype[1]} {ptype[2]} {pname}")
            else:
                head.append(f"property {ptype} {pname}")
    head.append("end_header")
    text = nl.join(head) + nl
    if fmt == "ascii":
        body = []
        for name, props, rows in elements:
            for row in rows:
                vals = []
                for (pname, ptype), val in zip(props, row):
                    if isinstance(ptype, tuple):
                        vals.append(str(len(val)))
                        vals.extend(g(x) if ptype[2] in ("float", "double", "float32", "float64") else str(x) for x in val)
                    else:
                        vals.append(g(val) if ptype in ("float", "double", "float32", "float64") else str(val))
                body.append(" ".join(vals))
        return (text + nl.join(body) + nl).encode()
    order = "<" if fmt == "binary_little_endian" else ">"
    b = bytearray(text.encode())
    for name, props, rows in elements:
        for row in rows:
            for (pname, ptype), val in zip(props, row):
                if isinstance(ptype, tuple):
                    b += struct.pack(order + PLY_TYPES[ptype[1]], len(val))
                    b += struct.pack(order + PLY_TYPES[ptype[2]] * len(val), *val)
                else:
                    b += struct.pack(order + PLY_TYPES[ptype], val)
    return bytes(b)


XYZ = [("x", "float"), ("y", "float"), ("z", "float")]
FACE = [("vertex_indices", ("list", "uchar", "int"))]


def ply_corpus():
    cv, cf = cube_grid(3)
    nv = vertex_normals(cv, cf)
    vprops = XYZ + [("nx", "float"), ("ny", "float"), ("nz", "float"), ("red", "uchar"), ("green", "uchar"),
                    ("blue", "uchar"), ("alpha", "uchar"), ("confidence", "float"), ("intensity", "float")]
    vrows = [list(v) + list(nv[i]) + [i % 256, 100, 200, 255, 0.9, 0.5] for i, v in enumerate(cv)]
    frows = [[f, 7] for f in cf]
    write("ply_ascii_extra_properties.ply", ply_file("ascii", [("vertex", vprops, vrows),
                                                               ("face", FACE + [("flags", "uchar")], frows)],
                                                     comments=["made by a scanner", "units m"]))
    expect("ply_ascii_extra_properties.ply", cv, cf, True, normals_from_file=True)

    write("ply_faces_before_vertices.ply", ply_file("ascii", [("face", FACE, [[f] for f in cf]),
                                                              ("vertex", XYZ, [list(v) for v in cv])]))
    expect("ply_faces_before_vertices.ply", cv, cf, True)

    write("ply_vertex_index_uint.ply",
          ply_file("ascii", [("vertex", XYZ, [list(v) for v in cv]),
                             ("face", [("vertex_index", ("list", "uchar", "uint"))], [[f] for f in cf])]))
    expect("ply_vertex_index_uint.ply", cv, cf, True)

    yv, yf = cylinder(24)
    write("ply_binary_le_double.ply",
          ply_file("binary_little_endian",
                   [("vertex", [("x", "double"), ("y", "double"), ("z", "double")], [list(v) for v in yv]),
                    ("face", [("vertex_indices", ("list", "int", "int"))], [[f] for f in yf])]))
    expect("ply_binary_le_double.ply", yv, yf, True)

    write("ply_binary_be.ply", ply_file("binary_big_endian", [("vertex", XYZ, [list(v) for v in yv]),
                                                              ("face", FACE, [[f] for f in yf])]))
    expect("ply_binary_be.ply", yv, yf, True)

    edges = [[cf[i][0], cf[i][1], 255, 0, 0] for i in range(4)]
    eprops = [("vertex1", "int"), ("vertex2", "int"), ("red", "uchar"), ("green", "uchar"), ("blue", "uchar")]
    mats = [[0.5, 0.5, 0.5, 1.0]]
    mprops = [("ambient_red", "float"), ("ambient_green", "float"), ("ambient_blue", "float"), ("shininess", "float")]
    write("ply_extra_elements.ply", ply_file("binary_little_endian",
                                             [("vertex", XYZ, [list(v) for v in cv]), ("edge", eprops, edges),
                                              ("face", FACE, [[f] for f in cf]), ("material", mprops, mats)]))
    expect("ply_extra_elements.ply", cv, cf, True)

    tprops = FACE + [("texcoord", ("list", "uchar", "float"))]
    write("ply_face_texcoords.ply",
          ply_file("binary_little_endian", [("vertex", XYZ, [list(v) for v in cv]),
                                            ("face", tprops, [[f, [0.5] * (2 * len(f))] for f in cf])],
                   comments=["TextureFile scan.png"]))
    expect("ply_face_texcoords.ply", cv, cf, True)

    sv, sf = star_prism()
    write("ply_star_prism_polygons.ply", ply_file("ascii", [("vertex", XYZ, [list(v) for v in sv]),
                                                            ("face", FACE, [[f] for f in sf])]))
    expect("ply_star_prism_polygons.ply", sv, sf, True)

    tv, tf = terrain()
    write("ply_crlf_terrain.ply", ply_file("ascii", [("vertex", XYZ, [list(v) for v in tv]),
                                                     ("face", FACE, [[f] for f in tf])], nl="\r\n"))
    expect("ply_crlf_terrain.ply", tv, tf, False, transparent_message="boundary edge")

    write("ply_point_cloud.ply", ply_file("binary_little_endian", [("vertex", XYZ, [list(v) for v in cv])]))
    refused("ply_point_cloud.ply", "no faces")

    lying = ply_file("binary_little_endian", [("vertex", XYZ, [list(v) for v in cv]), ("face", FACE, [[f] for f in cf])])
    lying = lying.replace(f"element vertex {len(cv)}".encode(), b"element vertex 2000000000")
    write("ply_lying_binary.ply", lying)
    refused("ply_lying_binary.ply", "the header declares")

    t = ply_file("binary_little_endian", [("vertex", XYZ, [list(v) for v in cv]), ("face", FACE, [[f] for f in cf])])
    write("ply_truncated_binary.ply", t[: len(t) - 40])
    refused("ply_truncated_binary.ply", "the header declares")

    bad = [[list(f)] for f in cf]
    bad[5][0][1] = 4096
    write("ply_index_out_of_range.ply", ply_file("ascii", [("vertex", XYZ, [list(v) for v in cv]), ("face", FACE, bad)]))
    refused("ply_index_out_of_range.ply", "face 5")

    # Valid PLY types CGAL's reader cannot take (mesh_header_check.cpp):
    # refused by name, or (normals) skipped with a warning.
    ip = [("x", "float"), ("y", "int32"), ("z", "float")]
    write("ply_int_coordinates.ply", ply_file("binary_little_endian", [("vertex", ip, [[x, int(y), z] for x, y, z in cv]),
                                                                        ("face", FACE, [[f] for f in cf])]))
    refused("ply_int_coordinates.ply", "the 'vertex' property 'y' is int32; coordinates must be float or double")
    write("ply_ushort_face_indices.ply",
          ply_file("ascii", [("vertex", XYZ, [list(v) for v in cv]),
                             ("face", [("vertex_indices", ("list", "uchar", "ushort"))], [[f] for f in cf])]))
    refused("ply_ushort_face_indices.ply", "'vertex_indices' is a list of ushort; it must be a list of int or uint")
    # An element without properties takes no bytes: its count is bounded by
    # the file's size (readers loop over its items).
    t = ply_file("ascii", [("vertex", XYZ, [list(v) for v in cv]), ("face", FACE, [[f] for f in cf])])
    write("ply_element_without_properties.ply", t.replace(b"end_header", b"element marker 4000000000\nend_header"))
    refused("ply_element_without_properties.ply", "4000000000 'marker' elements without properties")
    sn = [("nx", "short"), ("ny", "short"), ("nz", "short")]
    write("ply_short_normals.ply",
          ply_file("binary_big_endian", [("vertex", XYZ + sn, [list(v) + [int(c * 32767) for c in nv[i]]
                                                                  for i, v in enumerate(cv)]),
                                         ("face", FACE, [[f] for f in cf])]))
    expect("ply_short_normals.ply", cv, cf, True, normals_from_file=False,
           warning="the vertex normals (nx, ny, nz) include a short, not float or double; normals are computed")


# ---------------------------------------------------------------- STL

def tri_list(verts, faces):
    out = []
    for f in faces:
        for i in range(1, len(f) - 1):
            out.append((verts[f[0]], verts[f[i]], verts[f[i + 1]]))
    return out


def stl_ascii(tris, name="part", nl="\n", indent="  "):
    lines = [f"solid {name}"]
    for a, b, c in tris:
        n = cross(sub(b, a), sub(c, a))
        ln = math.sqrt(dot(n, n)) or 1
        lines.append(f"{indent}facet normal {g(n[0] / ln)} {g(n[1] / ln)} {g(n[2] / ln)}")
        lines.append(f"{indent}{indent}outer loop")
        for p in (a, b, c):
            lines.append(f"{indent}{indent}{indent}vertex {g(p[0])} {g(p[1])} {g(p[2])}")
        lines.append(f"{indent}{indent}endloop")
        lines.append(f"{indent}endfacet")
    lines.append(f"endsolid {name}")
    return nl.join(lines) + nl


def stl_binary(tris, header=b"binary STL written by generate.py", attribute=0):
    b = bytearray(header.ljust(80, b" ")[:80])
    b += struct.pack("<I", len(tris))
    for a, bb, c in tris:
        n = cross(sub(bb, a), sub(c, a))
        ln = math.sqrt(dot(n, n)) or 1
        b += struct.pack("<3f", *(x / ln for x in n))
        for p in (a, bb, c):
            b += struct.pack("<3f", *p)
        b += struct.pack("<H", attribute)
    return bytes(b)


def stl_corpus():
    cv, cf = cube_grid(3)
    tris = tri_list(cv, cf)
    tri_faces = [[3 * i, 3 * i + 1, 3 * i + 2] for i in range(len(tris))]
    tri_verts = [p for t in tris for p in t]
    write("stl_ascii.stl", stl_ascii(tris))
    expect("stl_ascii.stl", tri_verts, tri_faces, True)
    write("stl_binary.stl", stl_binary(tris))
    expect("stl_binary.stl", tri_verts, tri_faces, True)
    write("stl_binary_solid_header.stl", stl_binary(tris, header=b"solid part exported by a CAD program"))
    expect("stl_binary_solid_header.stl", tri_verts, tri_faces, True)
    write("stl_binary_colour_attributes.stl", stl_binary(tris, attribute=0x801F))
    expect("stl_binary_colour_attributes.stl", tri_verts, tri_faces, True)
    write("stl_ascii_crlf_tabs.stl", stl_ascii(tris, name="scan 01", nl="\r\n", indent="\t"))
    expect("stl_ascii_crlf_tabs.stl", tri_verts, tri_faces, True)
    # Two solids in one file (a part and a second part beside it).
    yv, yf = cylinder(16)
    ytris = tri_list([(x + 2.0, y, z) for x, y, z in yv], yf)
    write("stl_ascii_two_solids.stl", stl_ascii(tris, "a") + stl_ascii(ytris, "b"))
    both = tris + ytris
    expect("stl_ascii_two_solids.stl", [p for t in both for p in t],
           [[3 * i, 3 * i + 1, 3 * i + 2] for i in range(len(both))], True)
    b = stl_binary(tris)
    write("stl_binary_truncated.stl", b[: len(b) - 17])
    refused("stl_binary_truncated.stl", "the header declares")
    write("stl_ascii_bad_number.stl", stl_ascii(tris).replace("vertex", "vertex x", 1))
    refused("stl_ascii_bad_number.stl", "line 4")


# ---------------------------------------------------------------- OBJ

def obj_corpus():
    cv, cf = cube_grid(3)
    nv = vertex_normals(cv, cf)
    lines = ["# Exported by a modelling tool", "mtllib part.mtl", "o Part", ""]
    lines += ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines += ["vt 0.5 0.5", "vt 0.25 0.75"]
    lines += ["vn %s %s %s" % tuple(g(c) for c in n) for n in nv]
    for i, f in enumerate(cf):
        if i % 18 == 0:
            lines += [f"g side_{i // 18}", "usemtl grey", "s 1" if i % 36 == 0 else "s off"]
        lines.append("f " + " ".join(f"{k + 1}/{1 + (k % 2)}/{k + 1}" for k in f))
    write("obj_groups_materials.obj", "\n".join(lines) + "\n")
    expect("obj_groups_materials.obj", cv, cf, True, normals_from_file=True)

    # Relative (negative) indices: each face refers back from the vertices
    # written just before it (the way streaming exporters write).
    lines = ["# negative indices"]
    for f in cf:
        for k in f:
            lines.append("v %s %s %s" % tuple(g(c) for c in cv[k]))
        lines.append("f " + " ".join(str(-(len(f) - i)) for i in range(len(f))))
    write("obj_negative_indices.obj", "\n".join(lines) + "\n")
    dv = [cv[k] for f in cf for k in f]
    df, at = [], 0
    for f in cf:
        df.append(list(range(at, at + len(f))))
        at += len(f)
    expect("obj_negative_indices.obj", dv, df, True)

    sv, sf = star_prism(7)
    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in sv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in sf]
    write("obj_star_prism_polygons.obj", "\n".join(lines) + "\n")
    expect("obj_star_prism_polygons.obj", sv, sf, True)

    yv, yf = cylinder(24)
    lines = ["v %s %s %s 0.8 0.3 0.1" % tuple(g(c) for c in v) for v in yv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in yf]
    write("obj_vertex_colours.obj", "\n".join(lines) + "\n")
    expect("obj_vertex_colours.obj", yv, yf, True)

    tv, tf = terrain()
    lines = ["v\t%s\t%s\t%s" % tuple(g(c) for c in v) for v in tv]
    lines += ["l 1 2 3", "p 4"]
    lines += ["f  " + "   ".join(str(k + 1) for k in f) + " " for f in tf]
    write("obj_tabs_crlf_lines_points.obj", "\r\n".join(lines) + "\r\n")
    expect("obj_tabs_crlf_lines_points.obj", tv, tf, False, transparent_message="boundary edge")

    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines += ["vn 0 1 0"]
    lines += ["f " + " ".join(f"{k + 1}//1" for k in f) for f in cf]
    write("obj_normal_refs.obj", "\n".join(lines) + "\n")
    expect("obj_normal_refs.obj", cv, cf, True)

    lv, lf = l_shape()
    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in lv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in lf]
    write("obj_nonconvex_polygon.obj", "\n".join(lines) + "\n")
    expect("obj_nonconvex_polygon.obj", lv, lf, False)

    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in cf]
    lines[len(cv) + 9] = "f 1 2 999"
    write("obj_index_out_of_range.obj", "\n".join(lines) + "\n")
    refused("obj_index_out_of_range.obj", "line %d: corner 3 '999' refers to vertex 999; the file has %d vertices"
            % (len(cv) + 10, len(cv)))

    # Line continuations (a backslash at the end of a line, as CAD exporters
    # write long polygons; a comment ending in one is not continued), and
    # normal references in a file without normals (the normals are computed).
    sv, sf = star_prism(9)
    lines = ["# star prism \\", "v %s %s %s" % tuple(g(c) for c in sv[0])]
    lines += ["v %s %s %s" % tuple(g(c) for c in v) for v in sv[1:]]
    for f in sf:
        refs = [f"{k + 1}//{k + 1}" for k in f]
        half = len(refs) // 2
        lines.append("f " + " ".join(refs[:half]) + " \\")
        lines.append("  " + " ".join(refs[half:]))
    write("obj_line_continuation.obj", "\n".join(lines) + "\n")
    expect("obj_line_continuation.obj", sv, sf, True, normals_from_file=False)

    # What OpenMesh's OBJ reader would misread or stop on (mesh_read_openmesh.cpp).
    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in cf]
    lines[len(cv) + 3] = "f /1 2/2 3/3"
    write("obj_corner_without_vertex.obj", "\n".join(lines) + "\n")
    refused("obj_corner_without_vertex.obj", "line %d: corner 1 '/1' has no vertex index" % (len(cv) + 4))
    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines[5] = "v 0.5 0.25"
    lines += ["f " + " ".join(str(k - len(cv)) for k in f) for f in cf]
    write("obj_vertex_two_coordinates.obj", "\n".join(lines) + "\n")
    refused("obj_vertex_two_coordinates.obj", "line 6: vertex 6 has fewer than 3 coordinates")
    lines = ["v %s %s %s" % tuple(g(c) for c in v) for v in cv]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in cf]
    lines += ["f 1 2", "f 3 3/1 -%d" % (len(cv) - 2)]
    write("obj_faces_under_three_vertices.obj", "\n".join(lines) + "\n")
    expect("obj_faces_under_three_vertices.obj", cv, cf, True,
           warning="skipped 2 face(s) with fewer than 3 distinct vertices (first at line %d)" % (len(cv) + len(cf) + 1))

    write("obj_no_faces.obj", "\n".join("v %s %s %s" % tuple(g(c) for c in v) for v in cv) + "\n")
    refused("obj_no_faces.obj", "no faces")


def fuzz_seeds():
    """The corpus as seeds of tests/fuzz/fuzz_mesh_import.cpp: each file
    behind the byte that picks its extension (0 .obj, 1 .off, 2 .ply, 3 .stl)."""
    out = os.path.join(HERE, "..", "..", "fuzz", "corpus_mesh")
    os.makedirs(out, exist_ok=True)
    for e in EXPECT:
        name = e["file"]
        ext = {".obj": 0, ".off": 1, ".ply": 2, ".stl": 3}[os.path.splitext(name)[1]]
        with open(os.path.join(HERE, name), "rb") as f:
            data = f.read()
        with open(os.path.join(out, "seed_" + name), "wb") as f:
            f.write(bytes([ext]) + data)


if __name__ == "__main__":
    off_corpus()
    ply_corpus()
    stl_corpus()
    obj_corpus()
    with open(os.path.join(HERE, "expectations.json"), "w", newline="\n") as f:
        json.dump(EXPECT, f, indent=1)
        f.write("\n")
    fuzz_seeds()
    print(f"generate.py: {len(EXPECT)} files")
