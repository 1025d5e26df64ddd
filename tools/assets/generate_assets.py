#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Procedural low-poly mesh generator for the FMCW LiDAR simulator.

Writes self-contained glTF 2.0 files (JSON + base64-embedded binary buffer)
plus ``materials.yaml`` into the output folder.  Standard library only.

    /usr/bin/python3 tools/assets/generate_assets.py --out assets

COORDINATE FRAME -- READ THIS BEFORE LOADING THE FILES
------------------------------------------------------
* Units are metres.
* Right-handed, Z UP, X FORWARD, Y LEFT (ISO 8855 vehicle frame).
* glTF's own convention is Y-up.  NO Y-up conversion is applied here: vertex
  coordinates are written directly in the Z-up frame above, and the loader
  must interpret the file axes as x = forward, y = left, z = up.
* The origin of every object is on the ground (z = 0) below the centre of its
  footprint; vehicles face +X.  Exceptions (documented in assets/README.md):
  ``pole`` and ``sign`` have their origin at the base of the post.
* Triangles are wound counter-clockwise seen from outside (outward normals);
  every vertex carries a flat-shading NORMAL (smooth shading for the skinned
  walker).
* Two assets are animated (glTF skins / animations): walker_skinned (skinned
  human, clips 'walk' and 'idle') and car_keyframed (wheel spin as keyframes,
  clip 'roll').  At rest every node has only a translation.

The output is deterministic: coordinates are rounded before being packed as
float32, JSON is written with sorted keys and there are no timestamps, so two
runs produce byte-identical files.
"""

import argparse
import base64
import json
import math
import os
import struct
import sys

# --------------------------------------------------------------------------
# Materials
# --------------------------------------------------------------------------

# name: (baseColorFactor RGBA, metallic, roughness, reflectivity @ 1550 nm, note)
MATERIALS = {
    "car_paint": ((0.55, 0.06, 0.06, 1.0), 0.3, 0.35, 0.30, "automotive clear-coat paint"),
    "glass": ((0.20, 0.28, 0.32, 0.35), 0.0, 0.05, 0.05, "mostly transmissive/specular at 1550 nm"),
    "tire": ((0.04, 0.04, 0.04, 1.0), 0.0, 0.90, 0.05, "carbon-black rubber"),
    "metal": ((0.62, 0.63, 0.65, 1.0), 1.0, 0.40, 0.50, "bare or galvanised metal"),
    "plastic": ((0.08, 0.08, 0.09, 1.0), 0.0, 0.60, 0.20, "dark trim plastic"),
    "asphalt": ((0.18, 0.18, 0.19, 1.0), 0.0, 0.95, 0.10, "road surface"),
    "concrete": ((0.62, 0.61, 0.58, 1.0), 0.0, 0.90, 0.35, "sidewalk, facade, roof"),
    "curb": ((0.72, 0.71, 0.68, 1.0), 0.0, 0.85, 0.35, "curb stones"),
    "road_marking": ((0.95, 0.95, 0.93, 1.0), 0.0, 0.50, 0.90, "retroreflective paint (glass beads)"),
    "brick": ((0.55, 0.26, 0.18, 1.0), 0.0, 0.90, 0.30, "brick facade"),
    "foliage": ((0.16, 0.38, 0.12, 1.0), 0.0, 0.80, 0.40, "leaves (NIR/SWIR bright)"),
    "bark": ((0.30, 0.21, 0.13, 1.0), 0.0, 0.95, 0.25, "tree bark"),
    "skin": ((0.80, 0.60, 0.50, 1.0), 0.0, 0.70, 0.30, "human skin"),
    "cloth": ((0.22, 0.26, 0.42, 1.0), 0.0, 0.90, 0.25, "clothing textile"),
    "sign_face": ((0.10, 0.32, 0.75, 1.0), 0.0, 0.40, 0.90, "retroreflective sheeting"),
}

FRAME_NOTE = ("Z-up ISO 8855 frame: x forward, y left, z up, metres. "
              "NOT the glTF Y-up convention; do not apply a Y-up conversion.")

# --------------------------------------------------------------------------
# Small vector helpers (tuples of 3 floats)
# --------------------------------------------------------------------------


def vadd(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def vsub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def vmul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def vdot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def vcross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def vlen(a):
    return math.sqrt(vdot(a, a))


def vnorm(a):
    n = vlen(a)
    if n == 0.0:
        raise ValueError("cannot normalise zero vector")
    return (a[0] / n, a[1] / n, a[2] / n)


def vcentroid(pts):
    k = float(len(pts))
    return (sum(p[0] for p in pts) / k, sum(p[1] for p in pts) / k, sum(p[2] for p in pts) / k)


def newell_normal(pts):
    nx = ny = nz = 0.0
    count = len(pts)
    for i in range(count):
        a = pts[i]
        b = pts[(i + 1) % count]
        nx += (a[1] - b[1]) * (a[2] + b[2])
        ny += (a[2] - b[2]) * (a[0] + b[0])
        nz += (a[0] - b[0]) * (a[1] + b[1])
    return (nx, ny, nz)


def hash01(i, seed):
    """Deterministic integer hash mapped to [0, 1)."""
    x = (i * 2654435761 + seed * 40503 + 12345) & 0xFFFFFFFF
    x ^= x >> 16
    x = (x * 0x45D9F3B) & 0xFFFFFFFF
    x ^= x >> 16
    x = (x * 0x45D9F3B) & 0xFFFFFFFF
    x ^= x >> 16
    return x / 4294967296.0


# --------------------------------------------------------------------------
# 2D polygon triangulation (ear clipping, handles simple non-convex polygons)
# --------------------------------------------------------------------------


def _cross2(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def ear_clip(p):
    """Return index triples (counter-clockwise in 2D) triangulating polygon p."""
    n = len(p)
    area2 = 0.0
    for i in range(n):
        a = p[i]
        b = p[(i + 1) % n]
        area2 += a[0] * b[1] - b[0] * a[1]
    idx = list(range(n)) if area2 > 0 else list(range(n - 1, -1, -1))
    ext = max(max(q[0] for q in p) - min(q[0] for q in p),
              max(q[1] for q in p) - min(q[1] for q in p), 1e-9)
    eps = 1e-12 * ext * ext
    tris = []
    while len(idx) > 3:
        m = len(idx)
        clipped = False
        for k in range(m):
            ia, ib, ic = idx[k - 1], idx[k], idx[(k + 1) % m]
            a, b, c = p[ia], p[ib], p[ic]
            turn = _cross2(a, b, c)
            if abs(turn) <= eps:
                idx.pop(k)  # collinear vertex: drop it, the region is unchanged
                clipped = True
                break
            if turn < 0:
                continue  # reflex vertex
            blocked = False
            for j in idx:
                if j in (ia, ib, ic):
                    continue
                q = p[j]
                if q == a or q == b or q == c:
                    continue
                if (_cross2(a, b, q) >= -eps and _cross2(b, c, q) >= -eps
                        and _cross2(c, a, q) >= -eps):
                    blocked = True
                    break
            if not blocked:
                tris.append((ia, ib, ic))
                idx.pop(k)
                clipped = True
                break
        if not clipped:
            raise ValueError("ear clipping failed (self-intersecting polygon?)")
    if abs(_cross2(p[idx[0]], p[idx[1]], p[idx[2]])) > eps:
        tris.append((idx[0], idx[1], idx[2]))
    return tris


# --------------------------------------------------------------------------
# Mesh builder: one primitive per material, flat shading
# --------------------------------------------------------------------------


class MeshBuilder(object):
    def __init__(self, name):
        self.name = name
        self.prims = {}  # material -> (positions, normals, indices)
        self.tris = []   # every emitted triangle, for self-checks

    def _prim(self, mat):
        if mat not in MATERIALS:
            raise ValueError("unknown material %r" % mat)
        if mat not in self.prims:
            self.prims[mat] = ([], [], [])
        return self.prims[mat]

    def triangle_count(self):
        return len(self.tris)

    def polygon(self, mat, pts, hint=None):
        """Add a planar polygon.  If hint is given the face is oriented so its
        normal points along hint; otherwise pts must be counter-clockwise seen
        from the front side."""
        clean = []
        for q in pts:
            q = (float(q[0]), float(q[1]), float(q[2]))
            if not clean or vlen(vsub(q, clean[-1])) > 1e-9:
                clean.append(q)
        if len(clean) > 1 and vlen(vsub(clean[0], clean[-1])) <= 1e-9:
            clean.pop()
        if len(clean) < 3:
            raise ValueError("polygon with fewer than 3 distinct points")
        nrm = newell_normal(clean)
        if vlen(nrm) < 1e-12:
            raise ValueError("degenerate polygon")
        nrm = vnorm(nrm)
        if hint is not None and vdot(nrm, hint) < 0.0:
            clean.reverse()
            nrm = vmul(nrm, -1.0)
        ax = max(range(3), key=lambda i: abs(nrm[i]))
        i1, i2 = ((1, 2), (2, 0), (0, 1))[ax]
        tris = ear_clip([(q[i1], q[i2]) for q in clean])
        oriented = []
        for (a, b, c) in tris:
            pa, pb, pc = clean[a], clean[b], clean[c]
            g = vcross(vsub(pb, pa), vsub(pc, pa))
            if vlen(g) < 2e-10:
                continue  # zero-area sliver
            if vdot(g, nrm) < 0.0:
                b, c = c, b
            oriented.append((a, b, c))
        centre = vcentroid(clean)
        size = max(vlen(vsub(q, centre)) for q in clean)
        planar = all(abs(vdot(vsub(q, centre), nrm)) <= 1e-7 * (1.0 + size) for q in clean)
        pos, nor, ind = self._prim(mat)
        if planar:
            remap = {}
            for tri in oriented:
                for v in tri:
                    if v not in remap:
                        remap[v] = len(pos)
                        pos.append(clean[v])
                        nor.append(nrm)
                ind.extend(remap[v] for v in tri)
                self.tris.append(tuple(clean[v] for v in tri))
        else:
            for tri in oriented:
                tp = [clean[v] for v in tri]
                tn = vnorm(vcross(vsub(tp[1], tp[0]), vsub(tp[2], tp[0])))
                for q in tp:
                    ind.append(len(pos))
                    pos.append(q)
                    nor.append(tn)
                self.tris.append(tuple(tp))

    def mark(self):
        return len(self.tris)

    def check_solid(self, start, what):
        """Self-check: a closed solid built since `start` must enclose a
        positive volume (i.e. its faces point outwards)."""
        vol = 0.0
        for (a, b, c) in self.tris[start:]:
            vol += vdot(a, vcross(b, c)) / 6.0
        if vol <= 0.0:
            raise AssertionError("%s in %s has inward-facing winding (volume %g)"
                                 % (what, self.name, vol))


# --------------------------------------------------------------------------
# Solid primitives
# --------------------------------------------------------------------------


def box(mb, lo, hi, mat, face_mats=None):
    """Axis-aligned box; face_mats may override '+x','-x','+y','-y','+z','-z'."""
    face_mats = face_mats or {}
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    start = mb.mark()
    faces = [
        ("+x", [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)], (1, 0, 0)),
        ("-x", [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)], (-1, 0, 0)),
        ("+y", [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)], (0, 1, 0)),
        ("-y", [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)], (0, -1, 0)),
        ("+z", [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)], (0, 0, 1)),
        ("-z", [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)], (0, 0, -1)),
    ]
    for key, pts, hint in faces:
        mb.polygon(face_mats.get(key, mat), pts, hint)
    mb.check_solid(start, "box")


def hexahedron(mb, bottom, top, mat, top_mat=None, bottom_mat=None):
    """Convex 6-faced solid from 4 bottom and 4 top corners (same ordering)."""
    start = mb.mark()
    c = vcentroid(list(bottom) + list(top))

    def face(m, pts):
        mb.polygon(m, pts, vsub(vcentroid(pts), c))

    face(bottom_mat or mat, bottom)
    face(top_mat or mat, top)
    for i in range(4):
        j = (i + 1) % 4
        face(mat, [bottom[i], bottom[j], top[j], top[i]])
    mb.check_solid(start, "hexahedron")


def tapered_box(mb, z0, z1, half_bottom, half_top, mat, offset_bottom=(0.0, 0.0),
                offset_top=(0.0, 0.0)):
    """Box-like frustum between z0 and z1 with half extents (hx, hy)."""
    def rect(z, h, o):
        return [(o[0] - h[0], o[1] - h[1], z), (o[0] + h[0], o[1] - h[1], z),
                (o[0] + h[0], o[1] + h[1], z), (o[0] - h[0], o[1] + h[1], z)]
    hexahedron(mb, rect(z0, half_bottom, offset_bottom), rect(z1, half_top, offset_top), mat)


def tube(mb, p0, p1, r0, r1, segments, mat, cap_mat=None):
    """Closed prism/frustum with `segments` sides from p0 (radius r0) to p1 (r1)."""
    start = mb.mark()
    d = vnorm(vsub(p1, p0))
    ref = (0.0, 0.0, 1.0) if abs(d[2]) < 0.9 else (1.0, 0.0, 0.0)
    u = vnorm(vcross(ref, d))
    v = vcross(d, u)
    ring0, ring1, dirs = [], [], []
    for k in range(segments):
        t = 2.0 * math.pi * k / segments
        e = vadd(vmul(u, math.cos(t)), vmul(v, math.sin(t)))
        dirs.append(e)
        ring0.append(vadd(p0, vmul(e, r0)))
        ring1.append(vadd(p1, vmul(e, r1)))
    for k in range(segments):
        j = (k + 1) % segments
        hint = vadd(dirs[k], dirs[j])
        mb.polygon(mat, [ring0[k], ring0[j], ring1[j], ring1[k]], hint)
    mb.polygon(cap_mat or mat, ring0, vmul(d, -1.0))
    mb.polygon(cap_mat or mat, ring1, d)
    mb.check_solid(start, "tube")


def extrude_profile_y(mb, profile, y0, y1, mat):
    """Extrude a simple polygon given in the XZ plane along Y from y0 to y1.

    profile entries are (x, z) or (x, z, material); the material applies to the
    strip of the edge that starts at that point.  Caps use `mat`."""
    pts = [(p[0], p[1]) for p in profile]
    mats = [p[2] if len(p) > 2 else mat for p in profile]
    area2 = 0.0
    for i in range(len(pts)):
        a, b = pts[i], pts[(i + 1) % len(pts)]
        area2 += a[0] * b[1] - b[0] * a[1]
    if area2 < 0:  # make it counter-clockwise in (x, z)
        n = len(pts)
        pts = pts[::-1]
        mats = [mats[(n - 2 - i) % n] for i in range(n)]
    start = mb.mark()
    n = len(pts)
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        ex, ez = b[0] - a[0], b[1] - a[1]
        quad = [(a[0], y0, a[1]), (b[0], y0, b[1]), (b[0], y1, b[1]), (a[0], y1, a[1])]
        mb.polygon(mats[i], quad, (ez, 0.0, -ex))
    mb.polygon(mat, [(p[0], y1, p[1]) for p in pts], (0, 1, 0))
    mb.polygon(mat, [(p[0], y0, p[1]) for p in pts], (0, -1, 0))
    mb.check_solid(start, "y-extrusion")


def extrude_z(mb, poly, z0, z1, top_mat, side_mat=None, bottom_mat=None):
    """Extrude a simple polygon given in the XY plane from z0 to z1."""
    pts = [(p[0], p[1]) for p in poly]
    area2 = 0.0
    for i in range(len(pts)):
        a, b = pts[i], pts[(i + 1) % len(pts)]
        area2 += a[0] * b[1] - b[0] * a[1]
    if area2 < 0:
        pts = pts[::-1]
    start = mb.mark()
    n = len(pts)
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        ex, ey = b[0] - a[0], b[1] - a[1]
        quad = [(a[0], a[1], z0), (b[0], b[1], z0), (b[0], b[1], z1), (a[0], a[1], z1)]
        mb.polygon(side_mat or top_mat, quad, (ey, -ex, 0.0))
    mb.polygon(top_mat, [(p[0], p[1], z1) for p in pts], (0, 0, 1))
    mb.polygon(bottom_mat or side_mat or top_mat, [(p[0], p[1], z0) for p in pts], (0, 0, -1))
    mb.check_solid(start, "z-extrusion")


def icosphere(mb, centre, radii, subdivisions, mat, jitter=0.0, seed=1):
    phi = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, phi, 0), (1, phi, 0), (-1, -phi, 0), (1, -phi, 0),
             (0, -1, phi), (0, 1, phi), (0, -1, -phi), (0, 1, -phi),
             (phi, 0, -1), (phi, 0, 1), (-phi, 0, -1), (-phi, 0, 1)]
    verts = [vnorm(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                cache[key] = len(verts)
                verts.append(vnorm(vmul(vadd(verts[a], verts[b]), 0.5)))
            return cache[key]

        new_faces = []
        for (a, b, c) in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    pts = []
    for i, v in enumerate(verts):
        s = 1.0
        if jitter:
            s = 1.0 + jitter * (2.0 * hash01(i, seed) - 1.0)
        pts.append((centre[0] + v[0] * radii[0] * s,
                    centre[1] + v[1] * radii[1] * s,
                    centre[2] + v[2] * radii[2] * s))
    start = mb.mark()
    for (a, b, c) in faces:
        tri = [pts[a], pts[b], pts[c]]
        mb.polygon(mat, tri, vsub(vcentroid(tri), centre))
    mb.check_solid(start, "icosphere")


def torus_y(mb, centre, major, minor, n_major, n_minor, mat):
    """Torus lying in the XZ plane (axis along Y), e.g. a bicycle tyre."""
    start = mb.mark()

    def ring_point(i, j):
        u = 2.0 * math.pi * i / n_major
        v = 2.0 * math.pi * j / n_minor
        e = (math.cos(u), 0.0, math.sin(u))
        c = vadd(centre, vmul(e, major))
        return vadd(c, vadd(vmul(e, minor * math.cos(v)), (0.0, minor * math.sin(v), 0.0)))

    for i in range(n_major):
        um = 2.0 * math.pi * (i + 0.5) / n_major
        core = vadd(centre, (major * math.cos(um), 0.0, major * math.sin(um)))
        for j in range(n_minor):
            quad = [ring_point(i, j), ring_point(i + 1, j), ring_point(i + 1, j + 1),
                    ring_point(i, j + 1)]
            mb.polygon(mat, quad, vsub(vcentroid(quad), core))
    mb.check_solid(start, "torus")


def panel_pair_y(mb, polys_xz, y, mat):
    """Single-sided panels (e.g. side windows) at +y facing +Y and -y facing -Y."""
    for poly in polys_xz:
        mb.polygon(mat, [(p[0], y, p[1]) for p in poly], (0, 1, 0))
        mb.polygon(mat, [(p[0], -y, p[1]) for p in poly], (0, -1, 0))


def arch(xc, zc, r, steps=6):
    """Wheel-arch points from the rear (xc - r, zc) over the top to (xc + r, zc)."""
    out = []
    for k in range(steps + 1):
        a = math.pi - math.pi * k / steps
        out.append((xc + r * math.cos(a), zc + r * math.sin(a)))
    return out


# --------------------------------------------------------------------------
# Asset container and glTF writer
# --------------------------------------------------------------------------


class Node(object):
    def __init__(self, name, mesh=None, translation=(0.0, 0.0, 0.0), children=None, skin=None):
        self.name = name
        self.mesh = mesh
        self.translation = translation
        self.children = children or []
        self.skin = skin          # index into Asset.skins for a skinned mesh node


class Skin(object):
    """glTF skin.  The inverse bind matrices are not stored here: build_gltf derives
    them from the joints' rest translations, so they cannot drift from the nodes."""

    def __init__(self, name, joints, skeleton):
        self.name = name
        self.joints = joints      # joint node names; a vertex's JOINTS_0 indexes this list
        self.skeleton = skeleton  # name of the skeleton root joint


class Channel(object):
    """One animated node property: times [s] and one value tuple per key."""

    def __init__(self, node, path, times, values, interpolation="LINEAR"):
        self.node = node
        self.path = path          # "translation" or "rotation" (x, y, z, w)
        self.times = times
        self.values = values
        self.interpolation = interpolation


class Animation(object):
    def __init__(self, name, channels, extras=None):
        self.name = name
        self.channels = channels
        self.extras = extras


class Asset(object):
    def __init__(self, name, nodes, roots, description, paint=None, skins=None, animations=None):
        self.name = name
        self.nodes = nodes        # list of Node, index = glTF node index
        self.roots = roots        # names of scene root nodes
        self.description = description
        self.paint = paint        # optional car_paint colour override (RGB)
        self.skins = skins or []
        self.animations = animations or []


def _q(v):
    """Round a coordinate for deterministic, platform-independent output."""
    r = round(v, 6)
    return r + 0.0 if r != 0.0 else 0.0


def _f32(v):
    return struct.unpack("<f", struct.pack("<f", v))[0]


def _f32_short(v):
    """Shortest decimal that round-trips to the same float32 value."""
    f = _f32(v)
    for digits in range(1, 10):
        s = float("%.*g" % (digits, f))
        if _f32(s) == f:
            return s + 0.0 if s != 0.0 else 0.0
    return f


def _round_list(values, nd=6):
    return [round(x, nd) + 0.0 if round(x, nd) != 0.0 else 0.0 for x in values]


def build_gltf(asset):
    buf = bytearray()
    buffer_views, accessors, meshes, materials = [], [], [], []
    mesh_index, mat_index = {}, {}

    def add_view(data, target=None):
        while len(buf) % 4:
            buf.append(0)
        off = len(buf)
        buf.extend(data)
        view = {"buffer": 0, "byteOffset": off, "byteLength": len(data)}
        if target is not None:  # animation and skin data must not name a target
            view["target"] = target
        buffer_views.append(view)
        return len(buffer_views) - 1

    def material(name):
        if name not in mat_index:
            rgba, metallic, rough, refl, note = MATERIALS[name]
            if name == "car_paint" and asset.paint is not None:
                rgba = tuple(asset.paint) + (1.0,)
            entry = {
                "name": name,
                "pbrMetallicRoughness": {
                    "baseColorFactor": _round_list(rgba, 4),
                    "metallicFactor": metallic,
                    "roughnessFactor": rough,
                },
                "extras": {"lidar_reflectivity_1550nm": refl},
            }
            if rgba[3] < 1.0:
                entry["alphaMode"] = "BLEND"
            mat_index[name] = len(materials)
            materials.append(entry)
        return mat_index[name]

    def add_mesh(mb):
        prims = []
        for mat in sorted(mb.prims):
            pos, nor, ind = mb.prims[mat][:3]
            if not ind:
                continue
            qpos = [(_q(p[0]), _q(p[1]), _q(p[2])) for p in pos]
            pdata = b"".join(struct.pack("<3f", *p) for p in qpos)
            ndata = b"".join(struct.pack("<3f", *n) for n in nor)
            f32pos = [tuple(_f32(c) for c in p) for p in qpos]
            pmin = [_f32_short(min(p[i] for p in f32pos)) for i in range(3)]
            pmax = [_f32_short(max(p[i] for p in f32pos)) for i in range(3)]
            if len(pos) < 65536:
                idata = struct.pack("<%dH" % len(ind), *ind)
                ctype = 5123
            else:
                idata = struct.pack("<%dI" % len(ind), *ind)
                ctype = 5125
            pv = add_view(pdata, 34962)
            nv = add_view(ndata, 34962)
            iv = add_view(idata, 34963)
            accessors.append({"bufferView": pv, "componentType": 5126, "count": len(pos),
                              "type": "VEC3", "min": pmin, "max": pmax})
            pa = len(accessors) - 1
            accessors.append({"bufferView": nv, "componentType": 5126, "count": len(nor),
                              "type": "VEC3"})
            na = len(accessors) - 1
            accessors.append({"bufferView": iv, "componentType": ctype, "count": len(ind),
                              "type": "SCALAR"})
            ia = len(accessors) - 1
            attributes = {"POSITION": pa, "NORMAL": na}
            if len(mb.prims[mat]) > 3:
                # skinned mesh: four influences per vertex, joints as unsigned bytes
                joints, weights = mb.prims[mat][3:]
                jv = add_view(b"".join(struct.pack("<4B", *j) for j in joints), 34962)
                wv = add_view(b"".join(struct.pack("<4f", *w) for w in weights), 34962)
                accessors.append({"bufferView": jv, "componentType": 5121, "count": len(joints),
                                  "type": "VEC4"})
                attributes["JOINTS_0"] = len(accessors) - 1
                accessors.append({"bufferView": wv, "componentType": 5126, "count": len(weights),
                                  "type": "VEC4"})
                attributes["WEIGHTS_0"] = len(accessors) - 1
            prims.append({"attributes": attributes, "indices": ia,
                          "material": material(mat), "mode": 4})
        meshes.append({"name": mb.name, "primitives": prims})
        return len(meshes) - 1

    name_to_index = {n.name: i for i, n in enumerate(asset.nodes)}
    nodes = []
    for n in asset.nodes:
        entry = {"name": n.name}
        if n.mesh is not None:
            if id(n.mesh) not in mesh_index:
                mesh_index[id(n.mesh)] = add_mesh(n.mesh)
            entry["mesh"] = mesh_index[id(n.mesh)]
        if any(abs(t) > 0.0 for t in n.translation):
            entry["translation"] = _round_list(n.translation)
        if n.children:
            entry["children"] = [name_to_index[c] for c in n.children]
        if n.skin is not None:
            entry["skin"] = n.skin
        nodes.append(entry)

    # Skins: the inverse bind matrix of a joint is the exact inverse of its global rest
    # transform.  Rest transforms are pure translations (see Node), so it is the negated
    # sum of the translations from the scene root down to the joint.
    skins = []
    for sk in asset.skins:
        ibm = []
        for j in sk.joints:
            g = global_translation(asset, j)
            # column-major 4x4: identity rotation, translation -g in the last column
            ibm.extend([1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
                        _q(-g[0]), _q(-g[1]), _q(-g[2]), 1.0])
        view = add_view(struct.pack("<%df" % len(ibm), *ibm))
        accessors.append({"bufferView": view, "componentType": 5126, "count": len(sk.joints),
                          "type": "MAT4"})
        skins.append({"name": sk.name, "joints": [name_to_index[j] for j in sk.joints],
                      "inverseBindMatrices": len(accessors) - 1,
                      "skeleton": name_to_index[sk.skeleton]})

    # Animations: key times shared by several channels share one input accessor.
    animations = []
    time_accessor = {}
    for anim in asset.animations:
        samplers, channels = [], []
        for ch in anim.channels:
            key = tuple(ch.times)
            if key not in time_accessor:
                view = add_view(struct.pack("<%df" % len(ch.times), *ch.times))
                f32t = [_f32(t) for t in ch.times]
                accessors.append({"bufferView": view, "componentType": 5126,
                                  "count": len(ch.times), "type": "SCALAR",
                                  "min": [_f32_short(min(f32t))], "max": [_f32_short(max(f32t))]})
                time_accessor[key] = len(accessors) - 1
            width = len(ch.values[0])
            flat = [_q(c) for v in ch.values for c in v]
            view = add_view(struct.pack("<%df" % len(flat), *flat))
            accessors.append({"bufferView": view, "componentType": 5126, "count": len(ch.values),
                              "type": "VEC%d" % width})
            samplers.append({"input": time_accessor[key], "output": len(accessors) - 1,
                             "interpolation": ch.interpolation})
            channels.append({"sampler": len(samplers) - 1,
                             "target": {"node": name_to_index[ch.node], "path": ch.path}})
        entry = {"name": anim.name, "samplers": samplers, "channels": channels}
        if anim.extras:
            entry["extras"] = anim.extras
        animations.append(entry)

    while len(buf) % 4:
        buf.append(0)
    gltf = {
        "asset": {
            "version": "2.0",
            "generator": "tools/assets/generate_assets.py (procedural, deterministic)",
            "copyright": "FMCW LiDAR simulator project contributors; licensed under Apache-2.0",
            "extras": {"frame": FRAME_NOTE, "units": "metre", "description": asset.description},
        },
        "scene": 0,
        "scenes": [{"name": asset.name, "nodes": [name_to_index[r] for r in asset.roots]}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{
            "byteLength": len(buf),
            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode("ascii"),
        }],
    }
    if skins:
        gltf["skins"] = skins
    if animations:
        gltf["animations"] = animations
    return json.dumps(gltf, indent=1, sort_keys=True, ensure_ascii=True) + "\n"


def global_translation(asset, name):
    """Rest position of a node's origin: the sum of the translations from the scene
    root down to it (translation is the only rest transform used)."""
    parent = {}
    for n in asset.nodes:
        for c in n.children:
            parent[c] = n.name
    by_name = {n.name: n for n in asset.nodes}
    off = [0.0, 0.0, 0.0]
    while name is not None:
        t = by_name[name].translation
        off = [off[i] + t[i] for i in range(3)]
        name = parent.get(name)
    return off


def world_bbox(asset):
    """Bounding box after applying node translations (the only transform used)."""
    lo = [float("inf")] * 3
    hi = [float("-inf")] * 3
    tris = 0
    for n in asset.nodes:
        if n.mesh is None:
            continue
        off = global_translation(asset, n.name)
        tris += n.mesh.triangle_count()
        for prim in n.mesh.prims.values():
            for p in prim[0]:
                for i in range(3):
                    lo[i] = min(lo[i], p[i] + off[i])
                    hi[i] = max(hi[i], p[i] + off[i])
    return lo, hi, tris


# --------------------------------------------------------------------------
# Vehicles
# --------------------------------------------------------------------------


def wheel_mesh(name, radius, width, rim_radius, segments=12):
    """Wheel centred on the node origin, axle along local Y."""
    mb = MeshBuilder(name)
    h = width / 2.0
    tube(mb, (0.0, -h + 0.005, 0.0), (0.0, h - 0.005, 0.0), radius, radius, segments, "tire")
    tube(mb, (0.0, -h, 0.0), (0.0, h, 0.0), rim_radius, rim_radius, segments, "metal")
    return mb


def vehicle_asset(name, body, wheel, wheel_positions, description, paint):
    nodes = [Node("body", body)]
    for wname, pos in wheel_positions:
        nodes.append(Node(wname, wheel, pos))
    return Asset(name, nodes, [n.name for n in nodes], description, paint)


CAR_WHEEL_RADIUS = 0.32  # shared by car and car_keyframed (its roll clip's nominal speed)


def build_car():
    body = MeshBuilder("car_body")
    # side profile of the lower body (x, z[, material of the edge starting here])
    prof = [(-2.18, 0.30)]
    prof += arch(-1.35, 0.30, 0.42)
    prof += arch(1.35, 0.30, 0.42)
    prof += [(2.15, 0.30, "plastic"), (2.25, 0.42, "plastic"), (2.25, 0.66), (2.12, 0.82),
             (0.85, 0.96), (-1.75, 0.99), (-2.20, 0.96), (-2.25, 0.82, "plastic"),
             (-2.25, 0.40, "plastic")]
    extrude_profile_y(body, prof, -0.90, 0.90, "car_paint")
    # floor filling the channel between the wheel arches
    box(body, (-1.80, -0.62, 0.30), (1.80, 0.62, 0.74), "car_paint", {"-z": "plastic"})
    # cabin / greenhouse, narrower than the body
    cabin = [(-1.76, 0.92), (0.86, 0.92), (0.86, 0.96, "glass"), (-0.05, 1.42),
             (-0.15, 1.45), (-1.00, 1.45, "glass"), (-1.10, 1.42), (-1.76, 0.99)]
    extrude_profile_y(body, cabin, -0.77, 0.77, "car_paint")
    panel_pair_y(body, [
        [(0.70, 1.00), (-0.06, 1.38), (-0.45, 1.38), (-0.45, 1.00)],
        [(-0.55, 1.00), (-0.55, 1.38), (-1.06, 1.38), (-1.62, 1.00)],
    ], 0.773, "glass")
    # head and tail lights
    for y in (-0.62, 0.62):
        box(body, (2.20, y - 0.16, 0.68), (2.235, y + 0.16, 0.76), "glass")
        box(body, (-2.245, y - 0.15, 0.80), (-2.215, y + 0.15, 0.90), "plastic")
    # side mirrors
    for s in (-1.0, 1.0):
        box(body, (0.55, min(s * 0.76, s * 0.92), 1.00), (0.68, max(s * 0.76, s * 0.92), 1.10), "car_paint")
    r = CAR_WHEEL_RADIUS
    wheel = wheel_mesh("car_wheel", r, 0.23, 0.20)
    y = 0.785
    pos = [("wheel_fl", (1.35, y, r)), ("wheel_fr", (1.35, -y, r)),
           ("wheel_rl", (-1.35, y, r)), ("wheel_rr", (-1.35, -y, r))]
    return vehicle_asset("car", body, wheel, pos, "passenger car ~4.5 x 1.8 x 1.45 m",
                         (0.55, 0.06, 0.06))


def build_van():
    body = MeshBuilder("van_body")
    prof = [(-2.55, 0.33)]
    prof += arch(-1.60, 0.33, 0.46)
    prof += arch(1.70, 0.33, 0.46)
    prof += [(2.50, 0.33, "plastic"), (2.60, 0.45, "plastic"), (2.60, 0.82), (2.50, 1.06),
             (1.85, 1.16, "glass"), (1.15, 2.05), (1.00, 2.20), (-2.50, 2.20),
             (-2.60, 2.10), (-2.60, 0.48, "plastic")]
    extrude_profile_y(body, prof, -1.0, 1.0, "car_paint")
    box(body, (-2.10, -0.72, 0.33), (2.20, 0.72, 0.80), "car_paint", {"-z": "plastic"})
    panel_pair_y(body, [[(1.76, 1.24), (1.12, 2.02), (0.40, 2.02), (0.40, 1.24)],
                        [(-0.30, 1.30), (-0.30, 1.95), (-1.40, 1.95), (-1.40, 1.30)]],
                 1.003, "glass")
    for y0, y1 in ((0.08, 0.86), (-0.86, -0.08)):
        body.polygon("glass", [(-2.603, y0, 1.40), (-2.603, y1, 1.40), (-2.603, y1, 1.98),
                               (-2.603, y0, 1.98)], (-1, 0, 0))
    for y in (-0.72, 0.72):
        box(body, (2.55, y - 0.15, 0.86), (2.585, y + 0.15, 0.98), "glass")
    # mirrors: must stay within the 2.0 m body width, so they sit on the A-pillar
    for s in (-1.0, 1.0):
        box(body, (1.62, min(s * 0.90, s * 1.0), 1.30), (1.74, max(s * 0.90, s * 1.0), 1.55),
            "plastic")
    wheel = wheel_mesh("van_wheel", 0.35, 0.24, 0.22)
    y = 0.88
    pos = [("wheel_fl", (1.70, y, 0.35)), ("wheel_fr", (1.70, -y, 0.35)),
           ("wheel_rl", (-1.60, y, 0.35)), ("wheel_rr", (-1.60, -y, 0.35))]
    return vehicle_asset("van", body, wheel, pos, "delivery van ~5.2 x 2.0 x 2.2 m",
                         (0.88, 0.88, 0.86))


def build_truck():
    body = MeshBuilder("truck_body")
    # cab
    prof = [(2.30, 0.55)]
    prof += arch(3.30, 0.55, 0.62)
    prof += [(4.40, 0.55, "plastic"), (4.50, 0.70, "plastic"), (4.50, 1.40), (4.45, 1.65),
             (4.40, 1.72, "glass"), (4.28, 2.70), (4.18, 2.95), (2.40, 3.00), (2.30, 2.90)]
    extrude_profile_y(body, prof, -1.20, 1.20, "car_paint")
    box(body, (2.40, -0.88, 0.55), (4.30, 0.88, 1.20), "car_paint", {"-z": "metal"})
    panel_pair_y(body, [[(4.15, 1.75), (4.05, 2.55), (3.40, 2.55), (3.40, 1.75)]], 1.203, "glass")
    for y in (-0.95, 0.95):
        box(body, (4.46, y - 0.15, 1.10), (4.505, y + 0.15, 1.25), "glass")
    # chassis frame, fuel tank, rear bumper
    box(body, (-4.40, -0.45, 0.62), (4.30, 0.45, 1.00), "metal")
    box(body, (0.80, 0.60, 0.55), (2.00, 1.05, 1.05), "metal")
    box(body, (-4.50, -1.10, 0.50), (-4.38, 1.10, 0.66), "metal")
    # box trailer
    box(body, (-4.50, -1.25, 1.15), (2.10, 1.25, 3.50), "metal", {"-z": "plastic"})
    wheel = wheel_mesh("truck_wheel", 0.50, 0.30, 0.30)
    y = 1.10
    pos = [("wheel_fl", (3.30, y, 0.50)), ("wheel_fr", (3.30, -y, 0.50)),
           ("wheel_ml", (-2.30, y, 0.50)), ("wheel_mr", (-2.30, -y, 0.50)),
           ("wheel_rl", (-3.60, y, 0.50)), ("wheel_rr", (-3.60, -y, 0.50))]
    return vehicle_asset("truck", body, wheel, pos,
                         "box truck ~9 x 2.5 x 3.5 m (cab + box body, 3 axles)",
                         (0.10, 0.22, 0.55))


def build_bus():
    body = MeshBuilder("bus_body")
    prof = [(-5.95, 0.30)]
    prof += arch(-2.70, 0.30, 0.75, 8)
    prof += arch(3.30, 0.30, 0.75, 8)
    prof += [(5.95, 0.30, "plastic"), (6.00, 0.40), (6.00, 2.85), (5.85, 3.00),
             (-5.85, 3.00), (-6.00, 2.85), (-6.00, 0.40, "plastic")]
    extrude_profile_y(body, prof, -1.275, 1.275, "car_paint")
    box(body, (-5.80, -0.92, 0.30), (5.80, 0.92, 1.00), "car_paint", {"-z": "plastic"})
    # roof air-conditioning unit
    box(body, (-1.20, -0.85, 2.95), (1.20, 0.85, 3.10), "plastic")
    # window band: 7 side windows with pillars, both sides
    windows = []
    x = -5.70
    for w in (1.30, 1.45, 1.45, 1.45, 1.45, 1.45, 1.45):
        windows.append([(x, 1.25), (x + w, 1.25), (x + w, 2.55), (x, 2.55)])
        x += w + 0.12
    panel_pair_y(body, windows, 1.278, "glass")
    # front doors on the right-hand (-Y) side, driver window on the left
    body.polygon("glass", [(4.35, -1.278, 0.45), (5.55, -1.278, 0.45), (5.55, -1.278, 2.60),
                           (4.35, -1.278, 2.60)], (0, -1, 0))
    body.polygon("glass", [(4.60, 1.278, 1.25), (5.60, 1.278, 1.25), (5.60, 1.278, 2.55),
                           (4.60, 1.278, 2.55)], (0, 1, 0))
    # windscreen and rear window
    body.polygon("glass", [(6.003, -1.15, 1.05), (6.003, 1.15, 1.05), (6.003, 1.15, 2.75),
                           (6.003, -1.15, 2.75)], (1, 0, 0))
    body.polygon("glass", [(-6.003, -1.0, 1.60), (-6.003, 1.0, 1.60), (-6.003, 1.0, 2.60),
                           (-6.003, -1.0, 2.60)], (-1, 0, 0))
    for y in (-1.0, 1.0):
        box(body, (5.97, y - 0.15, 0.60), (6.005, y + 0.15, 0.75), "glass")
    wheel = wheel_mesh("bus_wheel", 0.50, 0.30, 0.30)
    y = 1.125
    pos = [("wheel_fl", (3.30, y, 0.50)), ("wheel_fr", (3.30, -y, 0.50)),
           ("wheel_rl", (-2.70, y, 0.50)), ("wheel_rr", (-2.70, -y, 0.50))]
    return vehicle_asset("bus", body, wheel, pos, "city bus ~12 x 2.55 x 3.1 m",
                         (0.95, 0.70, 0.10))


def bicycle_wheel_mesh():
    mb = MeshBuilder("bicycle_wheel")
    torus_y(mb, (0.0, 0.0, 0.0), 0.32, 0.02, 16, 6, "tire")
    tube(mb, (0.0, -0.05, 0.0), (0.0, 0.05, 0.0), 0.03, 0.03, 8, "metal")
    for k in range(8):
        a = 2.0 * math.pi * (k + 0.5) / 8.0
        e = (math.cos(a), 0.0, math.sin(a))
        side = 0.035 if k % 2 == 0 else -0.035
        p0 = vadd(vmul(e, 0.028), (0.0, side, 0.0))
        p1 = vmul(e, 0.305)
        tube(mb, p0, p1, 0.004, 0.004, 4, "metal")
    return mb


def build_cyclist():
    mb = MeshBuilder("cyclist_body")
    rear, front = (-0.55, 0.0, 0.34), (0.55, 0.0, 0.34)
    bb = (-0.05, 0.0, 0.27)
    seat_top = (-0.22, 0.0, 0.85)
    head_top = (0.38, 0.0, 0.82)
    head_bot = (0.42, 0.0, 0.66)
    r = 0.018
    tube(mb, bb, seat_top, r, r, 6, "metal")               # seat tube
    tube(mb, seat_top, head_top, r, r, 6, "metal")         # top tube
    tube(mb, bb, head_bot, 0.022, 0.022, 6, "metal")       # down tube
    tube(mb, head_bot, head_top, 0.025, 0.025, 6, "metal")  # head tube
    for s in (-1.0, 1.0):
        tube(mb, (rear[0], s * 0.055, rear[2]), (bb[0], s * 0.02, bb[2]), 0.011, 0.011, 6, "metal")
        tube(mb, (rear[0], s * 0.055, rear[2]), (seat_top[0], s * 0.015, seat_top[2] - 0.03),
             0.010, 0.010, 6, "metal")
        tube(mb, (head_bot[0], s * 0.03, head_bot[2]), (front[0], s * 0.055, front[2]),
             0.012, 0.012, 6, "metal")
    # seat post + saddle, stem + handlebar
    tube(mb, seat_top, (-0.235, 0.0, 0.93), 0.014, 0.014, 6, "metal")
    box(mb, (-0.35, -0.07, 0.93), (-0.12, 0.07, 0.97), "plastic")
    tube(mb, head_top, (0.40, 0.0, 0.97), 0.016, 0.016, 6, "metal")
    tube(mb, (0.40, -0.30, 0.97), (0.40, 0.30, 0.97), 0.013, 0.013, 6, "metal")
    # crank arms and pedals (left forward, right back)
    tube(mb, (bb[0], -0.09, bb[2]), (bb[0], 0.09, bb[2]), 0.02, 0.02, 6, "metal")
    lp = (bb[0] + 0.17, 0.11, bb[2])
    rp = (bb[0] - 0.17, -0.11, bb[2])
    tube(mb, (bb[0], 0.09, bb[2]), (lp[0], 0.09, lp[2]), 0.01, 0.01, 4, "metal")
    tube(mb, (bb[0], -0.09, bb[2]), (rp[0], -0.09, rp[2]), 0.01, 0.01, 4, "metal")
    for p in (lp, rp):
        box(mb, (p[0] - 0.05, p[1] - 0.04, p[2] - 0.012), (p[0] + 0.05, p[1] + 0.04, p[2] + 0.012),
            "plastic")
    # rider: torso leaning forward, head, arms to the bar, legs to the pedals
    hip = (-0.20, 0.0, 1.00)
    shoulder = (0.12, 0.0, 1.43)
    tube(mb, hip, shoulder, 0.15, 0.16, 8, "cloth")
    tube(mb, vadd(shoulder, (0.0, 0.0, -0.02)), (0.18, 0.0, 1.55), 0.05, 0.05, 6, "skin")
    icosphere(mb, (0.22, 0.0, 1.64), (0.11, 0.09, 0.11), 1, "skin")
    for s in (-1.0, 1.0):
        sh = (0.12, s * 0.19, 1.41)
        el = (0.26, s * 0.23, 1.17)
        hand = (0.39, s * 0.24, 0.98)
        tube(mb, sh, el, 0.05, 0.045, 6, "cloth")
        tube(mb, el, hand, 0.042, 0.035, 6, "skin")
    for hp, kn, pd in (((-0.20, 0.10, 0.98), (0.12, 0.12, 0.70), (lp[0], 0.13, lp[2] + 0.02)),
                       ((-0.20, -0.10, 0.98), (0.00, -0.12, 0.60), (rp[0], -0.13, rp[2] + 0.02))):
        tube(mb, hp, kn, 0.08, 0.06, 8, "cloth")
        tube(mb, kn, pd, 0.055, 0.045, 8, "cloth")
        box(mb, (pd[0] - 0.06, pd[1] - 0.045, pd[2] - 0.005), (pd[0] + 0.14, pd[1] + 0.045, pd[2] + 0.06),
            "cloth")
    wheel = bicycle_wheel_mesh()
    nodes = [Node("body", mb), Node("wheel_front", wheel, front), Node("wheel_rear", wheel, rear)]
    return Asset("cyclist", nodes, ["body", "wheel_front", "wheel_rear"],
                 "cyclist on a bicycle ~1.8 x 0.6 x 1.75 m")


# --------------------------------------------------------------------------
# Pedestrian (articulated)
# --------------------------------------------------------------------------


def build_pedestrian():
    pelvis = MeshBuilder("pelvis")
    tapered_box(pelvis, -0.10, 0.12, (0.10, 0.16), (0.10, 0.15), "cloth")

    torso = MeshBuilder("torso")
    tapered_box(torso, -0.02, 0.38, (0.10, 0.15), (0.11, 0.20), "cloth")
    tapered_box(torso, 0.38, 0.46, (0.11, 0.20), (0.08, 0.13), "cloth")

    head = MeshBuilder("head")
    tube(head, (0.0, 0.0, -0.03), (0.0, 0.0, 0.06), 0.05, 0.05, 8, "skin")
    icosphere(head, (0.01, 0.0, 0.135), (0.10, 0.085, 0.115), 1, "skin")

    upper_arm = MeshBuilder("upper_arm")
    tube(upper_arm, (0.0, 0.0, 0.0), (0.0, 0.0, -0.30), 0.055, 0.045, 8, "cloth")

    lower_arm = MeshBuilder("lower_arm")
    tube(lower_arm, (0.0, 0.0, 0.0), (0.0, 0.0, -0.24), 0.045, 0.036, 8, "cloth")
    tapered_box(lower_arm, -0.40, -0.23, (0.035, 0.018), (0.04, 0.03), "skin")

    upper_leg = MeshBuilder("upper_leg")
    tube(upper_leg, (0.0, 0.0, 0.0), (0.0, 0.0, -0.43), 0.08, 0.06, 8, "cloth")

    lower_leg = MeshBuilder("lower_leg")
    tube(lower_leg, (0.0, 0.0, 0.0), (0.0, 0.0, -0.41), 0.058, 0.045, 8, "cloth")
    tapered_box(lower_leg, -0.47, -0.40, (0.12, 0.05), (0.10, 0.045), "cloth",
                offset_bottom=(0.04, 0.0), offset_top=(0.03, 0.0))

    nodes = [
        Node("pelvis", pelvis, (0.0, 0.0, 0.95), ["torso", "upper_leg_l", "upper_leg_r"]),
        Node("torso", torso, (0.0, 0.0, 0.10), ["head", "upper_arm_l", "upper_arm_r"]),
        Node("head", head, (0.0, 0.0, 0.45)),
        Node("upper_arm_l", upper_arm, (0.0, 0.22, 0.40), ["lower_arm_l"]),
        Node("lower_arm_l", lower_arm, (0.0, 0.0, -0.30)),
        Node("upper_arm_r", upper_arm, (0.0, -0.22, 0.40), ["lower_arm_r"]),
        Node("lower_arm_r", lower_arm, (0.0, 0.0, -0.30)),
        Node("upper_leg_l", upper_leg, (0.0, 0.09, -0.05), ["lower_leg_l"]),
        Node("lower_leg_l", lower_leg, (0.0, 0.0, -0.43)),
        Node("upper_leg_r", upper_leg, (0.0, -0.09, -0.05), ["lower_leg_r"]),
        Node("lower_leg_r", lower_leg, (0.0, 0.0, -0.43)),
    ]
    return Asset("pedestrian", nodes, ["pelvis"],
                 "articulated pedestrian ~1.75 m; node translations are joint pivots")


# --------------------------------------------------------------------------
# Skinned walker (linear blend skinning, keyframed clips)
# --------------------------------------------------------------------------


class SkinnedMeshBuilder(object):
    """Smooth-shaded mesh for skinning: one primitive per material, vertices shared
    within a shell, each vertex with four (joint, weight) influences."""

    def __init__(self, name):
        self.name = name
        self.prims = {}  # material -> (positions, normals, indices, joints, weights)
        self.tris = []

    # same bookkeeping as MeshBuilder (self-checks, triangle count)
    mark = MeshBuilder.mark
    check_solid = MeshBuilder.check_solid
    triangle_count = MeshBuilder.triangle_count

    def shell(self, mat, pts, faces, influences):
        """Add a closed surface: pts, faces (counter-clockwise seen from outside) and
        per-vertex influence dicts {joint index: weight}.  Normals are the area-weighted
        average of the adjacent faces, i.e. smooth across the whole shell."""
        if mat not in MATERIALS:
            raise ValueError("unknown material %r" % mat)
        if mat not in self.prims:
            self.prims[mat] = ([], [], [], [], [])
        pos, nor, ind, jnt, wgt = self.prims[mat]
        qpts = [(_q(p[0]), _q(p[1]), _q(p[2])) for p in pts]
        acc = [(0.0, 0.0, 0.0)] * len(qpts)
        start = self.mark()
        for (a, b, c) in faces:
            g = vcross(vsub(qpts[b], qpts[a]), vsub(qpts[c], qpts[a]))
            if vlen(g) < 2e-10:
                raise ValueError("degenerate triangle in shell of %s" % self.name)
            for v in (a, b, c):
                acc[v] = vadd(acc[v], g)
            self.tris.append((qpts[a], qpts[b], qpts[c]))
        self.check_solid(start, "shell")
        base = len(pos)
        for p, n, infl in zip(qpts, acc, influences):
            pos.append(p)
            # rounded like the positions so the file does not depend on the last bit of libm
            nor.append(tuple(_q(c) for c in vnorm(n)))
            j, w = pack_influences(infl)
            jnt.append(j)
            wgt.append(w)
        ind.extend(base + v for f in faces for v in f)


def pack_influences(infl):
    """{joint: weight} -> (4 joint indices, 4 weights): largest first, weights rounded
    to 1e-6 and renormalised so they still sum to 1; unused slots are joint 0, weight 0."""
    items = sorted(((w, j) for j, w in infl.items() if w > 1e-6), key=lambda x: (-x[0], x[1]))
    if not items or len(items) > 4:
        raise ValueError("a vertex needs 1 to 4 influences, got %r" % (infl,))
    total = sum(w for w, _ in items)
    ws = [round(w / total, 6) for w, _ in items]
    ws[0] = round(1.0 - sum(ws[1:]), 6)  # the rounding error goes to the largest weight
    joints = [j for _, j in items] + [0] * (4 - len(items))
    return tuple(joints), tuple(ws + [0.0] * (4 - len(items)))


def _hermite_profile(stations, s):
    """Radii/offsets at axial position s: cubic Hermite through the stations (s, values...)
    with centred-difference slopes, zero slope at both ends so the caps join smoothly."""
    n = len(stations)
    k = 0
    while k < n - 2 and s > stations[k + 1][0]:
        k += 1
    s0, s1 = stations[k][0], stations[k + 1][0]
    h = s1 - s0
    t = min(max((s - s0) / h, 0.0), 1.0)

    def slope(i, c):
        if i == 0 or i == n - 1:
            return 0.0
        return (stations[i + 1][c] - stations[i - 1][c]) / (stations[i + 1][0] - stations[i - 1][0])

    h00 = 2 * t ** 3 - 3 * t ** 2 + 1
    h10 = t ** 3 - 2 * t ** 2 + t
    h01 = -2 * t ** 3 + 3 * t ** 2
    h11 = t ** 3 - t ** 2
    return tuple(h00 * stations[k][c] + h10 * h * slope(k, c) + h01 * stations[k + 1][c]
                 + h11 * h * slope(k + 1, c) for c in range(1, len(stations[0])))


def loft(sb, mat, origin, axis, forward, stations, segments, caps, weight_fn,
         cap_rings=4, ring_step=0.04):
    """Closed smooth solid around an axis: elliptical rings through `stations`
    (s, r_forward, r_side[, d_forward, d_side]) -- s along `axis` from `origin`, radii along
    `forward` (made perpendicular to the axis) and the side direction, optional centre
    offsets -- closed by half-ellipsoid caps of depth caps = (before first, after last)
    ending in a pole.  weight_fn(point) gives the vertex influences.  Returns the
    vertices (bind pose)."""
    a = vnorm(axis)
    u = vnorm(vsub(forward, vmul(a, vdot(forward, a))))
    v = vcross(a, u)  # (u, v, a) right-handed: ring order is counter-clockwise about a
    stations = [tuple(st) + (0.0,) * (5 - len(st)) for st in stations]
    rings = []  # (s, ru, rv, du, dv)
    first, last = stations[0], stations[-1]
    for j in range(1, cap_rings):
        th = 0.5 * math.pi * j / cap_rings  # angle from the pole
        rings.append((first[0] - caps[0] * math.cos(th), first[1] * math.sin(th),
                      first[2] * math.sin(th), first[3], first[4]))
    for k in range(len(stations) - 1):
        s0, s1 = stations[k][0], stations[k + 1][0]
        steps = max(1, int(math.ceil((s1 - s0) / ring_step - 1e-9)))
        for i in range(steps):
            s = s0 + (s1 - s0) * i / steps
            rings.append((s,) + _hermite_profile(stations, s))
    rings.append(last)
    for j in range(cap_rings - 1, 0, -1):
        th = 0.5 * math.pi * j / cap_rings
        rings.append((last[0] + caps[1] * math.cos(th), last[1] * math.sin(th),
                      last[2] * math.sin(th), last[3], last[4]))

    def point(s, cu, cv):
        return vadd(origin, vadd(vmul(a, s), vadd(vmul(u, cu), vmul(v, cv))))

    pts = [point(first[0] - caps[0], first[3], first[4])]
    for (s, ru, rv, du, dv) in rings:
        for k in range(segments):
            t = 2.0 * math.pi * k / segments
            pts.append(point(s, du + ru * math.cos(t), dv + rv * math.sin(t)))
    pts.append(point(last[0] + caps[1], last[3], last[4]))
    top = len(pts) - 1

    def ring_vertex(i, k):
        return 1 + i * segments + k % segments

    faces = []
    for k in range(segments):
        faces.append((0, ring_vertex(0, k + 1), ring_vertex(0, k)))
    for i in range(len(rings) - 1):
        for k in range(segments):
            a0, a1 = ring_vertex(i, k), ring_vertex(i, k + 1)
            b0, b1 = ring_vertex(i + 1, k), ring_vertex(i + 1, k + 1)
            faces.append((a0, a1, b1))
            faces.append((a0, b1, b0))
    for k in range(segments):
        faces.append((top, ring_vertex(len(rings) - 1, k), ring_vertex(len(rings) - 1, k + 1)))
    sb.shell(mat, pts, faces, [weight_fn(p) for p in pts])
    return pts


# Skeleton: (joint, parent joint, rest translation relative to the parent).  The order is
# the order of skin.joints, i.e. the values of JOINTS_0.  Rest rotations are identity, so
# each joint's frame is parallel to the model frame and the inverse bind matrices are pure
# translations.  Proportions follow the pedestrian (hip joints 0.90 m, knees 0.47 m).
WALKER_SKELETON = [
    ("hips", None, (0.0, 0.0, 0.95)),              # pelvis centre, root joint
    ("spine", "hips", (0.0, 0.0, 0.12)),           # lower spine, 1.07 m
    ("neck", "spine", (0.0, 0.0, 0.40)),           # base of the neck, 1.47 m
    ("head", "neck", (0.0, 0.0, 0.10)),            # skull base, 1.57 m
    ("upper_leg_l", "hips", (0.0, 0.09, -0.05)),   # hip joint
    ("lower_leg_l", "upper_leg_l", (0.0, 0.0, -0.43)),  # knee
    ("foot_l", "lower_leg_l", (0.0, 0.0, -0.39)),  # ankle, 0.08 m above the sole
    ("upper_leg_r", "hips", (0.0, -0.09, -0.05)),
    ("lower_leg_r", "upper_leg_r", (0.0, 0.0, -0.43)),
    ("foot_r", "lower_leg_r", (0.0, 0.0, -0.39)),
    ("upper_arm_l", "spine", (0.0, 0.18, 0.34)),   # shoulder
    ("lower_arm_l", "upper_arm_l", (0.0, 0.03, -0.29)),  # elbow; arm slightly abducted
    ("upper_arm_r", "spine", (0.0, -0.18, 0.34)),
    ("lower_arm_r", "upper_arm_r", (0.0, -0.03, -0.29)),
]
WALKER_WRIST = (0.0, 0.01, -0.26)  # wrist relative to the elbow (y mirrored on the right)
WALKER_LEG_LENGTH = 0.90           # hip joint to sole, for the hip swing amplitude


def _clamp01(x):
    return min(max(x, 0.0), 1.0)


def build_walker_mesh(joint_pos):
    """Body shells in the bind pose.  Each shell follows one bone; near a joint its
    vertices blend linearly into the neighbouring bone (see the weight terms below).
    Returns the mesh and, per side, the shoe's sole vertices (bind pose), which the
    walk clip keeps on the ground."""
    sb = SkinnedMeshBuilder("walker_body")
    index = {name: i for i, (name, _, _) in enumerate(WALKER_SKELETON)}
    d_blend = 0.04  # half-width of the blend band across a joint

    def axial(joint, axis, d):
        """Share of the bone beyond `joint` (along `axis`): 0.5 at the joint, rising
        linearly to 1 at d past it and falling to 0 at d before it."""
        J = joint_pos[joint]
        return lambda p: _clamp01(0.5 + 0.5 * vdot(vsub(p, J), axis) / d)

    def radial(joint, radius):
        """Share of a bone attached beside the shell (shoulder on the torso, legs on the
        pelvis, ankle on the foot): 0.5 at the joint, 0 beyond `radius`."""
        J = joint_pos[joint]
        return lambda p: 0.5 * _clamp01(1.0 - vlen(vsub(p, J)) / radius)

    def weights(bone, terms):
        """terms: (other joint, share function); the bone keeps the rest."""
        def fn(p):
            infl = {}
            for other, share in terms:
                w = share(p)
                if w > 0.0:
                    infl[index[other]] = infl.get(index[other], 0.0) + w
            rest = 1.0 - sum(infl.values())
            if rest < -1e-9:
                raise ValueError("blend shares exceed 1 on bone %s" % bone)
            infl[index[bone]] = infl.get(index[bone], 0.0) + max(rest, 0.0)
            return infl
        return fn

    up, down = (0.0, 0.0, 1.0), (0.0, 0.0, -1.0)
    fwd = (1.0, 0.0, 0.0)
    O = (0.0, 0.0, 0.0)
    soles = {}

    def inv(f):
        return lambda p: 1.0 - f(p)

    # pelvis: spine above, both thighs beside -> the crotch gets three influences
    loft(sb, "cloth", (-0.01, 0.0, 0.0), up, fwd,
         [(0.86, 0.10, 0.15), (0.92, 0.115, 0.165), (0.99, 0.11, 0.16), (1.05, 0.10, 0.145)],
         20, (0.05, 0.03),
         weights("hips", [("spine", axial("spine", up, d_blend)),
                          ("upper_leg_l", radial("upper_leg_l", 0.15)),
                          ("upper_leg_r", radial("upper_leg_r", 0.15))]))
    # torso: waist to shoulders; the shoulder tops follow the arms a little
    loft(sb, "cloth", O, up, fwd,
         [(1.02, 0.10, 0.14), (1.10, 0.10, 0.135), (1.20, 0.11, 0.145), (1.30, 0.12, 0.155),
          (1.38, 0.115, 0.165), (1.44, 0.10, 0.175)],
         20, (0.03, 0.05),
         weights("spine", [("hips", inv(axial("spine", up, d_blend))),
                           ("upper_arm_l", radial("upper_arm_l", 0.10)),
                           ("upper_arm_r", radial("upper_arm_r", 0.10))]))
    loft(sb, "skin", O, up, fwd,
         [(1.45, 0.05, 0.055), (1.53, 0.045, 0.05), (1.60, 0.045, 0.048)],
         12, (0.02, 0.02),
         weights("neck", [("spine", inv(axial("neck", up, 0.03))),
                          ("head", axial("head", up, 0.03))]))
    # head: an ellipsoid (a single station with two half-ellipsoid caps)
    loft(sb, "skin", (0.01, 0.0, 0.0), up, fwd, [(1.645, 0.10, 0.08)], 20, (0.11, 0.11),
         weights("head", [("neck", inv(axial("head", up, 0.03)))]), cap_rings=8)

    for side, sy in (("l", 1.0), ("r", -1.0)):
        hip, knee, ankle = (joint_pos["upper_leg_" + side], joint_pos["lower_leg_" + side],
                            joint_pos["foot_" + side])
        shoulder, elbow = joint_pos["upper_arm_" + side], joint_pos["lower_arm_" + side]
        wrist = vadd(elbow, (WALKER_WRIST[0], sy * WALKER_WRIST[1], WALKER_WRIST[2]))
        thigh_dir = vnorm(vsub(knee, hip))
        shin_dir = vnorm(vsub(ankle, knee))
        upper_arm_dir = vnorm(vsub(elbow, shoulder))
        forearm_dir = vnorm(vsub(wrist, elbow))
        ul, ll, ft = "upper_leg_" + side, "lower_leg_" + side, "foot_" + side
        ua, la = "upper_arm_" + side, "lower_arm_" + side
        loft(sb, "cloth", hip, thigh_dir, fwd,
             [(0.0, 0.085, 0.08), (0.15, 0.075, 0.07), (0.40, 0.055, 0.052)], 16, (0.06, 0.04),
             weights(ul, [("hips", inv(axial(ul, thigh_dir, 0.05))),
                          (ll, axial(ll, shin_dir, d_blend))]))
        loft(sb, "cloth", knee, shin_dir, fwd,
             [(0.0, 0.055, 0.052), (0.12, 0.058, 0.05), (0.36, 0.036, 0.034)], 16, (0.04, 0.03),
             weights(ll, [(ul, inv(axial(ll, shin_dir, d_blend))),
                          (ft, axial(ft, down, 0.03))]))
        # shoe: along +x, centre height = vertical radius so the sole touches z = 0
        shoe = loft(sb, "cloth", (0.0, hip[1], 0.0), fwd, up,
                    [(-0.05, 0.045, 0.040, 0.045), (0.02, 0.045, 0.045, 0.045),
                     (0.10, 0.035, 0.048, 0.035), (0.17, 0.025, 0.042, 0.025)], 14,
                    (0.025, 0.035), weights(ft, [(ll, radial(ft, 0.07))]))
        # below 1 cm the shoe is more than 7 cm from the ankle: rigid on the foot bone
        soles[side] = [q for q in shoe if q[2] < 0.01]
        loft(sb, "cloth", shoulder, upper_arm_dir, fwd,
             [(0.0, 0.05, 0.048), (0.12, 0.047, 0.044), (vlen(vsub(elbow, shoulder)), 0.04, 0.038)],
             12, (0.05, 0.035),
             weights(ua, [("spine", inv(axial(ua, upper_arm_dir, d_blend))),
                          (la, axial(la, forearm_dir, d_blend))]))
        loft(sb, "cloth", elbow, forearm_dir, fwd,
             [(0.0, 0.042, 0.04), (0.10, 0.042, 0.038), (vlen(vsub(wrist, elbow)), 0.03, 0.026)],
             12, (0.035, 0.02),
             weights(la, [(ua, inv(axial(la, forearm_dir, d_blend)))]))
        # hand: flat (wide along x, thin across), rigid on the forearm bone
        hand_end = vadd(wrist, (0.01, sy * 0.005, -0.19))
        hand_dir = vnorm(vsub(hand_end, wrist))
        loft(sb, "skin", wrist, hand_dir, fwd,
             [(0.03, 0.035, 0.018), (0.09, 0.045, 0.02), (0.14, 0.04, 0.016)], 12, (0.03, 0.05),
             weights(la, []))
    return sb, soles


def _quat_y(angle):
    """Unit quaternion (x, y, z, w) for a rotation by `angle` about +y.  For |angle| < pi
    w > 0, so consecutive keys of a smooth curve stay sign-continuous."""
    return (0.0, math.sin(0.5 * angle), 0.0, math.cos(0.5 * angle))


def _rot_y(angle, p):
    c, s = math.cos(angle), math.sin(angle)
    return (c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2])


def _walker_point(joint, p, angles, joint_pos):
    """Model-frame position of bind-pose point p, rigidly attached to `joint`, when each
    joint rotates by angles[joint] about its local +y (the only rotations the walk uses;
    rest rotations are identity, so a joint's frame is the model frame moved to it)."""
    parents = dict((name, par) for name, par, _ in WALKER_SKELETON)
    trans = dict((name, t) for name, _, t in WALKER_SKELETON)
    q = vsub(p, joint_pos[joint])
    cur = joint
    while cur is not None:
        q = vadd(trans[cur], _rot_y(angles.get(cur, 0.0), q))
        cur = parents[cur]
    return q


def walk_animation(joint_pos, soles, speed=1.4):
    """In-place walk cycle, the procedural gait of sim/src/trajectory.cpp (pedestrian_gait)
    baked into keys: positive angle about local +y swings a limb's lower end backwards.

    One gait cycle is 32 keys of 1/30 s = 1.0667 s (0.9375 Hz, the project's 0.93 Hz at
    1.4 m/s rounded so every key falls on the 30 Hz grid).  Per side x = 2 pi t / T + phase
    (left 0, right pi): hip = A sin(x), the foot moving back in stance (x in (-pi/2, pi/2));
    knee = K (1 + sin(x - pi/4)) >= 0 peaks early in swing; the arm swings opposite its leg
    and the elbow stays flexed (< 0), most when the arm is forward.  The shoe pitches
    F sin(x) in the model frame: toes up at heel strike, level at mid-stance, toes down at
    toe-off.  The hips only move vertically, by as much as keeps the lowest sole vertex on
    z = 0 at every key (the legs' swing shortens their reach by up to ~4 cm); there is no
    x/y motion: the simulator moves the body along its path."""
    n = 32
    period = n / 30.0
    times = [k / 30.0 for k in range(n + 1)]
    step = speed * period / 2.0  # one step = half a stride
    hip_amp = math.asin(step / (2.0 * WALKER_LEG_LENGTH))  # legs span one step, ~24.5 deg
    knee_amp = math.radians(25.0)   # knee 0 .. 50 deg
    foot_amp = math.radians(25.0)
    arm_amp = math.radians(20.0)
    elbow_amp = 0.4 * arm_amp
    elbow_offset = -(math.radians(5.0) + 0.6 * arm_amp)  # -17 deg: -25 .. -9 deg

    def phase(k):
        return 2.0 * math.pi * (k % n) / n  # k = n wraps onto k = 0: last key == first key

    angles = [dict() for _ in range(n + 1)]
    for k in range(n + 1):
        for side, ph in (("l", 0.0), ("r", math.pi)):
            x = phase(k) + ph
            hip = hip_amp * math.sin(x)
            knee = knee_amp * (1.0 + math.sin(x - 0.25 * math.pi))
            angles[k]["upper_leg_" + side] = hip
            angles[k]["lower_leg_" + side] = knee
            angles[k]["foot_" + side] = foot_amp * math.sin(x) - hip - knee
            angles[k]["upper_arm_" + side] = arm_amp * math.sin(x + math.pi)
            angles[k]["lower_arm_" + side] = elbow_offset + elbow_amp * math.sin(x + math.pi)
    hips = joint_pos["hips"]
    heights = []
    for k in range(n + 1):
        low = min(_walker_point("foot_" + side, q, angles[k], joint_pos)[2]
                  for side in ("l", "r") for q in soles[side])
        heights.append((0.0, 0.0, hips[2] - low))
    channels = [Channel("hips", "translation", times, heights)]
    for side in ("l", "r"):
        for joint in ("upper_leg_", "lower_leg_", "foot_", "upper_arm_", "lower_arm_"):
            channels.append(Channel(joint + side, "rotation", times,
                                    [_quat_y(angles[k][joint + side]) for k in range(n + 1)]))
    return Animation("walk", channels, {"nominal_speed_mps": speed})


def idle_animation():
    """Standing idle, 2 s loop at 30 Hz: the spine pitches +-1 deg (breathing) and the
    arms sway +-3 deg, a quarter cycle later."""
    n = 60
    times = [k / 30.0 for k in range(n + 1)]
    ph = [2.0 * math.pi * (k % n) / n for k in range(n + 1)]
    spine = [math.radians(1.0) * math.sin(x) for x in ph]
    arm = [math.radians(3.0) * math.sin(x - 0.5 * math.pi) for x in ph]
    channels = [Channel("spine", "rotation", times, [_quat_y(x) for x in spine])]
    for side in ("l", "r"):
        channels.append(Channel("upper_arm_" + side, "rotation", times, [_quat_y(x) for x in arm]))
    return Animation("idle", channels)


def build_walker_skinned():
    joint_pos = {}
    for name, parent, t in WALKER_SKELETON:
        joint_pos[name] = vadd(joint_pos[parent], t) if parent else t
    body, soles = build_walker_mesh(joint_pos)
    children = dict((name, []) for name, _, _ in WALKER_SKELETON)
    for name, parent, _ in WALKER_SKELETON:
        if parent:
            children[parent].append(name)
    nodes = [Node("walker", None, (0.0, 0.0, 0.0), ["hips", "body_mesh"])]
    nodes += [Node(name, None, t, children[name]) for name, _, t in WALKER_SKELETON]
    nodes.append(Node("body_mesh", body, skin=0))
    skin = Skin("walker_skin", [name for name, _, _ in WALKER_SKELETON], "hips")
    return Asset("walker_skinned", nodes, ["walker"],
                 "skinned walking human ~1.75 m, facing +X; clips 'walk' (in place, "
                 "nominal 1.4 m/s) and 'idle'", skins=[skin],
                 animations=[walk_animation(joint_pos, soles), idle_animation()])


def build_car_keyframed():
    """The car with its wheel spin as keyframes: clip 'roll' turns every wheel once about
    its local +y (positive = rolling forward along +x) in 1 s, 9 keys 45 deg apart.  Keys
    are sign-continuous, so the last is q(360 deg) = -q(0)."""
    car = build_car()
    duration = 1.0
    times = [duration * k / 8.0 for k in range(9)]
    keys = [_quat_y(2.0 * math.pi * k / 8.0) for k in range(9)]
    wheels = [n.name for n in car.nodes if n.name.startswith("wheel_")]
    channels = [Channel(w, "rotation", times, keys) for w in wheels]
    speed = round(2.0 * math.pi * CAR_WHEEL_RADIUS / duration, 6)
    roll = Animation("roll", channels, {"nominal_speed_mps": speed})
    return Asset("car_keyframed", car.nodes, car.roots,
                 "passenger car ~4.5 x 1.8 x 1.45 m; clip 'roll' spins the wheels one turn "
                 "(r = %.2f m) per second" % CAR_WHEEL_RADIUS, car.paint, animations=[roll])


# --------------------------------------------------------------------------
# Static world
# --------------------------------------------------------------------------


def build_road_segment():
    mb = MeshBuilder("road_segment")
    L, half_w, slab = 10.0, 3.5, 0.20
    box(mb, (-L, -half_w, -slab), (L, half_w, 0.0), "asphalt")
    for s in (-1.0, 1.0):
        y_curb = sorted((s * half_w, s * (half_w + 0.3)))
        y_walk = sorted((s * (half_w + 0.3), s * (half_w + 2.3)))
        box(mb, (-L, y_curb[0], -slab), (L, y_curb[1], 0.15), "curb")
        box(mb, (-L, y_walk[0], -slab), (L, y_walk[1], 0.15), "concrete")
    z = 0.005
    # dashed centre line: 3 m dashes, 2 m gaps, tiles seamlessly every 20 m
    for xc in (-7.5, -2.5, 2.5, 7.5):
        mb.polygon("road_marking", [(xc - 1.5, -0.075, z), (xc + 1.5, -0.075, z),
                                    (xc + 1.5, 0.075, z), (xc - 1.5, 0.075, z)], (0, 0, 1))
    # solid edge lines
    for yc in (-3.2, 3.2):
        mb.polygon("road_marking", [(-L, yc - 0.075, z), (L, yc - 0.075, z),
                                    (L, yc + 0.075, z), (-L, yc + 0.075, z)], (0, 0, 1))
    return Asset("road_segment", [Node("road_segment", mb)], ["road_segment"],
                 "straight road 20 m along X, 7 m asphalt, curbs and 2 m sidewalks")


def _rot90(p, k):
    x, y = p
    for _ in range(k % 4):
        x, y = -y, x
    return (x, y)


def build_intersection_patch():
    mb = MeshBuilder("intersection_patch")
    half, hw, curb, radius, slab = 10.0, 3.5, 0.3, 3.0, 0.20
    steps = 6
    c = hw + radius  # centre of the corner arc in the first quadrant

    def corner_arc(r, reverse=False):
        pts = []
        for k in range(steps + 1):
            a = math.radians(270.0 - 90.0 * k / steps)
            pts.append((c + r * math.cos(a), c + r * math.sin(a)))
        return pts[::-1] if reverse else pts

    # asphalt: plus-shaped region with rounded inner corners (counter-clockwise)
    quadrant = [(half, -hw), (half, hw)] + corner_arc(radius)  # (hw, half) = next quadrant's start
    asphalt = []
    for k in range(4):
        asphalt += [_rot90(p, k) for p in quadrant]
    extrude_z(mb, asphalt, -slab, 0.0, "asphalt")
    for k in range(4):
        band = ([(half, hw), (half, hw + curb)] + corner_arc(radius - curb)
                + [(hw + curb, half), (hw, half)] + corner_arc(radius, reverse=True))
        extrude_z(mb, [_rot90(p, k) for p in band], -slab, 0.15, "curb")
        walk = [(half, hw + curb), (half, half), (hw + curb, half)] + \
            corner_arc(radius - curb, reverse=True)
        extrude_z(mb, [_rot90(p, k) for p in walk], -slab, 0.15, "concrete")
    # zebra crossings on the four approaches and stop lines
    z = 0.005
    for k in range(4):
        for i in range(7):
            y0 = -3.25 + i * 1.0
            quad = [(6.6, y0), (9.4, y0), (9.4, y0 + 0.5), (6.6, y0 + 0.5)]
            mb.polygon("road_marking", [_rot90(p, k) + (z,) for p in quad], (0, 0, 1))
        stop = [(6.0, -3.4), (6.3, -3.4), (6.3, 0.0), (6.0, 0.0)]
        mb.polygon("road_marking", [_rot90(p, k) + (z,) for p in stop], (0, 0, 1))
    return Asset("intersection_patch", [Node("intersection_patch", mb)], ["intersection_patch"],
                 "20 x 20 m four-way intersection, 7 m roads, rounded curb corners")


def facade(mb, origin, u_dir, length, height, windows, wall_mat, depth):
    """Flat wall with recessed glass windows.  u_dir runs left-to-right as seen
    from outside; windows are (u0, u1, v0, v1) rectangles in wall coordinates."""
    n = vcross(u_dir, (0.0, 0.0, 1.0))

    def P(u, v, d=0.0):
        return (origin[0] + u_dir[0] * u - n[0] * d,
                origin[1] + u_dir[1] * u - n[1] * d,
                origin[2] + v)

    ub = sorted(set([0.0, length] + [round(w[0], 6) for w in windows] + [round(w[1], 6) for w in windows]))
    vb = sorted(set([0.0, height] + [round(w[2], 6) for w in windows] + [round(w[3], 6) for w in windows]))

    def in_window(u, v):
        return any(w[0] < u < w[1] and w[2] < v < w[3] for w in windows)

    for j in range(len(vb) - 1):
        v0, v1 = vb[j], vb[j + 1]
        run = None
        for i in range(len(ub) - 1):
            u0, u1 = ub[i], ub[i + 1]
            if in_window((u0 + u1) / 2.0, (v0 + v1) / 2.0):
                if run is not None:
                    mb.polygon(wall_mat, [P(run[0], v0), P(run[1], v0), P(run[1], v1), P(run[0], v1)], n)
                    run = None
            else:
                run = (run[0], u1) if run is not None else (u0, u1)
        if run is not None:
            mb.polygon(wall_mat, [P(run[0], v0), P(run[1], v0), P(run[1], v1), P(run[0], v1)], n)
    up = (0.0, 0.0, 1.0)
    for (u0, u1, v0, v1) in windows:
        mb.polygon("glass", [P(u0, v0, depth), P(u1, v0, depth), P(u1, v1, depth), P(u0, v1, depth)], n)
        mb.polygon(wall_mat, [P(u0, v0), P(u1, v0), P(u1, v0, depth), P(u0, v0, depth)], up)
        mb.polygon(wall_mat, [P(u0, v1), P(u1, v1), P(u1, v1, depth), P(u0, v1, depth)], vmul(up, -1))
        mb.polygon(wall_mat, [P(u0, v0), P(u0, v1), P(u0, v1, depth), P(u0, v0, depth)], u_dir)
        mb.polygon(wall_mat, [P(u1, v0), P(u1, v1), P(u1, v1, depth), P(u1, v0, depth)], vmul(u_dir, -1))


def building(name, size, height, floors, win_w, win_h, sill, per_floor, wall_mat,
             depth, parapet_h, ground_openings, description):
    mb = MeshBuilder(name)
    a = size / 2.0
    t = 0.3
    start = mb.mark()
    walls = [((a, -a, 0.0), (0.0, 1.0, 0.0), "+x"), ((a, a, 0.0), (-1.0, 0.0, 0.0), "+y"),
             ((-a, a, 0.0), (0.0, -1.0, 0.0), "-x"), ((-a, -a, 0.0), (1.0, 0.0, 0.0), "-y")]
    floor_h = (height - parapet_h) / floors
    pitch = size / per_floor
    for origin, u_dir, key in walls:
        windows = list(ground_openings.get(key, []))
        first = 1 if key in ground_openings else 0
        for f in range(first, floors):
            for i in range(per_floor):
                uc = pitch * (i + 0.5)
                windows.append((uc - win_w / 2.0, uc + win_w / 2.0,
                                f * floor_h + sill, f * floor_h + sill + win_h))
        facade(mb, origin, u_dir, size, height, windows, wall_mat, depth)
    # parapet cap, inner parapet faces and the flat roof
    up, r = (0.0, 0.0, 1.0), a - t
    roof_z = height - parapet_h
    caps = [[(-a, -a), (a, -a), (a, -r), (-a, -r)], [(-a, r), (a, r), (a, a), (-a, a)],
            [(-a, -r), (-r, -r), (-r, r), (-a, r)], [(r, -r), (a, -r), (a, r), (r, r)]]
    for q in caps:
        mb.polygon("concrete", [(p[0], p[1], height) for p in q], up)
    for (p0, p1, inward) in (((r, -r), (r, r), (-1, 0, 0)), ((-r, -r), (-r, r), (1, 0, 0)),
                             ((-r, r), (r, r), (0, -1, 0)), ((-r, -r), (r, -r), (0, 1, 0))):
        mb.polygon("concrete", [(p0[0], p0[1], roof_z), (p1[0], p1[1], roof_z),
                                (p1[0], p1[1], height), (p0[0], p0[1], height)], inward)
    mb.polygon("concrete", [(-r, -r, roof_z), (r, -r, roof_z), (r, r, roof_z), (-r, r, roof_z)], up)
    mb.polygon("concrete", [(-a, -a, 0.0), (a, -a, 0.0), (a, a, 0.0), (-a, a, 0.0)], (0, 0, -1))
    mb.check_solid(start, "building shell")
    return Asset(name, [Node(name, mb)], [name], description)


def build_building_block():
    # ground-level openings start 2 cm up (threshold) so the recess floor is not
    # coplanar with the building's bottom face
    door = {"+x": [(1.2, 2.8, 0.9, 2.4), (4.4, 5.6, 0.02, 2.4), (7.2, 8.8, 0.9, 2.4)]}
    return building("building_block", 10.0, 12.0, 4, 1.6, 1.5, 0.9, 3, "brick", 0.15, 0.6,
                    door, "10 x 10 x 12 m brick block, recessed windows, roof parapet")


def build_building_tall():
    lobby = {"+x": [(4.5, 10.5, 0.02, 2.7)]}
    return building("building_tall", 15.0, 30.0, 10, 2.2, 1.9, 0.7, 5, "concrete", 0.2, 1.0,
                    lobby, "15 x 15 x 30 m concrete tower, recessed windows, roof parapet")


def build_tree():
    mb = MeshBuilder("tree")
    tube(mb, (0.0, 0.0, 0.0), (0.0, 0.0, 3.2), 0.20, 0.12, 8, "bark")
    for ang, length in ((20.0, 1.1), (150.0, 1.0), (260.0, 0.9)):
        a = math.radians(ang)
        p0 = (0.0, 0.0, 2.2)
        p1 = (length * math.cos(a), length * math.sin(a), 3.2)
        tube(mb, p0, p1, 0.07, 0.04, 6, "bark")
    icosphere(mb, (0.0, 0.0, 4.25), (1.75, 1.75, 1.75), 2, "foliage", jitter=0.08, seed=7)
    return Asset("tree", [Node("tree", mb)], ["tree"],
                 "deciduous tree ~6 m: bark trunk and branches, low-poly foliage crown")


def build_pole():
    mb = MeshBuilder("pole")
    tube(mb, (0.0, 0.0, 0.0), (0.0, 0.0, 0.45), 0.22, 0.20, 12, "metal")
    tube(mb, (0.0, 0.0, 0.0), (0.0, 0.0, 6.0), 0.15, 0.15, 12, "metal")
    tube(mb, (0.0, 0.0, 5.70), (1.55, 0.0, 5.90), 0.05, 0.045, 8, "metal")
    box(mb, (1.40, -0.16, 5.82), (2.00, 0.16, 5.98), "metal")
    mb.polygon("plastic", [(1.46, -0.11, 5.815), (1.94, -0.11, 5.815), (1.94, 0.11, 5.815),
                           (1.46, 0.11, 5.815)], (0, 0, -1))
    return Asset("pole", [Node("pole", mb)], ["pole"],
                 "street light: 6 m pole (r 0.15 m) with arm and lamp head along +X; "
                 "origin at the pole base")


def build_sign():
    mb = MeshBuilder("sign")
    tube(mb, (0.0, 0.0, 0.0), (0.0, 0.0, 2.50), 0.03, 0.03, 8, "metal")
    box(mb, (0.035, -0.30, 1.90), (0.055, 0.30, 2.50), "metal", {"+x": "sign_face"})
    for z in (2.0, 2.4):
        box(mb, (0.0, -0.04, z - 0.02), (0.035, 0.04, z + 0.02), "metal")
    return Asset("sign", [Node("sign", mb)], ["sign"],
                 "traffic sign: post with a 0.6 x 0.6 m retroreflective panel centred at "
                 "2.2 m facing +X; origin at the post base")


def build_barrier():
    # New Jersey profile: a 7.5 cm vertical lip, the steep lower slope to 0.33 m, then the upper
    # face to the 0.15 m wide top at 0.81 m. 10 m along X, so a row of them tiles a road edge.
    mb = MeshBuilder("barrier")
    half = 5.0
    tapered_box(mb, 0.0, 0.075, (half, 0.30), (half, 0.30), "concrete")
    tapered_box(mb, 0.075, 0.33, (half, 0.30), (half, 0.20), "concrete")
    tapered_box(mb, 0.33, 0.81, (half, 0.20), (half, 0.075), "concrete")
    return Asset("barrier", [Node("barrier", mb)], ["barrier"],
                 "concrete safety barrier, New Jersey profile: 10 m along X, 0.6 m wide at the "
                 "base, 0.15 m at the top, 0.81 m high")


BUILDERS = [
    ("car", build_car),
    ("van", build_van),
    ("truck", build_truck),
    ("bus", build_bus),
    ("cyclist", build_cyclist),
    ("pedestrian", build_pedestrian),
    ("walker_skinned", build_walker_skinned),
    ("car_keyframed", build_car_keyframed),
    ("road_segment", build_road_segment),
    ("intersection_patch", build_intersection_patch),
    ("building_block", build_building_block),
    ("building_tall", build_building_tall),
    ("tree", build_tree),
    ("pole", build_pole),
    ("sign", build_sign),
    ("barrier", build_barrier),
]


def materials_yaml():
    lines = [
        "# SPDX-License-Identifier: Apache-2.0",
        "# Generated by tools/assets/generate_assets.py -- do not edit by hand.",
        "# LiDAR reflectivity (diffuse-equivalent, 0..1) at 1550 nm per glTF material name.",
        "# road_marking and sign_face are retroreflective; glass is mostly transmissive.",
    ]
    for name in sorted(MATERIALS):
        refl = MATERIALS[name][3]
        lines.append("%s: %.2f  # %s" % (name, refl, MATERIALS[name][4]))
    return "\n".join(lines) + "\n"


def generate(out_dir, quiet=False):
    if not os.path.isdir(out_dir):
        os.makedirs(out_dir)
    report = []
    for name, fn in BUILDERS:
        asset = fn()
        text = build_gltf(asset)
        path = os.path.join(out_dir, name + ".gltf")
        with open(path, "w", encoding="ascii", newline="\n") as fh:
            fh.write(text)
        lo, hi, tris = world_bbox(asset)
        report.append((name, tris, lo, hi, len(text)))
    with open(os.path.join(out_dir, "materials.yaml"), "w", encoding="ascii", newline="\n") as fh:
        fh.write(materials_yaml())
    if not quiet:
        print("%-20s %6s  %-44s %s" % ("file", "tris", "bbox min .. max [m]", "size [x y z]"))
        for name, tris, lo, hi, nbytes in report:
            print("%-20s %6d  (%6.2f %6.2f %6.2f)..(%6.2f %6.2f %6.2f)  %.2f x %.2f x %.2f  %d B"
                  % (name + ".gltf", tris, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
                     hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], nbytes))
    return report


def main(argv=None):
    default_out = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                "..", "..", "assets"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=default_out, help="output folder (default: %(default)s)")
    ap.add_argument("--quiet", action="store_true", help="do not print the summary table")
    args = ap.parse_args(argv)
    generate(args.out, args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
