#!/usr/bin/python3
"""Independent optimum of max ||L(x)||_p over the simplex for D, A and E with cvxopt.

Usage: graph_information_cvxopt.py "n m u1-v1 u2-v2 ..."   (a graph-list line, 1-based ids)
Prints one JSON object {"D": value, "A": value, "E": value} with the thesis' normalised
information functions (power means over the n-1 non-zero Laplacian eigenvalues).

D uses cvxopt.solvers.cp on log det of the reduced Laplacian Q^T L(x) Q (Q an orthonormal
basis of 1-perp); A is the SDP min tr(Y) s.t. [[Q^T L(x) Q, I], [I, Y]] >= 0; E is the SDP
max t s.t. Q^T L(x) Q - t I >= 0, sum x = 1, x >= 0 with cvxopt.solvers.sdp.
Used by tests/test_graph_information.cpp (needs Debian's python3-cvxopt; no numpy).
"""
import json
import math
import sys

from cvxopt import lapack, matrix, solvers, spmatrix

# Tighter than the defaults (1e-7/1e-6); much tighter makes cvxopt break down near the end.
TIGHT = {"show_progress": False, "abstol": 1e-9, "reltol": 1e-9, "feastol": 1e-9,
         "maxiters": 200}
MEDIUM = {"show_progress": False, "abstol": 1e-8, "reltol": 1e-8, "feastol": 1e-8,
          "maxiters": 200}
LOOSE = {"show_progress": False}


def solve(fn):
    """fn() with tight tolerances, falling back to cvxopt's defaults if that breaks down."""
    seen = []
    for opts in (TIGHT, MEDIUM, LOOSE):
        solvers.options.clear()
        solvers.options.update(opts)
        try:
            sol = fn()
            if sol["status"] == "optimal":
                return sol
            # 'unknown' = stopped without meeting every tolerance; keep it if it is converged
            # far beyond what the comparison needs (gap and feasibility below 1e-8).
            gap = sol.get("relative gap")
            pinf, dinf = sol.get("primal infeasibility"), sol.get("dual infeasibility")
            if gap is not None and gap < 1e-8 and pinf < 1e-8 and dinf < 1e-8:
                return sol
            seen.append("%s (relative gap %s, infeasibility %s / %s)" % (sol["status"], gap, pinf, dinf))
        except (ArithmeticError, ValueError) as e:
            seen.append(repr(e))
    raise RuntimeError("cvxopt did not reach an optimal solution: " + "; ".join(seen))


def parse(line):
    tok = line.split()
    n, m = int(tok[0]), int(tok[1])
    edges = []
    for t in tok[2:2 + m]:
        u, v = t.split("-")
        u, v = int(u) - 1, int(v) - 1
        if u != v:
            edges.append((u, v))
    return n, edges


def helmert(n):
    """n x (n-1) orthonormal basis of the complement of the all-ones vector."""
    Q = matrix(0.0, (n, n - 1))
    for i in range(1, n):
        s = 1.0 / math.sqrt(i * (i + 1))
        for r in range(i):
            Q[r, i - 1] = s
        Q[i, i - 1] = -i * s
    return Q


def design(n, edges):
    """Rows b_j = Q^T (e_u - e_v) as a list of k-vectors."""
    Q = helmert(n)
    k = n - 1
    return [[Q[u, c] - Q[v, c] for c in range(k)] for (u, v) in edges], k


def moment(B, x, k):
    M = matrix(0.0, (k, k))
    for j, b in enumerate(B):
        for r in range(k):
            if b[r] == 0.0:
                continue
            for c in range(k):
                M[r, c] += x[j] * b[r] * b[c]
    return M


def inverse(M):
    """Inverse of a PD matrix, or None."""
    P = matrix(M)
    try:
        lapack.potrf(P)
    except ArithmeticError:
        return None
    logdet = 2.0 * sum(math.log(P[i, i]) for i in range(P.size[0]))
    lapack.potri(P)
    k = P.size[0]
    for r in range(k):
        for c in range(r + 1, k):
            P[r, c] = P[c, r]
    return P, logdet


def quad(B, X):
    """[b_j^T X b_l] for all j, l."""
    W = [X * matrix(b) for b in B]
    return [[sum(B[j][r] * W[l][r] for r in range(len(B[j]))) for l in range(len(B))]
            for j in range(len(B))]


def doptimal(B, k):
    """max log det(Q^T L(x) Q) over the simplex with cvxopt.solvers.cp."""
    m = len(B)
    G = spmatrix(-1.0, range(m), range(m))
    h = matrix(0.0, (m, 1))
    A = matrix(1.0, (1, m))
    b = matrix(1.0)

    def F(x=None, z=None):
        if x is None:
            return 0, matrix(1.0 / m, (m, 1))
        if min(x) < 0:
            return None
        inv = inverse(moment(B, x, k))
        if inv is None:
            return None
        P, logdet = inv
        R = quad(B, P)
        Df = matrix([-R[j][j] for j in range(m)], (1, m))
        if z is None:
            return -logdet, Df
        H = matrix([[z[0] * R[j][l] ** 2 for j in range(m)] for l in range(m)])
        return -logdet, Df, H

    sol = solve(lambda: solvers.cp(F, G=G, h=h, A=A, b=b))
    _, logdet = inverse(moment(B, sol["x"], k))
    return math.exp(logdet / k)


def aoptimal(B, k):
    """min tr(Y) s.t. [[M(x), I], [I, Y]] >= 0, sum x = 1, x >= 0 (cvxopt's cp stalls on
    some graphs for tr(M^-1) directly)."""
    m = len(B)
    pairs = [(r, c) for c in range(k) for r in range(c, k)]
    nv = m + len(pairs)
    K = 2 * k
    cvec = matrix([0.0] * m + [1.0 if r == c else 0.0 for (r, c) in pairs])
    Gl = spmatrix(-1.0, range(m), range(m), (m, nv))
    hl = matrix(0.0, (m, 1))
    cols = []
    for bj in B:
        col = [0.0] * (K * K)
        for cc in range(k):
            for r in range(k):
                col[cc * K + r] = -bj[r] * bj[cc]
        cols.append(col)
    for (r, c) in pairs:
        col = [0.0] * (K * K)
        col[(k + c) * K + (k + r)] = -1.0
        col[(k + r) * K + (k + c)] = -1.0
        cols.append(col)
    hs = matrix(0.0, (K, K))
    for i in range(k):
        hs[k + i, i] = hs[i, k + i] = 1.0
    A = matrix([1.0] * m + [0.0] * len(pairs), (1, nv))
    sol = solve(lambda: solvers.sdp(cvec, Gl=Gl, hl=hl, Gs=[matrix(cols)], hs=[hs], A=A,
                                    b=matrix(1.0)))
    w = [max(0.0, sol["x"][j]) for j in range(m)]
    s = sum(w)
    P, _ = inverse(moment(B, [wi / s for wi in w], k))
    return k / sum(P[i, i] for i in range(k))


def eoptimal(B, k):
    m = len(B)
    nv = m + 1  # x_1..x_m, t
    c = matrix([0.0] * m + [-1.0])
    Gl = spmatrix(-1.0, range(m), range(m), (m, nv))
    hl = matrix(0.0, (m, 1))
    # hs - sum_i y_i Gs_i >= 0 with hs = 0: Gs column of x_j = -vec(b b^T), of t = vec(I).
    cols = []
    for bj in B:
        cols.append([-bj[r] * bj[cc] for cc in range(k) for r in range(k)])
    cols.append([1.0 if r == cc else 0.0 for cc in range(k) for r in range(k)])
    Gs = [matrix(cols)]
    hs = [matrix(0.0, (k, k))]
    A = matrix([1.0] * m + [0.0], (1, nv))
    sol = solve(lambda: solvers.sdp(c, Gl=Gl, hl=hl, Gs=Gs, hs=hs, A=A, b=matrix(1.0)))
    x = sol["x"]
    w = [max(0.0, x[j]) for j in range(m)]
    s = sum(w)
    M = moment(B, [wi / s for wi in w], k)
    ev = matrix(0.0, (k, 1))
    lapack.syev(M, ev)
    return min(ev), -sol["primal objective"], -sol["dual objective"], sol["status"]


def main():
    n, edges = parse(sys.argv[1])
    B, k = design(n, edges)
    e_value, e_primal, e_dual, status = eoptimal(B, k)
    out = {"D": doptimal(B, k), "A": aoptimal(B, k), "E": e_value,
           "E_sdp_primal": e_primal, "E_sdp_dual": e_dual, "E_status": status}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
