#!/usr/bin/python3
"""Random prisms for the 3-D friction search (bench.md, section 23): 2-D scenes extruded along y,
gravity across y, each standing on friction in its section. Five families in turn: a block on an
incline under a fixed roof that touches it (the block needs tan(slope + tilt) of friction and may
tip), a wedge between a fixed block and a free one on a table, a wedge between two free blocks, two
rafters leaning on each other, and 3-D arches of 3 to 5 voussoirs (bench/vault.awk).

  usage: random_prisms.py SEED DIR COUNT     writes DIR/pNN_KIND.json and prints their names
A research measurement, not part of cairn.
"""
import json
import math
import os
import random
import subprocess
import sys


def ext(poly, y0=0.0, y1=1.0):
    return [[x, y, z] for (x, z) in poly for y in (y0, y1)]

def rot(poly, a, cx=0.0, cz=0.0):
    c, s = math.cos(a), math.sin(a)
    return [(cx + c * (x - cx) - s * (z - cz), cz + s * (x - cx) + c * (z - cz)) for x, z in poly]

def rect(x0, z0, x1, z1):
    return [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]

def part(name, poly, fixed=False, wide=False):
    d = {"name": name, "hull": ext(poly, -0.5, 1.5) if wide else ext(poly)}
    if fixed:
        d["fixed"] = True
    return d

def under_roof(r):
    th = math.radians(r.uniform(5, 20))
    ph = math.radians(r.uniform(-10, 10))
    need = abs(math.tan(th + ph))  # the friction the block needs on the incline
    mu = round(min(1.0, need + r.uniform(0.05, 0.3)), 3)
    w, h = r.uniform(0.6, 2.0), r.uniform(0.3, 1.0)
    base = rot(rect(-3, -1, 5, 0), th)
    blk = rot(rect(0, 0, w, h), th)
    roof = rot(rect(-3, h, 5, h + 0.5), th)
    g = [9.81 * math.sin(ph), 0, -9.81 * math.cos(ph)]
    parts = [part("base", base, True, True), part("roof", roof, True, True), part("b", blk)]
    return {"dimension": 3, "gravity": g, "friction": mu, "parts": parts}

def wedge(r, free_b):
    z0, h, top = r.uniform(0.3, 0.8), 1.0, 0.6
    a = math.radians(r.uniform(4, min(20, math.degrees(math.atan(0.5 / (h + z0))))))
    mu = round(r.uniform(0.3, 0.9), 3)
    bot = top - h * math.tan(a)
    # blocks' inner faces: x = +-(bot + (z - z0) tan a) for z in [0, z0 + h]
    def xin(z):
        return bot + (z - z0) * math.tan(a)
    A = [(-2.5, 0), (-xin(0), 0), (-xin(z0 + h), z0 + h), (-2.5, z0 + h)]
    B = [(x * -1, z) for (x, z) in A][::-1]
    W = [(-bot, z0), (bot, z0), (top, z0 + h), (-top, z0 + h)]
    parts = [part("table", rect(-6, -1, 6, 0), True, True), part("A", A),
             part("B", B, fixed=not free_b, wide=not free_b), part("wedge", W)]
    return {"dimension": 3, "friction": mu, "parts": parts}

def aframe(r):
    a = math.radians(r.uniform(10, 35))
    mu = round(r.uniform(0.3, 0.9), 3)
    L, t = 2.0, 0.2
    leg = [(0, 0), (t / math.cos(a), 0), (t / math.cos(a) + L * math.sin(a), L * math.cos(a)),
           (L * math.sin(a), L * math.cos(a))]
    # apex at x = L sin a + t/cos a: the right leg mirrored about it
    xm = L * math.sin(a) + t / math.cos(a)
    right = [(2 * xm - x, z) for (x, z) in leg][::-1]
    ground = part("ground", rect(-3, -1, 2 * xm + 3, 0), True, True)
    return {"dimension": 3, "friction": mu, "parts": [ground, part("L", leg), part("R", right)]}

def arch(r, path):
    n, mu = r.choice([3, 4, 5]), round(r.uniform(0.5, 1.0), 2)
    awk = os.path.join(os.path.dirname(os.path.abspath(__file__)), "vault.awk")
    with open(path, "w") as f:
        subprocess.run(["awk", "-v", "dim=3", "-v", f"n={n}", "-v", "c=1", "-v", f"mu={mu}", "-f", awk],
                       stdout=f, check=True)

def main():
    r, out, count = random.Random(int(sys.argv[1])), sys.argv[2], int(sys.argv[3])
    kinds = ["under_roof", "wedge1", "wedge2", "aframe", "arch"]
    for i in range(count):
        k = kinds[i % len(kinds)]
        name = f"{out}/p{i:02d}_{k}.json"
        if k == "arch":
            arch(r, name)
        else:
            d = {"under_roof": lambda: under_roof(r), "wedge1": lambda: wedge(r, False),
                 "wedge2": lambda: wedge(r, True), "aframe": lambda: aframe(r)}[k]()
            d["name"] = f"random prism {i} ({k})"
            with open(name, "w") as f:
                json.dump(d, f)
        print(name)

main()
