#!/usr/bin/python3
"""Parts from mesh files (OBJ, STL ascii and binary, PLY, OFF): hand-derived verdicts, the same
verdicts as the equivalent box / hull files, and every refusal (exit 2, naming the file's JSON
path and the face). Meshes are written here, independently of cairn.
   args: CAIRN"""
import json
import math
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile

CAIRN = str(pathlib.Path(sys.argv[1]).resolve())
fails = []
T = pathlib.Path(tempfile.mkdtemp(prefix="cairn-mesh-"))


def fail(msg):
    fails.append(msg)


def box(lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return v, f


def gamma(a):
    """A Gamma standing on its leg: leg x 0..1, z 0..3; arm x 1..a, z 2..3; y 0..1. Faces are
    triangles and quads, outward."""
    o = [(0, 0), (1, 0), (1, 2), (a, 2), (a, 3), (0, 3)]
    v = [(x, 0.0, z) for x, z in o] + [(x, 1.0, z) for x, z in o]
    tri = [(0, 1, 2), (0, 2, 5), (2, 3, 4), (2, 4, 5)]
    f = [t for t in tri] + [(6 + t[0], 6 + t[2], 6 + t[1]) for t in tri]
    for i in range(6):
        j = (i + 1) % 6
        f.append((i, 6 + i, 6 + j, j))
    # outward: the y = 0 face must face -y
    (x0, _, z0), (x1, _, z1), (x2, _, z2) = v[0], v[1], v[2]
    ny = (z1 - z0) * (x2 - x0) - (x1 - x0) * (z2 - z0)
    if ny > 0:
        f = [tuple(reversed(t)) for t in f]
    return v, f


def turned(v, axis, deg, shift):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    out = []
    for x, y, z in v:
        if axis == "y":
            x, z = c * x + s * z, -s * x + c * z
        else:
            x, y = c * x - s * y, s * x + c * y
        out.append((x + shift[0], y + shift[1], z + shift[2]))
    return out


def tris(v, f):
    return [(v[t[0]], v[t[k]], v[t[k + 1]]) for t in f for k in range(1, len(t) - 1)]


def write(path, objs, fmt):
    """objs: [(name, (v, f))]; fmt obj writes one object each, the others join them."""
    path = T / path
    if fmt == "obj":
        lines, base = [], 1
        for name, (v, f) in objs:
            if len(objs) > 1:
                lines.append("o %s" % name)
            lines += ["v %r %r %r" % p for p in v]
            lines += ["f " + " ".join(str(base + i) for i in t) for t in f]
            base += len(v)
        path.write_text("\n".join(lines) + "\n")
        return path
    v, f = [], []
    for _, (ov, of) in objs:
        f += [tuple(len(v) + i for i in t) for t in of]
        v += ov
    if fmt == "stl":
        out = ["solid part"]
        for t in tris(v, f):
            out += [" facet normal 0 0 0", "  outer loop"] + ["   vertex %r %r %r" % p for p in t]
            out += ["  endloop", " endfacet"]
        path.write_text("\n".join(out + ["endsolid part"]) + "\n")
    elif fmt == "stlb":
        ts = tris(v, f)
        b = bytearray(80) + struct.pack("<I", len(ts))
        for t in ts:
            b += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
        path.write_bytes(bytes(b))
    elif fmt == "ply":
        hdr = ["ply", "format ascii 1.0", "element vertex %d" % len(v), "property double x",
               "property double y", "property double z", "element face %d" % len(f),
               "property list uchar int vertex_indices", "end_header"]
        path.write_text("\n".join(hdr + ["%r %r %r" % p for p in v] +
                                  ["%d %s" % (len(t), " ".join(map(str, t))) for t in f]) + "\n")
    elif fmt == "off":
        path.write_text("\n".join(["OFF", "%d %d 0" % (len(v), len(f))] + ["%r %r %r" % p for p in v] +
                                  ["%d %s" % (len(t), " ".join(map(str, t))) for t in f]) + "\n")
    return path


TABLE = {"name": "table", "fixed": True, "box": {"min": [-5, -5, -1], "max": [5, 5, 0]}}


def run(part, name, args=(), mu=0.5):
    doc = {"dimension": 3, "friction": mu, "parts": [TABLE, dict(part, name="P")]}
    f = T / (name + ".json")
    f.write_text(json.dumps(doc))
    p = subprocess.run([CAIRN, "check", str(f), "--json", *args], capture_output=True, text=True)
    return p, (json.loads(p.stdout) if p.returncode in (0, 1) and p.stdout else None)


def outcome(j):
    return (j["verdict"], tuple(j["moving_parts"]), round(j["reference_weight"]["weight"], 6))


FORMATS = {"obj": "obj", "stl": "stl", "stlb": "stl", "ply": "ply", "off": "off"}
cases = 0


def compare(label, objs, extra, reference, want):
    """Every format of the mesh against the reference part (box or hulls) and the verdict."""
    global cases
    p, j = run(reference, label + "_ref")
    if not j:
        fail("%s: the reference did not run: %s" % (label, p.stderr.strip()))
        return
    ref = outcome(j)
    if ref[0] != want:
        fail("%s: the reference is %s, not %s" % (label, ref[0], want))
    # OBJ keeps objects apart (each a closed piece); the other formats have none, so a part of
    # several boxes is written as one closed surface, their union (as is OBJ once more)
    one = [("all", union(objs))] if len(objs) > 1 else objs
    fmts = [("obj", objs), ("stl", one), ("stlb", one), ("ply", one), ("off", one)]
    if len(objs) > 1:
        fmts.append(("obj", one))
    for k, (fmt, o) in enumerate(fmts):
        mesh = write("%s_%d.%s" % (label, k, FORMATS[fmt]), o, fmt)
        p, j = run(dict(extra, mesh=mesh.name), "%s_%d" % (label, k))
        cases += 1
        if not j:
            fail("%s as %s: exit %d: %s" % (label, fmt, p.returncode, p.stderr.strip()))
            continue
        if outcome(j) != ref:
            fail("%s as %s: %s, the reference %s" % (label, fmt, outcome(j), ref))


def union(objs):
    """The Gamma's leg and arm as one closed surface (the arm's far end gives a)."""
    return gamma(objs[1][1][0][1][0])


# 1. a unit cube turned 30 degrees about the vertical: stands (as a turned box)
cube = box((-0.5, -0.5, 0), (0.5, 0.5, 1))
compare("cube_turned", [("cube", cube)], {"rotation": {"axis": [0, 0, 1], "angle": 30}},
        {"box": {"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}, "rotation": {"axis": [0, 0, 1], "angle": 30}},
        "stable")
# 2. a cube resting on an edge, turned 40 degrees about y: its centre is beyond the edge
c = box((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5))
low = min(p[2] for p in turned(c[0], "y", 40, (0, 0, 0)))
shift = (0, 0, -low)
compare("cube_edge", [("cube", c)], {"rotation": {"axis": [0, 1, 0], "angle": 40}, "position": list(shift)},
        {"hull": [list(p) for p in turned(c[0], "y", 40, shift)]}, "unstable")
# 3. a Gamma on its leg: centre inside the leg (arm to x = 2: x_c = 0.75) stands, outside
#    (arm to x = 3: x_c = 1.1) tips
for a, want in ((2, "stable"), (3, "unstable")):
    leg, arm = box((0, 0, 0), (1, 1, 3)), box((1, 0, 2), (a, 1, 3))
    compare("gamma%d" % a, [("leg", leg), ("arm", arm)], {},
            {"hulls": [[list(p) for p in leg[0]], [list(p) for p in arm[0]]]}, want)
    # one non-convex mesh: split exactly, and the report says so
    mesh = write("gamma%d_one.obj" % a, [("g", gamma(a))], "obj")
    p, j = run({"mesh": mesh.name}, "gamma%d_one" % a)
    if not j or j["verdict"] != want or j["meshes"][0]["pieces_from_decomposition"] < 2:
        fail("gamma %d as one mesh: %s %s" % (a, j and j["verdict"], j and j["meshes"]))
    cases += 1

# 4. scale: a cube of side 1 scaled by 2 weighs 8 times as much
mesh = write("unit.obj", [("c", box((0, 0, 0), (1, 1, 1)))], "obj")
p1, j1 = run({"mesh": "unit.obj"}, "unit")
p2, j2 = run({"mesh": "unit.obj", "scale": 2}, "unit2")
if not (j1 and j2 and abs(j2["reference_weight"]["weight"] / j1["reference_weight"]["weight"] - 8) < 1e-9):
    fail("scale 2: weights %s, %s" % (j1 and j1["reference_weight"], j2 and j2["reference_weight"]))
cases += 1

# 5. refusals: exit 2, the part's JSON path, what is wrong
v, f = box((0, 0, 0), (1, 1, 1))
(T / "sub").mkdir()
write("sub/inside.obj", [("c", (v, f))], "obj")
bad = {
    "open": ([("c", (v, f[:-1]))], "is open: an edge of face"),
    "flipped": ([("c", (v, f[:-1] + [tuple(reversed(f[-1]))]))], "oriented inconsistently"),
    "degenerate": ([("c", (v + [(0, 0, 0)], f + [(0, 8, 0)]))], "is degenerate"),
    "self_intersecting": ([("g", gamma_x)] if (gamma_x := (lambda g: ([(-0.5, p[1], 2.5) if i in (3, 9) else p for i, p in enumerate(g[0])], g[1]))(gamma(3))) else [], "intersects itself"),
}
for name, (objs, msg) in bad.items():
    write(name + ".obj", objs, "obj")
    p, _ = run({"mesh": name + ".obj"}, "bad_" + name)
    cases += 1
    if p.returncode != 2 or "parts[1].mesh" not in p.stderr or msg not in p.stderr:
        fail("%s mesh: exit %d, stderr %r (wanted exit 2 and %r)" % (name, p.returncode, p.stderr.strip(), msg))
(T / "notamesh.obj").write_text("hello\n")
for name, part, msg in (("missing", {"mesh": "nowhere.obj"}, "cannot open the mesh file"),
                        ("notamesh", {"mesh": "notamesh.obj"}, "parts[1].mesh"),
                        ("scale_box", {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "scale": 2}, "applies to a mesh only")):
    p, _ = run(part, "bad_" + name)
    cases += 1
    if p.returncode != 2 or msg not in p.stderr:
        fail("%s: exit %d, stderr %r" % (name, p.returncode, p.stderr.strip()))
# a path outside the assembly file's directory: refused, unless --mesh-anywhere
doc = {"dimension": 3, "parts": [TABLE, {"name": "P", "mesh": "../unit.obj"}]}
(T / "sub" / "out.json").write_text(json.dumps(doc))
p = subprocess.run([CAIRN, "check", str(T / "sub" / "out.json")], capture_output=True, text=True)
q = subprocess.run([CAIRN, "check", str(T / "sub" / "out.json"), "--mesh-anywhere"], capture_output=True, text=True)
if p.returncode != 2 or "outside the assembly file's directory" not in p.stderr or q.returncode != 0:
    fail("outside path: exit %d (%s), with --mesh-anywhere exit %d (%s)" % (p.returncode, p.stderr.strip(), q.returncode, q.stderr.strip()))
doc["parts"][1]["mesh"] = "inside.obj"
(T / "sub" / "in.json").write_text(json.dumps(doc))
p = subprocess.run([CAIRN, "check", str(T / "sub" / "in.json")], capture_output=True, text=True, cwd="/")
if p.returncode != 0:
    fail("a mesh beside its assembly file, run from /: exit %d (%s)" % (p.returncode, p.stderr.strip()))
# a 2-D assembly has no meshes
p = subprocess.run([CAIRN, "check", "-"], input=json.dumps({"dimension": 2, "parts": [{"name": "P", "mesh": "unit.obj"}]}),
                   capture_output=True, text=True)
if p.returncode != 2 or "3-D shape" not in p.stderr:
    fail("2-D mesh: exit %d (%s)" % (p.returncode, p.stderr.strip()))
cases += 4

for m in fails:
    print("FAIL:", m)
print("meshes: %d cases, %d failures%s" % (cases, len(fails), " (files in %s)" % T if fails else ""))
if not fails:
    shutil.rmtree(T)
sys.exit(1 if fails else 0)
