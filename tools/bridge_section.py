#!/usr/bin/env python3
"""Write the x-z section of compas_cra's bridge (examples/compas/bridge.json) as a 2-D cairn file.

Every block of the bridge is a prism along y, so its face at the lowest y is its exact section.
A part's polygon is the outer boundary of that face (the edges no other face of the same y
shares; the loop of largest area), without collinear points. Parts 0 and 1 (the piers) are
fixed; gravity is -9.81 along the section's second axis (the file's z).

    tools/bridge_section.py [MU] > examples/compas/bridge_section.json     (MU default 0.9)
"""
import json
import sys
from collections import Counter, defaultdict

ROOT = __file__.rsplit("/tools/", 1)[0]


def area(poly):
    return 0.5 * sum(poly[i][0] * poly[i - 1][1] - poly[i - 1][0] * poly[i][1] for i in range(len(poly)))


def collinear(a, b, c):
    return abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) < 1e-12


def section(block):
    v = block["vertex"]
    y0 = min(p["y"] for p in v.values())
    edges = Counter()
    for f in block["face"].values():
        if all(v[str(i)]["y"] == y0 for i in f):
            for a, b in zip(f, f[1:] + f[:1]):
                edges[frozenset((a, b))] += 1
    adj = defaultdict(list)
    for e, n in edges.items():
        if n == 1:
            a, b = tuple(e)
            adj[a].append(b)
            adj[b].append(a)
    if any(len(x) != 2 for x in adj.values()):
        raise SystemExit("a face at the lowest y is not bounded by simple loops")
    seen, loops = set(), []
    for start in adj:
        if start in seen:
            continue
        loop, prev, cur = [start], None, start
        seen.add(start)
        while True:
            nxt = [x for x in adj[cur] if x != prev and x not in seen]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            loop.append(cur)
            seen.add(cur)
        loops.append(loop)
    pts = lambda loop: [(v[str(i)]["x"], v[str(i)]["z"]) for i in loop]
    poly = pts(max(loops, key=lambda loop: abs(area(pts(loop)))))
    changed = True
    while changed:
        changed = False
        for i in range(len(poly)):
            if collinear(poly[i - 1], poly[i], poly[(i + 1) % len(poly)]):
                poly.pop(i)
                changed = True
                break
    return poly


def main():
    mu = float(sys.argv[1]) if len(sys.argv) > 1 else 0.9
    d = json.load(open(ROOT + "/examples/compas/bridge.json"))
    nodes = d["data"]["graph"]["data"]["node"]
    parts = []
    for k in sorted(nodes, key=int):
        part = {"name": k, "polygon": [list(p) for p in section(nodes[k]["block"]["data"])]}
        if k in ("0", "1"):
            part["fixed"] = True
        parts.append(part)
    out = {"name": "bridge x-z section (y=0 faces of compas_cra bridge.json)", "dimension": 2,
           "gravity": [0, -9.81], "friction": mu, "parts": parts}
    print(json.dumps(out, indent=1))


main()
