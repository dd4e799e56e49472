#!/usr/bin/env python3
"""Write sessions/gltf/boxes.gltf: a small glTF 2.0 test scene for reproj's glTF sessions.

A ground plane, a box spinning about Y (rotation, LINEAR), a box sliding inside a parent node
(translation LINEAR, scale STEP: the hierarchy and both interpolations), a static box, one
material with an 8x8 checker base-color texture (an embedded PNG), and a perspective camera.
Everything is embedded as data URIs, so the file stands alone. Run from the repository root:
    python3 scripts/make-gltf-boxes.py
"""
import base64, json, math, struct, zlib

def png(w, h, rgb_rows):
    raw = b"".join(b"\x00" + bytes(row) for row in rgb_rows)
    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))

buf = bytearray()
views, accessors = [], []

def add(data, fmt, count, typ, comp, target=None, minmax=None):
    while len(buf) % 4:
        buf.append(0)
    off = len(buf)
    for v in data:
        buf.extend(struct.pack(fmt, *v) if isinstance(v, (list, tuple)) else struct.pack(fmt, v))
    view = {"buffer": 0, "byteOffset": off, "byteLength": len(buf) - off}
    if target:
        view["target"] = target
    views.append(view)
    acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
    if minmax:
        acc["min"], acc["max"] = minmax
    accessors.append(acc)
    return len(accessors) - 1

FLOAT, USHORT = 5126, 5123
ARRAY, ELEMENTS = 34962, 34963

def cube():
    p, n, uv, idx = [], [], [], []
    faces = [((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0))]
    for nrm, u, v in faces:
        base = len(p)
        for (a, b) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            p.append([0.5 * (nrm[i] + a * u[i] + b * v[i]) for i in range(3)])
            n.append(list(nrm))
            uv.append([(a + 1) / 2, (1 - b) / 2])
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return p, n, uv, idx

def plane(size):
    h = size / 2
    p = [[-h, 0, h], [h, 0, h], [h, 0, -h], [-h, 0, -h]]
    return p, [[0, 1, 0]] * 4, [[0, 4], [4, 4], [4, 0], [0, 0]], [0, 1, 2, 0, 2, 3]

def mesh(p, n, uv, idx):
    lo = [min(v[i] for v in p) for i in range(3)]
    hi = [max(v[i] for v in p) for i in range(3)]
    attrs = {
        "POSITION": add(p, "<3f", len(p), "VEC3", FLOAT, ARRAY, (lo, hi)),
        "NORMAL": add(n, "<3f", len(n), "VEC3", FLOAT, ARRAY),
        "TEXCOORD_0": add(uv, "<2f", len(uv), "VEC2", FLOAT, ARRAY),
    }
    ind = add(idx, "<H", len(idx), "SCALAR", USHORT, ELEMENTS)
    return {"primitives": [{"attributes": attrs, "indices": ind, "material": 0}]}

meshes = [mesh(*cube()), mesh(*plane(8.0))]

def times(ts):
    return add(ts, "<f", len(ts), "SCALAR", FLOAT, None, ([min(ts)], [max(ts)]))

def quat_y(deg):
    a = math.radians(deg) / 2
    return [0.0, math.sin(a), 0.0, math.cos(a)]

t_spin = times([0.0, 0.8, 1.6])
r_spin = add([quat_y(0), quat_y(90), quat_y(180)], "<4f", 3, "VEC4", FLOAT)
t_slide = times([0.0, 1.6])
p_slide = add([[0, 0.3, -1.2], [0, 0.3, 1.2]], "<3f", 2, "VEC3", FLOAT)
t_step = times([0.0, 0.8])
s_step = add([[0.6, 0.6, 0.6], [0.9, 0.9, 0.9]], "<3f", 2, "VEC3", FLOAT)

checker = [[c for x in range(8) for c in ((230, 190, 90) if (x + y) % 2 else (60, 90, 160))]
           for y in range(8)]
pitch = math.radians(-24) / 2
doc = {
    "asset": {"version": "2.0", "generator": "reproj scripts/make-gltf-boxes.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 4, 5]}],
    "nodes": [
        {"name": "ground", "mesh": 1},
        {"name": "spinner", "mesh": 0, "translation": [-1.2, 0.5, 0]},
        {"name": "group", "translation": [1.2, 0, 0], "children": [3]},
        {"name": "slider", "mesh": 0, "scale": [0.6, 0.6, 0.6]},
        {"name": "static", "mesh": 0, "translation": [0, 0.5, -2.2]},
        {"name": "camera", "camera": 0, "translation": [0, 2.6, 5.2],
         "rotation": [math.sin(pitch), 0, 0, math.cos(pitch)]},
    ],
    "cameras": [{"type": "perspective",
                 "perspective": {"yfov": math.radians(45), "znear": 0.1, "zfar": 50.0}}],
    "meshes": meshes,
    "materials": [{"name": "checker", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
    "textures": [{"source": 0, "sampler": 0}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987}],
    "images": [{"uri": "data:image/png;base64,"
                + base64.b64encode(png(8, 8, checker)).decode()}],
    "animations": [{"name": "move", "samplers": [
        {"input": t_spin, "output": r_spin, "interpolation": "LINEAR"},
        {"input": t_slide, "output": p_slide, "interpolation": "LINEAR"},
        {"input": t_step, "output": s_step, "interpolation": "STEP"},
    ], "channels": [
        {"sampler": 0, "target": {"node": 1, "path": "rotation"}},
        {"sampler": 1, "target": {"node": 3, "path": "translation"}},
        {"sampler": 2, "target": {"node": 3, "path": "scale"}},
    ]}],
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buf),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode()}],
}
with open("sessions/gltf/boxes.gltf", "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
