#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Validate the generated glTF assets (standard library only).

    /usr/bin/python3 tools/assets/check_assets.py [--dir assets] [--no-generate]

Checks every ``*.gltf`` in the folder:
  * valid JSON / glTF 2.0 structure, embedded base64 buffers decode to byteLength
  * bufferView / accessor byte ranges inside their buffers, alignment, counts
  * triangle-list indices in range, no degenerate (zero-area) triangles
  * NORMALs unit length and consistent with the triangle winding; every mesh
    encloses a positive signed volume (outward-facing winding)
  * POSITION accessor min/max equal the data
  * materials named from the allowed set and listed in materials.yaml
  * world bounding box (node transforms applied) within 10 % of the intended
    dimensions, footprint centred on the origin, resting on z = 0
  * required node names / hierarchy (wheels, pedestrian joints, walker skeleton)
  * triangle budget per asset (5000; the skinned walker needs at least 5000)
  * skins: joints, skeleton, inverse bind matrices (MAT4 float, one per joint, the
    inverse of each joint's global rest transform to 1e-4), JOINTS_0 / WEIGHTS_0
    (VEC4, weights >= 0 summing to 1 within 1e-3, joint indices < len(skin.joints))
  * animations: channel targets, samplers (input float SCALAR with min/max, strictly
    increasing; output count = input count, x3 for CUBICSPLINE; unit, sign-continuous
    quaternions), plus the clip contracts of walker_skinned and car_keyframed
Unless --no-generate is given it also runs generate_assets.py twice into
temporary folders, requires byte-identical output (determinism) and requires
the checked folder to match that output (assets up to date).

Frame convention: x forward, y left, z up (Z-up, NOT glTF's Y-up), metres.
Exits with status 1 and one "file: problem" line per failure.
"""

import argparse
import base64
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

ALLOWED_MATERIALS = {
    "car_paint", "glass", "tire", "metal", "plastic", "asphalt", "concrete", "curb",
    "road_marking", "brick", "foliage", "bark", "skin", "cloth", "sign_face",
}

TOL = 0.10  # relative tolerance on the intended dimensions

# Intended dimensions (x length, y width, z height) in metres; None = not specified.
# centred: footprint centre must be on the origin; ground: min z must be 0.
EXPECTED = {
    "car": dict(size=(4.5, 1.8, 1.45), centred=True, ground=True,
                nodes=["body", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"]),
    "van": dict(size=(5.2, 2.0, 2.2), centred=True, ground=True,
                nodes=["body", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"]),
    "truck": dict(size=(9.0, 2.5, 3.5), centred=True, ground=True,
                  nodes=["body", "wheel_fl", "wheel_fr", "wheel_ml", "wheel_mr",
                         "wheel_rl", "wheel_rr"]),
    "bus": dict(size=(12.0, 2.55, 3.1), centred=True, ground=True,
                nodes=["body", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"]),
    "cyclist": dict(size=(1.8, 0.6, 1.75), centred=True, ground=True,
                    nodes=["body", "wheel_front", "wheel_rear"]),
    "pedestrian": dict(size=(None, None, 1.75), centred=True, ground=True,
                       nodes=["pelvis", "torso", "head", "upper_arm_l", "lower_arm_l",
                              "upper_arm_r", "lower_arm_r", "upper_leg_l", "lower_leg_l",
                              "upper_leg_r", "lower_leg_r"]),
    "walker_skinned": dict(size=(None, None, 1.75), centred=True, ground=True,
                           nodes=["walker", "body_mesh", "hips", "spine", "neck", "head",
                                  "upper_leg_l", "lower_leg_l", "foot_l", "upper_leg_r",
                                  "lower_leg_r", "foot_r", "upper_arm_l", "lower_arm_l",
                                  "upper_arm_r", "lower_arm_r"],
                           min_tris=5000, max_tris=12000),
    "car_keyframed": dict(size=(4.5, 1.8, 1.45), centred=True, ground=True,
                          nodes=["body", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"]),
    "road_segment": dict(size=(20.0, 11.6, None), centred=True, ground=False, nodes=[]),
    "intersection_patch": dict(size=(20.0, 20.0, None), centred=True, ground=False, nodes=[]),
    "building_block": dict(size=(10.0, 10.0, 12.0), centred=True, ground=True, nodes=[]),
    "building_tall": dict(size=(15.0, 15.0, 30.0), centred=True, ground=True, nodes=[]),
    "tree": dict(size=(None, None, 6.0), centred=True, ground=True, nodes=[]),
    # pole and sign: origin at the base of the post (documented exception)
    "pole": dict(size=(None, None, 6.0), centred=False, ground=True, nodes=[]),
    "sign": dict(size=(None, 0.6, None), centred=False, ground=True, nodes=[]),
    "barrier": dict(size=(10.0, 0.6, 0.81), centred=True, ground=True, nodes=[]),
}

# expected sign of (x, y) of each wheel's axle centre: front +x, left +y
WHEEL_SIGNS = {
    "wheel_fl": (1, 1), "wheel_fr": (1, -1), "wheel_ml": (-1, 1), "wheel_mr": (-1, -1),
    "wheel_rl": (-1, 1), "wheel_rr": (-1, -1), "wheel_front": (1, 0), "wheel_rear": (-1, 0),
}

PEDESTRIAN_PARENTS = {
    "torso": "pelvis", "head": "torso",
    "upper_arm_l": "torso", "lower_arm_l": "upper_arm_l",
    "upper_arm_r": "torso", "lower_arm_r": "upper_arm_r",
    "upper_leg_l": "pelvis", "lower_leg_l": "upper_leg_l",
    "upper_leg_r": "pelvis", "lower_leg_r": "upper_leg_r",
}
HANGING_LIMBS = ["upper_arm_l", "lower_arm_l", "upper_arm_r", "lower_arm_r",
                 "upper_leg_l", "lower_leg_l", "upper_leg_r", "lower_leg_r"]

MAX_TRIANGLES = 5000  # default budget; EXPECTED[...]["max_tris"] overrides it

# walker_skinned: skeleton (joint -> parent joint); skin.joints must be exactly these
WALKER_PARENTS = {
    "hips": None, "spine": "hips", "neck": "spine", "head": "neck",
    "upper_leg_l": "hips", "lower_leg_l": "upper_leg_l", "foot_l": "lower_leg_l",
    "upper_leg_r": "hips", "lower_leg_r": "upper_leg_r", "foot_r": "lower_leg_r",
    "upper_arm_l": "spine", "lower_arm_l": "upper_arm_l",
    "upper_arm_r": "spine", "lower_arm_r": "upper_arm_r",
}
WALK_SPEED_MPS = 1.4
WALK_CYCLE_S = (1.0, 1.15)  # one gait cycle at 1.4 m/s (0.93 Hz stride frequency: 1.075 s)
KEY_STEP_S = 1.0 / 30.0
ANIM_PATHS = {"translation": "VEC3", "rotation": "VEC4", "scale": "VEC3"}

COMPONENT = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2),
             5125: ("I", 4), 5126: ("f", 4)}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


class CheckError(Exception):
    pass


def f32(v):
    return struct.unpack("<f", struct.pack("<f", v))[0]


# ---- 4x4 matrices as row-major nested lists -------------------------------

def mat_identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major in glTF
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = node.get("translation", [0.0, 0.0, 0.0])
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    s = node.get("scale", [1.0, 1.0, 1.0])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m = mat_identity()
    for i in range(3):
        for j in range(3):
            m[i][j] = r[i][j] * s[j]
        m[i][3] = t[i]
    return m


def transform(m, p):
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


# ---- glTF parsing -----------------------------------------------------------

def decode_buffers(g, folder, errors):
    bufs = []
    for i, b in enumerate(g.get("buffers", [])):
        uri = b.get("uri")
        if uri is None:
            raise CheckError("buffer %d has no uri (GLB not supported here)" % i)
        if uri.startswith("data:"):
            head, _, payload = uri.partition(",")
            if not head.endswith(";base64"):
                raise CheckError("buffer %d data URI is not base64" % i)
            try:
                data = base64.b64decode(payload, validate=True)
            except Exception as exc:  # noqa: BLE001 - report any decode problem
                raise CheckError("buffer %d base64 decode failed: %s" % (i, exc))
        else:
            errors.append("buffer %d uses external uri %r (assets must be self-contained)" % (i, uri))
            with open(os.path.join(folder, uri), "rb") as fh:
                data = fh.read()
        if len(data) != b.get("byteLength"):
            raise CheckError("buffer %d byteLength %r != decoded %d bytes"
                             % (i, b.get("byteLength"), len(data)))
        bufs.append(data)
    return bufs


def read_accessor(g, bufs, index):
    accs = g.get("accessors", [])
    if not (0 <= index < len(accs)):
        raise CheckError("accessor index %r out of range" % index)
    a = accs[index]
    ctype = a.get("componentType")
    if ctype not in COMPONENT or a.get("type") not in NCOMP:
        raise CheckError("accessor %d has bad componentType/type %r/%r"
                         % (index, ctype, a.get("type")))
    fmt, csize = COMPONENT[ctype]
    ncomp = NCOMP[a["type"]]
    count = a.get("count", 0)
    if not isinstance(count, int) or count <= 0:
        raise CheckError("accessor %d has invalid count %r" % (index, count))
    bvi = a.get("bufferView")
    views = g.get("bufferViews", [])
    if bvi is None or not (0 <= bvi < len(views)):
        raise CheckError("accessor %d bufferView %r out of range" % (index, bvi))
    bv = views[bvi]
    bi = bv.get("buffer", -1)
    if not (0 <= bi < len(bufs)):
        raise CheckError("bufferView %d buffer %r out of range" % (bvi, bi))
    bv_off = bv.get("byteOffset", 0)
    bv_len = bv.get("byteLength", 0)
    if bv_off < 0 or bv_len <= 0 or bv_off + bv_len > len(bufs[bi]):
        raise CheckError("bufferView %d range [%d, %d) exceeds buffer %d of %d bytes"
                         % (bvi, bv_off, bv_off + bv_len, bi, len(bufs[bi])))
    elem = csize * ncomp
    stride = bv.get("byteStride", elem)
    acc_off = a.get("byteOffset", 0)
    need = acc_off + stride * (count - 1) + elem
    if need > bv_len:
        raise CheckError("accessor %d needs %d bytes but bufferView %d has %d"
                         % (index, need, bvi, bv_len))
    if (bv_off + acc_off) % csize:
        raise CheckError("accessor %d is not aligned to its %d-byte components" % (index, csize))
    data = bufs[bi]
    out = []
    for k in range(count):
        vals = struct.unpack_from("<%d%s" % (ncomp, fmt), data, bv_off + acc_off + k * stride)
        out.append(vals if ncomp > 1 else vals[0])
    return a, out


NORMALISED = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}


def read_floats(g, bufs, index, where, errors):
    """Accessor values as floats: float32 as is, normalised integers scaled to [-1, 1] or
    [0, 1] (glTF allows those for rotations and weights); None if neither."""
    a, vals = read_accessor(g, bufs, index)
    ctype = a["componentType"]
    if ctype == 5126:
        scale = None
    elif a.get("normalized") and ctype in NORMALISED:
        scale = NORMALISED[ctype]
    else:
        errors.append("%s: accessor %d must be float or normalised integer" % (where, index))
        return a, None
    out = []
    for v in vals:
        t = v if isinstance(v, tuple) else (v,)
        if scale is not None:
            t = tuple(max(c / scale, -1.0) for c in t)
        if any(not math.isfinite(c) for c in t):
            errors.append("%s: accessor %d has non-finite values" % (where, index))
            return a, None
        out.append(t)
    return a, out


def parse_materials_yaml(path):
    table = {}
    with open(path, "r", encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            text = line.split("#", 1)[0].strip()
            if not text:
                continue
            key, sep, val = text.partition(":")
            if not sep:
                raise CheckError("materials.yaml:%d: expected 'name: value'" % lineno)
            try:
                table[key.strip()] = float(val.strip())
            except ValueError:
                raise CheckError("materials.yaml:%d: %r is not a number" % (lineno, val.strip()))
    return table


def check_skin_attributes(g, bufs, attrs, count, where, errors, info):
    """JOINTS_0 / WEIGHTS_0 of one primitive; records the largest joint index and the
    number of vertices with three or more influences in info."""
    if "JOINTS_0" not in attrs or "WEIGHTS_0" not in attrs:
        errors.append("%s: JOINTS_0 and WEIGHTS_0 must come together" % where)
        return
    jacc, joints = read_accessor(g, bufs, attrs["JOINTS_0"])
    if jacc["componentType"] not in (5121, 5123) or jacc["type"] != "VEC4":
        errors.append("%s: JOINTS_0 must be VEC4 of unsigned byte or short" % where)
        return
    wacc, weights = read_floats(g, bufs, attrs["WEIGHTS_0"], where + " WEIGHTS_0", errors)
    if weights is None:
        return
    if wacc["type"] != "VEC4" or wacc["componentType"] not in (5126, 5121, 5123):
        errors.append("%s: WEIGHTS_0 must be VEC4 float (or normalised unsigned)" % where)
        return
    if len(joints) != count or len(weights) != count:
        errors.append("%s: JOINTS_0/WEIGHTS_0 counts %d/%d != POSITION count %d"
                      % (where, len(joints), len(weights), count))
        return
    for k, (j, w) in enumerate(zip(joints, weights)):
        if min(w) < 0.0:
            errors.append("%s: vertex %d has a negative weight %r" % (where, k, w))
            return
        if abs(sum(w) - 1.0) > 1e-3:
            errors.append("%s: vertex %d weights sum to %.6f, not 1" % (where, k, sum(w)))
            return
        info["max_joint"] = max(info["max_joint"], max(j))
        if sum(1 for x in w if x > 0.0) >= 3:
            info["multi"] += 1


def rest_rotation_ok(node):
    q = node.get("rotation")
    return q is None or (len(q) == 4 and abs(math.sqrt(sum(c * c for c in q)) - 1.0) <= 1e-3)


def quat_angle_about_y(q):
    """Signed angle of a rotation about +y (q = x, y, z, w), or None if it has a
    noticeable x or z component."""
    if abs(q[0]) > 1e-4 or abs(q[2]) > 1e-4:
        return None
    return 2.0 * math.atan2(q[1], q[3])


def check_skins(g, bufs, nodes, names, world, mesh_skin, errors):
    """Skins: joints, skeleton, inverse bind matrices vs. the rest pose, and the
    meshes they deform.  Returns the joint names of each skin."""
    skins = g.get("skins", [])
    out = []
    for si, skin in enumerate(skins):
        where = "skin %d" % si
        joints = skin.get("joints", [])
        out.append([names[j] if isinstance(j, int) and 0 <= j < len(nodes) else None
                    for j in joints])
        if not joints:
            errors.append("%s: no joints" % where)
            continue
        if any(not isinstance(j, int) or not 0 <= j < len(nodes) for j in joints):
            errors.append("%s: joint index out of range" % where)
            continue
        if len(set(joints)) != len(joints):
            errors.append("%s: duplicate joints" % where)
        for j in joints:
            if "matrix" in nodes[j]:
                errors.append("%s: joint %r uses a matrix (cannot be animated)" % (where, names[j]))
            if j not in world:
                errors.append("%s: joint %r is not in the scene" % (where, names[j]))
        sk = skin.get("skeleton")
        if sk is not None:
            if not isinstance(sk, int) or not 0 <= sk < len(nodes):
                errors.append("%s: skeleton index out of range" % where)
            else:
                parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
                for j in joints:
                    cur = j
                    while cur is not None and cur != sk:
                        cur = parent.get(cur)
                    if cur is None:
                        errors.append("%s: joint %r is not below the skeleton root %r"
                                      % (where, names[j], names[sk]))
        if "inverseBindMatrices" not in skin:
            errors.append("%s: no inverseBindMatrices" % where)
            continue
        acc, mats = read_accessor(g, bufs, skin["inverseBindMatrices"])
        if acc["componentType"] != 5126 or acc["type"] != "MAT4":
            errors.append("%s: inverseBindMatrices must be float MAT4" % where)
            continue
        if len(mats) != len(joints):
            errors.append("%s: %d inverse bind matrices for %d joints"
                          % (where, len(mats), len(joints)))
            continue
        for j, m in zip(joints, mats):
            if j not in world:
                continue
            ibm = [[m[c * 4 + r] for c in range(4)] for r in range(4)]  # column-major
            prod = mat_mul(ibm, world[j])
            err = max(abs(prod[r][c] - (1.0 if r == c else 0.0)) for r in range(4) for c in range(4))
            if err > 1e-4:
                errors.append("%s: inverse bind matrix of %r is not the inverse of its global "
                              "rest transform (error %.2g)" % (where, names[j], err))
    skinned_meshes = set()
    for i, n in enumerate(nodes):
        if "skin" not in n:
            continue
        si = n["skin"]
        if not isinstance(si, int) or not 0 <= si < len(skins):
            errors.append("node %r: skin index out of range" % names[i])
            continue
        if "mesh" not in n or not 0 <= n["mesh"] < len(mesh_skin):
            errors.append("node %r has a skin but no mesh" % names[i])
            continue
        skinned_meshes.add(n["mesh"])
        info = mesh_skin[n["mesh"]]
        if info["plain"] or not info["skinned"]:
            errors.append("node %r: every primitive of a skinned mesh needs JOINTS_0/WEIGHTS_0"
                          % names[i])
        if info["max_joint"] >= len(skins[si].get("joints", [])):
            errors.append("node %r: joint index %d >= %d joints of its skin"
                          % (names[i], info["max_joint"], len(skins[si].get("joints", []))))
    for i, n in enumerate(nodes):
        if "mesh" in n and "skin" not in n and 0 <= n["mesh"] < len(mesh_skin) \
                and mesh_skin[n["mesh"]]["skinned"]:
            errors.append("node %r instances a mesh with JOINTS_0 but has no skin" % names[i])
    return out


def check_animations(g, bufs, nodes, names, errors):
    """Structure of every animation.  Returns per clip: name, extras, duration and
    {(node name, path): (interpolation, times, values)} for the asset-specific checks."""
    clips = []
    for ai, anim in enumerate(g.get("animations", [])):
        aname = anim.get("name", "animation %d" % ai)
        where = "animation %r" % aname
        samplers = anim.get("samplers", [])
        channels = anim.get("channels", [])
        if not channels:
            errors.append("%s: no channels" % where)
        curves = {}
        used = set()
        duration = 0.0
        for ci, ch in enumerate(channels):
            cw = "%s channel %d" % (where, ci)
            si = ch.get("sampler")
            target = ch.get("target", {})
            node, path = target.get("node"), target.get("path")
            if not isinstance(si, int) or not 0 <= si < len(samplers):
                errors.append("%s: sampler index %r out of range" % (cw, si))
                continue
            used.add(si)
            if not isinstance(node, int) or not 0 <= node < len(nodes):
                errors.append("%s: target node %r out of range" % (cw, node))
                continue
            if path not in ANIM_PATHS:
                errors.append("%s: target path %r not supported" % (cw, path))
                continue
            if "matrix" in nodes[node]:
                errors.append("%s: animates node %r, which uses a matrix" % (cw, names[node]))
            if (names[node], path) in curves:
                errors.append("%s: %s of %r is animated twice" % (cw, path, names[node]))
            smp = samplers[si]
            interp = smp.get("interpolation", "LINEAR")
            if interp not in ("LINEAR", "STEP", "CUBICSPLINE"):
                errors.append("%s: interpolation %r" % (cw, interp))
                continue
            iacc, times = read_accessor(g, bufs, smp.get("input", -1))
            if iacc["componentType"] != 5126 or iacc["type"] != "SCALAR":
                errors.append("%s: sampler input must be float SCALAR" % cw)
                continue
            if "min" not in iacc or "max" not in iacc:
                errors.append("%s: sampler input accessor lacks min/max" % cw)
            elif f32(iacc["min"][0]) != min(times) or f32(iacc["max"][0]) != max(times):
                errors.append("%s: sampler input min/max %r/%r do not match the data"
                              % (cw, iacc["min"], iacc["max"]))
            if times[0] < 0.0 or any(b <= a for a, b in zip(times, times[1:])):
                errors.append("%s: key times must be >= 0 and strictly increasing" % cw)
                continue
            oacc, vals = read_floats(g, bufs, smp.get("output", -1), cw + " output", errors)
            if vals is None:
                continue
            if oacc["type"] != ANIM_PATHS[path]:
                errors.append("%s: %s output must be %s, got %s"
                              % (cw, path, ANIM_PATHS[path], oacc["type"]))
                continue
            per_key = 3 if interp == "CUBICSPLINE" else 1
            if len(vals) != per_key * len(times):
                errors.append("%s: %d output values for %d keys (%s)"
                              % (cw, len(vals), len(times), interp))
                continue
            keys = vals[1::3] if per_key == 3 else vals
            if path == "rotation":
                bad = [k for k, q in enumerate(keys)
                       if abs(math.sqrt(sum(c * c for c in q)) - 1.0) > 1e-3]
                if bad:
                    errors.append("%s: key %d is not a unit quaternion" % (cw, bad[0]))
                if interp == "LINEAR":
                    flips = [k for k in range(1, len(keys))
                             if sum(a * b for a, b in zip(keys[k - 1], keys[k])) < 0.0]
                    if flips:
                        errors.append("%s: quaternion sign flips between keys %d and %d"
                                      % (cw, flips[0] - 1, flips[0]))
            duration = max(duration, times[-1])
            curves[(names[node], path)] = (interp, times, keys)
        for si in range(len(samplers)):
            if si not in used:
                errors.append("%s: sampler %d is not used by any channel" % (where, si))
        clips.append((anim.get("name"), anim.get("extras", {}), duration, curves))
    return clips


def check_walker(nodes, names, roots, parent, skin_joints, skin_meta, clips, mesh_skin,
                 materials, errors):
    by_name = dict((nm, i) for i, nm in enumerate(names))
    if [names[r] for r in roots] != ["walker"]:
        errors.append("the scene must have the single root 'walker'")
    for child in ("hips", "body_mesh"):
        if child in by_name and parent.get(by_name[child]) != by_name.get("walker"):
            errors.append("node %r must be a child of 'walker'" % child)
    for joint, par in sorted(WALKER_PARENTS.items()):
        if par and joint in by_name and par in by_name and parent.get(by_name[joint]) != by_name[par]:
            errors.append("node %r must be a child of %r" % (joint, par))
        if joint in by_name:
            n = nodes[by_name[joint]]
            if "mesh" in n or "matrix" in n or not rest_rotation_ok(n):
                errors.append("joint %r: no mesh, no matrix, unit rotation" % joint)
    if "hips" in by_name:
        tz = nodes[by_name["hips"]].get("translation", [0, 0, 0])[2]
        if not 0.85 <= tz <= 1.05:
            errors.append("hips translation z = %.3f, expected pelvis height ~0.95" % tz)
    body = nodes[by_name["body_mesh"]] if "body_mesh" in by_name else {}
    if "mesh" not in body or "skin" not in body:
        errors.append("'body_mesh' must carry the mesh and the skin")
    if len(skin_joints) != 1:
        errors.append("expected exactly one skin, found %d" % len(skin_joints))
    else:
        if sorted(j or "" for j in skin_joints[0]) != sorted(WALKER_PARENTS):
            errors.append("skin joints %r are not the walker skeleton" % skin_joints[0])
        sk = skin_meta[0].get("skeleton")
        if sk is None or names[sk] != "hips":
            errors.append("skin.skeleton must be 'hips'")
    if "mesh" in body and 0 <= body["mesh"] < len(mesh_skin):
        if mesh_skin[body["mesh"]]["multi"] == 0:
            errors.append("no vertex has three or more joint influences")
    if not {"skin", "cloth"} <= set(m.get("name") for m in materials):
        errors.append("walker must use the materials 'skin' and 'cloth'")
    clip_names = [c[0] for c in clips]
    if not clip_names or clip_names[0] != "walk" or "idle" not in clip_names:
        errors.append("animations must be ['walk', ..., 'idle', ...] (walk first), got %r"
                      % clip_names)
    for cname, extras, duration, curves in clips:
        if cname == "idle" and abs(duration - 2.0) > 1e-3:
            errors.append("clip 'idle' lasts %.4f s, expected 2 s" % duration)
        if cname != "walk":
            continue
        if abs(extras.get("nominal_speed_mps", 0.0) - WALK_SPEED_MPS) > 1e-9:
            errors.append("clip 'walk' extras.nominal_speed_mps must be %.1f" % WALK_SPEED_MPS)
        if not WALK_CYCLE_S[0] <= duration <= WALK_CYCLE_S[1]:
            errors.append("clip 'walk' lasts %.4f s, not one gait cycle (%.2f..%.2f s)"
                          % (duration, WALK_CYCLE_S[0], WALK_CYCLE_S[1]))
        hips_t = nodes[by_name["hips"]].get("translation", [0, 0, 0]) if "hips" in by_name else None
        for (node, path), (interp, times, keys) in sorted(curves.items()):
            cw = "clip 'walk' %s of %r" % (path, node)
            if interp != "LINEAR":
                errors.append("%s: interpolation must be LINEAR" % cw)
            if times[0] != 0.0 or any(abs(b - a - KEY_STEP_S) > 1e-4 for a, b in zip(times, times[1:])):
                errors.append("%s: keys must start at 0 and be 1/30 s apart" % cw)
            if max(abs(a - b) for a, b in zip(keys[0], keys[-1])) > 1e-6:
                errors.append("%s: last key differs from the first (loop not seamless)" % cw)
            if path == "translation":
                if node != "hips" or hips_t is None:
                    errors.append("%s: only the hips may be translated" % cw)
                elif any(abs(k[0] - hips_t[0]) > 1e-6 or abs(k[1] - hips_t[1]) > 1e-6 for k in keys):
                    errors.append("%s: x/y root motion (the walk must be in place)" % cw)
                elif max(abs(k[2] - hips_t[2]) for k in keys) > 0.05:
                    errors.append("%s: hip bob exceeds 5 cm" % cw)
            if path == "rotation" and node.startswith("lower_leg_"):
                angles = [quat_angle_about_y(q) for q in keys]
                if any(a is None or a < -1e-4 or a > math.radians(90.0) for a in angles):
                    errors.append("%s: knees must bend backwards only (0..90 deg about +y)" % cw)


def check_car_keyframed(nodes, names, clips, mesh_bbox, errors):
    wheels = ["wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr"]
    roll = [c for c in clips if c[0] == "roll"]
    if len(clips) != 1 or not roll:
        errors.append("expected the single animation 'roll', got %r" % [c[0] for c in clips])
        return
    _, extras, duration, curves = roll[0]
    if sorted(curves) != sorted((w, "rotation") for w in wheels):
        errors.append("clip 'roll' must rotate exactly the four wheels (body static), got %r"
                      % sorted(curves))
    radius = None
    by_name = dict((nm, i) for i, nm in enumerate(names))
    for (node, path), (interp, times, keys) in sorted(curves.items()):
        cw = "clip 'roll' %s of %r" % (path, node)
        if interp != "LINEAR" or len(times) != 9 or times[0] != 0.0:
            errors.append("%s: expected 9 LINEAR keys from 0 s (every 1/8 turn)" % cw)
            continue
        angles = [quat_angle_about_y(q) for q in keys]
        if any(a is None for a in angles):
            errors.append("%s: keys must be rotations about local +y" % cw)
            continue
        # unwrap: sign-continuous keys give half-angles that never jump by more than pi/2
        total = 0.0
        for a, b in zip(angles, angles[1:]):
            step = (b - a + math.pi) % (2.0 * math.pi) - math.pi
            if step <= 0.0:
                errors.append("%s: wheel does not turn forward (positive about +y)" % cw)
                break
            total += step
        else:
            if abs(total - 2.0 * math.pi) > 1e-4:
                errors.append("%s: turns %.4f rad, expected one full turn (2 pi)" % (cw, total))
        n = nodes[by_name[node]]
        if "mesh" in n and mesh_bbox[n["mesh"]] is not None:
            mlo, mhi = mesh_bbox[n["mesh"]]
            radius = 0.5 * (mhi[2] - mlo[2])
    speed = extras.get("nominal_speed_mps")
    if radius is not None and duration > 0.0:
        want = 2.0 * math.pi * radius / duration
        if speed is None or abs(speed - want) > 1e-4:
            errors.append("clip 'roll' extras.nominal_speed_mps %r != 2 pi r / duration = %.6f"
                          % (speed, want))


def check_file(path, reflectivity):
    """Return (errors, summary) for one glTF file."""
    errors = []
    name = os.path.splitext(os.path.basename(path))[0]
    try:
        with open(path, "r", encoding="utf-8") as fh:
            g = json.load(fh)
    except (ValueError, UnicodeDecodeError) as exc:
        return ["invalid JSON: %s" % exc], None
    if g.get("asset", {}).get("version") != "2.0":
        errors.append("asset.version is not '2.0'")
    bufs = decode_buffers(g, os.path.dirname(path), errors)
    for i, bv in enumerate(g.get("bufferViews", [])):
        if bv.get("byteOffset", 0) % 4:
            errors.append("bufferView %d byteOffset %d not 4-byte aligned" % (i, bv["byteOffset"]))

    materials = g.get("materials", [])
    for i, m in enumerate(materials):
        mname = m.get("name")
        if mname not in ALLOWED_MATERIALS:
            errors.append("material %d has name %r outside the allowed set" % (i, mname))
        elif reflectivity is not None and mname not in reflectivity:
            errors.append("material %r missing from materials.yaml" % mname)
        col = m.get("pbrMetallicRoughness", {}).get("baseColorFactor")
        if col is None or len(col) != 4 or any(not (0.0 <= c <= 1.0) for c in col):
            errors.append("material %r has no valid baseColorFactor" % mname)

    # ---- meshes: geometry checks, local bounding boxes, local positions
    mesh_points = []
    mesh_bbox = []
    mesh_tris = []
    mesh_skin = []  # per mesh: skinned primitive count, plain count, max joint, 3+ influences
    for mi, mesh in enumerate(g.get("meshes", [])):
        points = []
        volume = 0.0
        tris = 0
        skin_info = {"skinned": 0, "plain": 0, "max_joint": -1, "multi": 0}
        mesh_skin.append(skin_info)
        mname = mesh.get("name", "mesh%d" % mi)
        for pi, prim in enumerate(mesh.get("primitives", [])):
            where = "mesh %r primitive %d" % (mname, pi)
            if prim.get("mode", 4) != 4:
                errors.append("%s: mode %r is not TRIANGLES" % (where, prim.get("mode")))
                continue
            mat = prim.get("material")
            if mat is None or not (0 <= mat < len(materials)):
                errors.append("%s: missing or invalid material" % where)
            attrs = prim.get("attributes", {})
            if "POSITION" not in attrs or "NORMAL" not in attrs:
                errors.append("%s: POSITION and NORMAL attributes required" % where)
                continue
            pacc, pos = read_accessor(g, bufs, attrs["POSITION"])
            nacc, nor = read_accessor(g, bufs, attrs["NORMAL"])
            if pacc["componentType"] != 5126 or pacc["type"] != "VEC3":
                errors.append("%s: POSITION must be float32 VEC3" % where)
            if len(pos) != len(nor):
                errors.append("%s: POSITION count %d != NORMAL count %d" % (where, len(pos), len(nor)))
                continue
            if "min" not in pacc or "max" not in pacc:
                errors.append("%s: POSITION accessor lacks min/max" % where)
            else:
                dmin = [min(p[i] for p in pos) for i in range(3)]
                dmax = [max(p[i] for p in pos) for i in range(3)]
                for i in range(3):
                    if f32(pacc["min"][i]) != dmin[i] or f32(pacc["max"][i]) != dmax[i]:
                        errors.append("%s: POSITION min/max %r/%r do not match data %r/%r"
                                      % (where, pacc["min"], pacc["max"], dmin, dmax))
                        break
            for k, n in enumerate(nor):
                ln = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
                if abs(ln - 1.0) > 1e-3:
                    errors.append("%s: normal %d has length %.6f" % (where, k, ln))
                    break
            if "JOINTS_0" in attrs or "WEIGHTS_0" in attrs:
                skin_info["skinned"] += 1
                check_skin_attributes(g, bufs, attrs, len(pos), where, errors, skin_info)
            else:
                skin_info["plain"] += 1
            if "indices" not in prim:
                errors.append("%s: non-indexed primitive" % where)
                continue
            iacc, ind = read_accessor(g, bufs, prim["indices"])
            if iacc["componentType"] not in (5121, 5123, 5125) or iacc["type"] != "SCALAR":
                errors.append("%s: indices must be unsigned SCALAR" % where)
            if len(ind) % 3:
                errors.append("%s: index count %d not a multiple of 3" % (where, len(ind)))
                continue
            bad = [v for v in ind if v >= len(pos)]
            if bad:
                errors.append("%s: index %d out of range (%d vertices)" % (where, bad[0], len(pos)))
                continue
            ndeg = nflip = 0
            for t in range(0, len(ind), 3):
                a, b, c = pos[ind[t]], pos[ind[t + 1]], pos[ind[t + 2]]
                e1 = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
                e2 = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
                cr = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0])
                area = 0.5 * math.sqrt(cr[0] ** 2 + cr[1] ** 2 + cr[2] ** 2)
                if area < 1e-10:
                    ndeg += 1
                    continue
                nsum = [nor[ind[t]][i] + nor[ind[t + 1]][i] + nor[ind[t + 2]][i] for i in range(3)]
                if cr[0] * nsum[0] + cr[1] * nsum[1] + cr[2] * nsum[2] <= 0.0:
                    nflip += 1
                volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
                           + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
            tris += len(ind) // 3
            if ndeg:
                errors.append("%s: %d degenerate (zero-area) triangles" % (where, ndeg))
            if nflip:
                errors.append("%s: %d triangles whose winding disagrees with their normals"
                              % (where, nflip))
            points.extend(pos[v] for v in set(ind))
        if volume <= 0.0:
            errors.append("mesh %r encloses non-positive volume %.4g m^3 (inward winding?)"
                          % (mname, volume))
        mesh_points.append(points)
        mesh_tris.append(tris)
        if points:
            mesh_bbox.append(([min(p[i] for p in points) for i in range(3)],
                              [max(p[i] for p in points) for i in range(3)]))
        else:
            mesh_bbox.append(None)
    # ---- node hierarchy and world transforms
    nodes = g.get("nodes", [])
    names = [n.get("name") for n in nodes]
    dup = sorted(set(x for x in names if names.count(x) > 1 and x is not None))
    if dup:
        errors.append("duplicate node names %s" % dup)
    parent = {}
    for i, n in enumerate(nodes):
        for c in n.get("children", []):
            if not (0 <= c < len(nodes)):
                raise CheckError("node %r child index %r out of range" % (names[i], c))
            if c in parent:
                raise CheckError("node %r has more than one parent" % names[c])
            parent[c] = i
    scene = g.get("scenes", [{}])[g.get("scene", 0)]
    roots = scene.get("nodes", [])
    world = {}

    def visit(i, m, depth):
        if depth > len(nodes):
            raise CheckError("node hierarchy has a cycle")
        world[i] = mat_mul(m, node_matrix(nodes[i]))
        for c in nodes[i].get("children", []):
            visit(c, world[i], depth + 1)

    for r in roots:
        if r in parent:
            errors.append("scene root %r is also a child" % names[r])
        visit(r, mat_identity(), 0)
    lo = [float("inf")] * 3
    hi = [float("-inf")] * 3
    node_world_bbox = {}
    for i, n in enumerate(nodes):
        if "mesh" not in n:
            continue
        if i not in world:
            errors.append("node %r is not reachable from the scene" % names[i])
            continue
        nlo = [float("inf")] * 3
        nhi = [float("-inf")] * 3
        # a skinned mesh is in the bind pose; glTF ignores its node's transform
        m = mat_identity() if "skin" in n else world[i]
        for p in mesh_points[n["mesh"]]:
            q = transform(m, p)
            for k in range(3):
                nlo[k] = min(nlo[k], q[k])
                nhi[k] = max(nhi[k], q[k])
        node_world_bbox[names[i]] = (nlo, nhi)
        for k in range(3):
            lo[k] = min(lo[k], nlo[k])
            hi[k] = max(hi[k], nhi[k])
    size = [hi[k] - lo[k] for k in range(3)]
    # triangles as rendered: shared meshes (e.g. wheels) count once per instance
    total_tris = sum(mesh_tris[n["mesh"]] for n in nodes
                     if "mesh" in n and 0 <= n["mesh"] < len(mesh_tris))
    for i, n in enumerate(nodes):
        if not rest_rotation_ok(n):
            errors.append("node %r rotation is not a unit quaternion" % names[i])
    skin_joints = check_skins(g, bufs, nodes, names, world, mesh_skin, errors)
    clips = check_animations(g, bufs, nodes, names, errors)

    exp = EXPECTED.get(name, {})
    budget = exp.get("max_tris", MAX_TRIANGLES)
    if total_tris > budget:
        errors.append("%d triangles exceeds the budget of %d" % (total_tris, budget))
    if total_tris < exp.get("min_tris", 0):
        errors.append("%d triangles, fewer than the required %d" % (total_tris, exp["min_tris"]))

    exp = EXPECTED.get(name)
    if exp is None:
        errors.append("no expectations defined for this asset (unknown file name)")
    else:
        for k, axis in enumerate("xyz"):
            want = exp["size"][k]
            if want is not None and abs(size[k] - want) > TOL * want:
                errors.append("bounding-box %s extent %.3f m is not within 10%% of %.3f m"
                              % (axis, size[k], want))
        if exp["centred"]:
            for k, axis in enumerate("xy"):
                centre = 0.5 * (lo[k] + hi[k])
                if abs(centre) > max(0.05, 0.05 * size[k]):
                    errors.append("footprint centre %s = %.3f m is not at the origin" % (axis, centre))
        if exp["ground"] and abs(lo[2]) > 0.01:
            errors.append("lowest point z = %.3f m, expected to rest on z = 0" % lo[2])
        for req in exp["nodes"]:
            if req not in names:
                errors.append("required node %r missing" % req)
        by_name = dict((nm, i) for i, nm in enumerate(names))
        for req in exp["nodes"]:
            if req in WHEEL_SIGNS and req in by_name:
                i = by_name[req]
                n = nodes[i]
                t = transform(world.get(i, mat_identity()), (0.0, 0.0, 0.0))
                sx, sy = WHEEL_SIGNS[req]
                if t[0] * sx <= 0 or (sy and t[1] * sy <= 0):
                    errors.append("wheel %r at (%.2f, %.2f) is on the wrong side (front=+x, left=+y)"
                                  % (req, t[0], t[1]))
                if "mesh" not in n or mesh_bbox[n["mesh"]] is None:
                    errors.append("wheel %r has no mesh" % req)
                    continue
                mlo, mhi = mesh_bbox[n["mesh"]]
                c = [0.5 * (mlo[k] + mhi[k]) for k in range(3)]
                ext = [mhi[k] - mlo[k] for k in range(3)]
                if max(abs(v) for v in c) > 0.01:
                    errors.append("wheel %r mesh is not centred on its node origin (centre %s)"
                                  % (req, ["%.3f" % v for v in c]))
                if abs(ext[0] - ext[2]) > 0.05 * ext[0] or ext[1] >= ext[0]:
                    errors.append("wheel %r mesh is not a disc about local Y (extent %s)"
                                  % (req, ["%.3f" % v for v in ext]))
                wlo = node_world_bbox.get(req, ([0, 0, 1], None))[0]
                if abs(wlo[2]) > 0.02:
                    errors.append("wheel %r does not touch the ground (min z %.3f)" % (req, wlo[2]))
            if req in ("body",) and req in by_name:
                n = nodes[by_name[req]]
                if "mesh" not in n:
                    errors.append("node 'body' has no mesh")
        if name == "pedestrian":
            for child, par in sorted(PEDESTRIAN_PARENTS.items()):
                if child in by_name and par in by_name and parent.get(by_name[child]) != by_name[par]:
                    errors.append("node %r must be a child of %r" % (child, par))
            if "pelvis" in by_name:
                pi = by_name["pelvis"]
                if pi not in roots:
                    errors.append("'pelvis' must be the scene root")
                tz = nodes[pi].get("translation", [0, 0, 0])[2]
                if not 0.85 <= tz <= 1.05:
                    errors.append("pelvis translation z = %.3f, expected hip height ~0.95" % tz)
            for limb in HANGING_LIMBS:
                if limb not in by_name:
                    continue
                n = nodes[by_name[limb]]
                if "mesh" not in n or mesh_bbox[n["mesh"]] is None:
                    errors.append("limb %r has no mesh" % limb)
                    continue
                mlo, mhi = mesh_bbox[n["mesh"]]
                if mhi[2] > 0.02 or mlo[2] > -0.2:
                    errors.append("limb %r mesh must hang from its joint (local z %.3f..%.3f)"
                                  % (limb, mlo[2], mhi[2]))
                if any(k in n for k in ("rotation", "scale", "matrix")):
                    errors.append("limb %r should only carry a translation (joint pivot)" % limb)
        if name == "walker_skinned":
            check_walker(nodes, names, roots, parent, skin_joints, g.get("skins", []), clips,
                         mesh_skin, materials, errors)
        if name == "car_keyframed":
            check_car_keyframed(nodes, names, clips, mesh_bbox, errors)
    summary = (name, total_tris, lo, hi, size, names)
    return errors, summary


def generate_into(folder):
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "generate_assets.py")
    proc = subprocess.run([sys.executable, script, "--out", folder, "--quiet"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
    if proc.returncode != 0:
        raise CheckError("generate_assets.py failed:\n%s" % proc.stderr)


def read_tree(folder):
    out = {}
    for fn in sorted(os.listdir(folder)):
        with open(os.path.join(folder, fn), "rb") as fh:
            out[fn] = fh.read()
    return out


def check_generation(folder):
    errors = []
    with tempfile.TemporaryDirectory() as t1, tempfile.TemporaryDirectory() as t2:
        generate_into(t1)
        generate_into(t2)
        a, b = read_tree(t1), read_tree(t2)
        if sorted(a) != sorted(b):
            errors.append("generator: runs produced different file sets")
        for fn in sorted(set(a) & set(b)):
            if a[fn] != b[fn]:
                errors.append("%s: not deterministic (two generator runs differ)" % fn)
        for fn in sorted(a):
            path = os.path.join(folder, fn)
            if not os.path.exists(path):
                errors.append("%s: missing from %s (run generate_assets.py)" % (fn, folder))
                continue
            with open(path, "rb") as fh:
                if fh.read() != a[fn]:
                    errors.append("%s: differs from freshly generated output "
                                  "(stale; re-run generate_assets.py)" % fn)
    return errors


def main(argv=None):
    default_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                "..", "..", "assets"))
    ap = argparse.ArgumentParser(description="Validate generated glTF assets.")
    ap.add_argument("--dir", default=default_dir, help="asset folder (default: %(default)s)")
    ap.add_argument("--no-generate", action="store_true",
                    help="skip the determinism / up-to-date regeneration check")
    ap.add_argument("--quiet", action="store_true", help="only print failures")
    args = ap.parse_args(argv)

    failures = []
    if not os.path.isdir(args.dir):
        print("%s: not a directory" % args.dir)
        return 1
    reflectivity = None
    ypath = os.path.join(args.dir, "materials.yaml")
    try:
        reflectivity = parse_materials_yaml(ypath)
        for mname in sorted(ALLOWED_MATERIALS):
            if mname not in reflectivity:
                failures.append("materials.yaml: material %r missing" % mname)
        for mname, val in sorted(reflectivity.items()):
            if mname not in ALLOWED_MATERIALS:
                failures.append("materials.yaml: unknown material %r" % mname)
            if not 0.0 <= val <= 1.0:
                failures.append("materials.yaml: reflectivity of %r = %g outside [0, 1]" % (mname, val))
    except (OSError, CheckError) as exc:
        failures.append("materials.yaml: %s" % exc)

    files = sorted(f for f in os.listdir(args.dir) if f.endswith(".gltf"))
    present = set(os.path.splitext(f)[0] for f in files)
    for missing in sorted(set(EXPECTED) - present):
        failures.append("%s.gltf: missing" % missing)
    summaries = []
    for fn in files:
        try:
            errs, summary = check_file(os.path.join(args.dir, fn), reflectivity)
        except CheckError as exc:
            errs, summary = [str(exc)], None
        failures.extend("%s: %s" % (fn, e) for e in errs)
        if summary:
            summaries.append(summary)
    if not args.no_generate:
        try:
            failures.extend(check_generation(args.dir))
        except CheckError as exc:
            failures.append(str(exc))

    if not args.quiet:
        for name, tris, lo, hi, size, _ in summaries:
            print("%-20s %5d tris  size %6.2f x %5.2f x %5.2f m  z %.2f..%.2f"
                  % (name, tris, size[0], size[1], size[2], lo[2], hi[2]))
    if failures:
        for f in failures:
            print("FAIL " + f)
        print("%d problem(s) found" % len(failures))
        return 1
    if not args.quiet:
        print("OK: %d glTF files valid%s" % (len(files), "" if args.no_generate else
                                              "; generator deterministic and output up to date"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
