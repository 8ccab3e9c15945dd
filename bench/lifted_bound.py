#!/usr/bin/python3
"""How much power can gravity put into a motion from rest, at most? Two relaxations of the
friction LCP that `cairn check --lcp-out` writes (bench.md, section 20).

The LCP is Stewart-Trinkle's, unknowns z = [p_n (K); p_f (K D); lambda (K)], w = M z + q. With
x = [p_n; p_f] and A = M[x, x] (= J M^-1 J^T), every solution has kinetic energy
|a|^2 = c + 2 q_x.x + x^T A x and gravity's power c + q_x.x, where c = |fext|^2 (free fall; a
static solution has power 0). The search for a motion (src/check/strong.c) bounds the power by
an LP; its limit with every energy cut is the convex relaxation below. The lifted one (Shor's
semidefinite relaxation with the products z_i w_j >= 0 and Z >= 0, a doubly nonnegative
relaxation) replaces z z^T by a matrix Z and keeps every product of two sides of the problem.

  usage: lifted_bound.py FILE.lcp [K D] [convex|floors|lifted]...
K (contact points) and D (friction directions) are read from the LCP's last row when not given.
Prints, for each relaxation, the bound on the power as a fraction of free fall and the seconds.
Needs python3-numpy and python3-cvxopt (Debian). A research measurement, not part of cairn.
"""
import sys
import time

import numpy as np
from cvxopt import matrix, solvers, sparse, spmatrix

solvers.options["show_progress"] = False


def load(path):
    t = open(path).read().split()
    n = int(t[0])
    a = np.array(t[1:], float)
    return n, a[: n * n].reshape(n, n), a[n * n : n * n + n]


def spm(rows, ncol):
    ii, jj, vv = [], [], []
    for r, d in enumerate(rows):
        for c, v in d.items():
            ii.append(r), jj.append(c), vv.append(v)
    return spmatrix(vv, ii, jj, (len(rows), ncol))


def factor(A):
    """L with A = L^T L (A symmetric positive semidefinite)."""
    ev, V = np.linalg.eigh(A)
    keep = ev > 1e-12 * ev.max()
    return (V[:, keep] * np.sqrt(ev[keep])).T


def energy_cone(L, lin, N, nx):
    """x^T L^T L x + lin.z <= 0 as a second-order cone over N unknowns (x the first nx):
    ||(2 L x, 1 - t)|| <= 1 + t with t = -lin.z. Returns (G, h) rows."""
    G, h = np.zeros((L.shape[0] + 2, N)), np.zeros(L.shape[0] + 2)
    G[0], h[0] = lin, 1.0
    G[1], h[1] = -lin, 1.0
    G[2:, :nx] = -2 * L
    return G, h


def convex(n, M, q, nx, c):
    """max power s.t. z >= 0, w >= 0, |a|^2 <= power (every complementarity dropped)."""
    qx = q[:nx]
    lin = np.zeros(n)
    lin[:nx] = qx
    Gl = np.vstack([-np.eye(n), -M])
    hl = np.concatenate([np.zeros(n), q])
    Gs, hs = energy_cone(factor(M[:nx, :nx]), lin, n, nx)
    obj = np.zeros(n)
    obj[:nx] = -qx
    s = solvers.conelp(matrix(obj), matrix(np.vstack([Gl, Gs])), matrix(np.concatenate([hl, hs])),
                       dims={"l": 2 * n, "q": [Gs.shape[0]], "s": []})
    return s["status"], c - s["primal objective"], c - s["dual objective"]


def floors(n, M, q, nx, c):
    """The convex relaxation with normal-force floors (src/check/search_lp.c): the points whose
    friction rows are parallel slide together (a 2-D joint); each such group J's least total
    normal force l_J over the relaxation bounds its dissipation, x^T A x + q_x.x <= -mu l_J s_J
    with s_J >= |slip of J|, and the power is maximised again. Prints the floors' count."""
    D = int(np.sum(M[n - 1] == -1))
    K = n // (D + 2)
    A, qx = M[:nx, :nx], q[:nx]
    mu = np.array([M[nx + i, i] for i in range(K)])
    L = factor(A)
    groups = {}
    for i in range(K):
        R = A[K + i * D:K + (i + 1) * D]
        groups.setdefault(tuple(np.round((R / np.linalg.norm(R)).ravel(), 6)), []).append(i)
    J = list(groups.values())
    nJ, N = len(J), n + len(J)

    def solve(obj, ell):
        lin = np.zeros(N)
        lin[:nx] = qx
        lin[n:] = np.array([mu[j[0]] for j in J]) * ell
        Gl = [np.hstack([-np.eye(n), np.zeros((n, nJ))]), np.hstack([-M, np.zeros((n, nJ))])]
        hl = [np.zeros(n), q]
        for jj, pts in enumerate(J):  # s_J >= -(A x + q)_row for each friction row of J
            i = pts[0]
            for k in range(D):
                row = np.zeros(N)
                row[:nx], row[n + jj] = -A[K + i * D + k], -1
                Gl.append(row[None, :]), hl.append(np.array([qx[K + i * D + k]]))
        Gs, hs = energy_cone(L, lin, N, nx)
        return solvers.conelp(matrix(np.concatenate([obj, np.zeros(nJ)])), matrix(np.vstack(Gl + [Gs])),
                              matrix(np.concatenate(hl + [hs])), dims={"l": sum(len(h) for h in hl),
                                                                        "q": [Gs.shape[0]], "s": []})

    ell = np.zeros(nJ)
    for jj, pts in enumerate(J):
        if len(pts) < 2:
            continue  # a single point can lose its load by rocking
        o = np.zeros(n)
        o[pts] = 1
        s = solve(o, np.zeros(nJ))
        ell[jj] = max(0.0, s["primal objective"] * (1 - 1e-6) - 1e-6) if s["status"] == "optimal" else 0.0
    print(f"floors: {int(np.sum(ell > 0))} of {nJ} groups have a positive floor")
    obj = np.zeros(n)
    obj[:nx] = -qx
    s = solve(obj, ell)
    return s["status"], c - s["primal objective"], c - s["dual objective"]


def lifted(n, M, q, nx, c):
    """max power over Y = [[1, z^T], [z, Z]] >= 0 (semidefinite), Z >= 0, w >= 0,
    z_i w_j >= 0 (as sum_k M_jk Z_ik + q_j z_i), z_i w_i = 0."""
    qx = q[:nx]
    idx = {}
    k = n
    for i in range(n):
        for j in range(i, n):
            idx[i, j] = idx[j, i] = k
            k += 1
    nv = k
    rows, h = [], []
    for i in range(n):
        rows.append({i: -1.0}), h.append(0.0)
    for i in range(n):
        rows.append({j: -M[i, j] for j in range(n) if M[i, j] != 0}), h.append(q[i])
    for i in range(n):
        for j in range(i, n):
            rows.append({idx[i, j]: -1.0}), h.append(0.0)
    for i in range(n):
        for j in range(n):
            d = {}
            for kk in np.nonzero(M[j])[0]:
                d[idx[i, kk]] = d.get(idx[i, kk], 0.0) - M[j, kk]
            d[i] = d.get(i, 0.0) - q[j]
            rows.append(d), h.append(0.0)
    eq = []
    for i in range(n):
        d = {}
        for kk in np.nonzero(M[i])[0]:
            d[idx[i, kk]] = d.get(idx[i, kk], 0.0) + M[i, kk]
        d[i] = d.get(i, 0.0) + q[i]
        eq.append(d)
    m = n + 1
    ii, jj, vv = [], [], []
    hsd = np.zeros(m * m)
    for a in range(m):
        for b in range(m):
            r = a + b * m
            if a == 0 and b == 0:
                hsd[r] = 1.0
            else:
                ii.append(r), jj.append(b - 1 if a == 0 else a - 1 if b == 0 else idx[a - 1, b - 1])
                vv.append(-1.0)
    G = sparse([spm(rows, nv), spmatrix(vv, ii, jj, (m * m, nv))])
    obj = np.zeros(nv)
    obj[:nx] = -qx
    s = solvers.conelp(matrix(obj), G, matrix(np.concatenate([np.array(h), hsd])),
                       dims={"l": len(rows), "q": [], "s": [m]}, A=spm(eq, nv), b=matrix(np.zeros(n)))
    return s["status"], c - s["primal objective"], c - s["dual objective"]


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    n, M, q = load(sys.argv[1])
    args = sys.argv[2:]
    if len(args) >= 2 and args[0].isdigit():
        K, D = int(args[0]), int(args[1])
        args = args[2:]
    else:  # the last sliding-speed row: mu on its point's normal, -1 on each friction direction
        D = int(np.sum(M[n - 1] == -1))
        K = n // (D + 2) if D > 0 else 0
    if K <= 0 or n != K * (D + 2):
        sys.exit(f"{sys.argv[1]}: {n} unknowns, not K (D + 2) with K = {K}, D = {D}: give K and D")
    nx = K + K * D
    A, qx = M[:nx, :nx], q[:nx]
    c = -qx @ np.linalg.lstsq(A, -qx, rcond=None)[0]  # |fext|^2: the largest power, free fall
    for kind in args or ["convex", "lifted"]:
        t = time.time()
        st, primal, dual = {"convex": convex, "floors": floors, "lifted": lifted}[kind](n, M, q, nx, c)
        print(f"{kind}: {st}, power at most {dual / c:.3g} of free fall (primal {primal / c:.3g}), "
              f"{time.time() - t:.1f} s, {n} unknowns")


if __name__ == "__main__":
    main()
