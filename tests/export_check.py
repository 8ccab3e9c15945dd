#!/usr/bin/python3
"""`cairn export` read back independently: every example (and every case file cairn loads)
written as OBJ and as glTF 2.0, then parsed here. Each 3-D piece must be a closed surface with
outward faces (every directed edge once, its reverse once; positive volume), each 2-D piece a
counter-clockwise polygon; the glTF's accessors must say what its buffer holds (counts, min and
max), and both formats must carry the same parts at the same places.
   args: CAIRN ROOT"""
import base64
import json
import pathlib
import struct
import subprocess
import sys
import tempfile
from collections import Counter

CAIRN, ROOT = sys.argv[1], pathlib.Path(sys.argv[2])
fails = []


def fail(msg):
    fails.append(msg)


def closed(tris, what):
    """Every directed edge once and its reverse once: closed, consistently oriented."""
    e = Counter()
    for t in tris:
        for k in range(3):
            e[(t[k], t[(k + 1) % 3])] += 1
    bad = [x for x, n in e.items() if n != 1 or e[(x[1], x[0])] != 1]
    if bad:
        fail(f"{what}: not a closed, consistently oriented surface (edge {bad[0]})")


def volume(tris, v):
    """About the first vertex: far from the origin the digits stay."""
    o = v[tris[0][0]]
    s = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = ([p[k] - o[k] for k in range(3)] for p in (v[a], v[b], v[c]))
        s += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    return s / 6


def read_obj(path):
    parts, verts = [], []
    for line in open(path, encoding="utf-8"):
        w = line.split()
        if not w or w[0].startswith("#"):
            continue
        if w[0] == "o":
            parts.append({"name": line[2:].rstrip("\n"), "pieces": []})
        elif w[0] == "g":
            parts[-1]["pieces"].append([])
        elif w[0] == "v":
            verts.append(tuple(map(float, w[1:4])))
        elif w[0] == "f":
            idx = [int(x) - 1 for x in w[1:]]
            if any(i < 0 or i >= len(verts) for i in idx) or len(idx) < 3:
                fail(f"{path}: bad face {line.strip()}")
                continue
            parts[-1]["pieces"][-1].append(idx)
    return parts, verts


def read_gltf(path):
    d = json.load(open(path))
    if d.get("asset", {}).get("version") != "2.0":
        fail(f"{path}: not glTF 2.0")
    uri = d["buffers"][0]["uri"]
    data = base64.b64decode(uri.split(",", 1)[1])
    if len(data) != d["buffers"][0]["byteLength"]:
        fail(f"{path}: buffer is {len(data)} bytes, byteLength says {d['buffers'][0]['byteLength']}")
    parts = []
    for node in d["nodes"]:
        mesh = d["meshes"][node["mesh"]]
        tr = node.get("translation", [0, 0, 0])  # the pieces are stored about it
        pieces = []
        for pr in mesh["primitives"]:
            pa, ia = d["accessors"][pr["attributes"]["POSITION"]], d["accessors"][pr["indices"]]
            pv, iv = d["bufferViews"][pa["bufferView"]], d["bufferViews"][ia["bufferView"]]
            pos = [struct.unpack_from("<3f", data, pv["byteOffset"] + 12 * k) for k in range(pa["count"])]
            idx = list(struct.unpack_from(f"<{ia['count']}I", data, iv["byteOffset"]))
            for k in range(3):
                lo, hi = min(p[k] for p in pos), max(p[k] for p in pos)
                if abs(lo - pa["min"][k]) > 1e-6 * (1 + abs(lo)) or abs(hi - pa["max"][k]) > 1e-6 * (1 + abs(hi)):
                    fail(f"{path}: accessor min/max disagree with the data")
            if any(i >= len(pos) for i in idx) or len(idx) % 3:
                fail(f"{path}: bad indices")
            pos = [tuple(p[k] + tr[k] for k in range(3)) for p in pos]
            pieces.append((pos, [tuple(idx[k:k + 3]) for k in range(0, len(idx), 3)]))
        parts.append({"name": node["name"], "fixed": node.get("extras", {}).get("fixed"), "pieces": pieces,
                      "translation": tr})
    return parts


# Known defect, kept visible: the 3-D hull (src/model/hull3.c) merges nearly coplanar qhull
# facets by flooding from one facet's plane, which is not transitive, so a few thin pieces of an
# exact decomposition get a T-junction (a vertex on one face's loop, not on its neighbour's).
# Contacts do not use the loops' closure; the exported surface of such a piece is not closed.
# This test fails when the file exports closed, so that the entry is removed with the fix.
KNOWN_OPEN = {"mesh_half_torus.json"}
known = {}
# The input-error cases (err_*) are left out: most are refused on loading (error_catalogue and the
# CLI cases run them), and the few that load are small variants of assemblies written here.
files = sorted(ROOT.glob("examples/*.json")) + sorted(
    f for d in ("tests/cases", "tests/cases_cgal") for f in (ROOT / d).glob("*.json") if not f.name.startswith("err_"))
n = 0
with tempfile.TemporaryDirectory() as t:
    for f in files:
        o, g = f"{t}/a.obj", f"{t}/a.gltf"
        r1 = subprocess.run([CAIRN, "export", str(f), "--to", "obj", o], capture_output=True, text=True)
        if r1.returncode != 0:
            continue  # files cairn refuses (error cases, plan-only files)
        r2 = subprocess.run([CAIRN, "export", str(f), "--to", "gltf", g], capture_output=True, text=True)
        if r2.returncode != 0:
            fail(f"{f.name}: OBJ written, glTF not: {r2.stderr.strip()}")
            continue
        n += 1
        doc = json.load(open(f))
        dim = doc["dimension"]
        op, ov = read_obj(o)
        gp = read_gltf(g)
        names = [p["name"] for p in doc["parts"]]
        if [p["name"] for p in op] != names or [p["name"] for p in gp] != names:
            fail(f"{f.name}: the parts written are not the file's")
            continue
        for p in doc["parts"]:
            gq = next(q for q in gp if q["name"] == p["name"])
            if gq["fixed"] != bool(p.get("fixed", False)):
                fail(f"{f.name}: {p['name']}: fixed not carried")
        for po, pg in zip(op, gp):
            if len(po["pieces"]) != len(pg["pieces"]):
                fail(f"{f.name}: {po['name']}: {len(po['pieces'])} pieces in OBJ, {len(pg['pieces'])} in glTF")
                continue
            for k, (faces, (pos, tris)) in enumerate(zip(po["pieces"], pg["pieces"])):
                what = f"{f.name}: {po['name']} piece {k}"
                used = sorted({i for fc in faces for i in fc})
                v = [ov[i] for i in used]
                # single precision about the part's middle (its node's translation, 9 digits)
                ext = max((max(x[k] for x in v) - min(x[k] for x in v) for k in range(3)), default=0)
                tol = 1e-6 * (1 + ext) + 1e-8 * max(map(abs, pg["translation"]))
                if len(v) != len(pos) or any(max(abs(a - b) for a, b in zip(x, y)) > tol for x, y in zip(v, pos)):
                    fail(f"{what}: OBJ and glTF vertices differ")
                if dim == 3:
                    otris = [(fc[0], fc[i], fc[i + 1]) for fc in faces for i in range(1, len(fc) - 1)]
                    nf = len(fails)
                    closed(otris, what + " (OBJ)")
                    closed(tris, what + " (glTF)")
                    if f.name in KNOWN_OPEN and len(fails) > nf:
                        known[f.name] = known.get(f.name, 0) + len(fails) - nf
                        del fails[nf:]
                    if not volume(otris, ov) > 0:
                        fail(f"{what}: faces point inwards (volume {volume(otris, ov)})")
                else:
                    fc = faces[0]
                    a2 = sum(ov[fc[i]][0] * ov[fc[(i + 1) % len(fc)]][1] - ov[fc[(i + 1) % len(fc)]][0] * ov[fc[i]][1]
                             for i in range(len(fc)))
                    if not a2 > 0:
                        fail(f"{what}: not counter-clockwise")
for name in sorted(KNOWN_OPEN):
    if name in known:
        print(f"export: known defect: {name}: {known[name]} piece surfaces not closed (hull3 T-junctions)")
    else:
        fail(f"{name} now exports closed pieces: remove it from KNOWN_OPEN")
for m in fails[:20]:
    print("FAIL export:", m)
if n < 20:
    print(f"FAIL export: only {n} files exported")
    sys.exit(1)
if fails:
    sys.exit(1)
print(f"export: {n} assemblies written as OBJ and glTF and read back: closed outward pieces, the same parts and places")
