#!/usr/bin/env python3
"""Natural frequencies of the pinned pendulum of the NGSolve tutorial "FEM Pendulum: Basics",
computed independently of pendulum-fem with NGSolve/Netgen and SciPy: the reference of
`tests/data/ngsolve_modes.json` (checked by `tests/modes.rs`).

Model: the tutorial's geometry meshed by Netgen (the CSG of `pendulum_basics.py`), curved
elements and H1 vector elements of order p, the linearisation of the tutorial's Neo-Hookean law
at F = I, i.e. linear elasticity with the plane-stress Lamé constants
λ* = Eν/(1 − ν²), μ = E/(2(1 + ν)), thickness t, density ρ:

    K: ∫ t (2μ ε(u):ε(w) + λ* div u div w) dA,     M: ∫ ρ t u·w dA,
    hinge: the mean displacement of the "rotation" edge vanishes (two NumberSpace multipliers).

The generalised eigenproblem of the saddle-point pencil

    [K  Cᵀ] [φ]     2 [M  0] [φ]
    [C  0 ] [μ] = ω   [0  0] [μ]

is solved by SciPy's `eigsh` (ARPACK, shift-invert mode about σ = −1 rad²/s², a sparse LU of
the saddle-point matrix K − σM with its multipliers). The first eigenvalue is the rigid rotation
about the pivot (0 Hz); the others are elastic. The mesh is refined uniformly (`--refine R`
halves every element R times, curving again) and the order raised (`--orders`) until the
frequencies agree; the finest result is the reference.

    ~/ngs-venv/bin/python scripts/ngsolve/pendulum_modes.py --orders 2,3,4 --refine 0,1,2 \\
        --out tests/data/ngsolve_modes.json
"""
import argparse
import json
import os
import sys
import time


def options():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name, default in [("E", 2.1e11), ("nu", 0.3), ("rho", 7800.0), ("maxh", 0.03), ("thickness", 0.01)]:
        p.add_argument("--" + name, type=float, default=default)
    p.add_argument("--n", type=int, default=12, help="eigenpairs (the rigid mode included)")
    p.add_argument("--orders", default="2,3,4", help="polynomial orders, comma-separated")
    p.add_argument("--refine", default="0,1,2", help="uniform refinements, comma-separated")
    p.add_argument("--out", default=None, help="JSON file for the table and the reference")
    return p.parse_args()


def frequencies(ng, ngs, a, order, refinements):
    import numpy as np
    import scipy.sparse as sp
    from scipy.sparse.linalg import eigsh, splu, LinearOperator

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from pendulum_basics import pendulum_geometry

    ngmesh = ng.OCCGeometry(pendulum_geometry(ng), dim=2).GenerateMesh(maxh=a.maxh)
    for _ in range(refinements):
        ngmesh.Refine()
    mesh = ngs.Mesh(ngmesh)
    mesh.Curve(order)
    lam = a.E * a.nu / (1 - a.nu ** 2)
    mu = a.E / (2 * (1 + a.nu))
    t, rho = a.thickness, a.rho
    V = ngs.VectorH1(mesh, order=order)
    Q = ngs.NumberSpace(mesh, definedon=mesh.Boundaries("rotation"))
    X = V * Q ** 2
    (u, lag), (w, mult) = X.TnT()

    def eps(v):
        return 0.5 * (ngs.Grad(v) + ngs.Grad(v).trans)

    k = ngs.BilinearForm(X)
    k += t * (2 * mu * ngs.InnerProduct(eps(u), eps(w)) + lam * ngs.Trace(eps(u)) * ngs.Trace(eps(w))) * ngs.dx
    k += (ngs.InnerProduct(u, mult) + ngs.InnerProduct(w, lag)) * ngs.ds("rotation")
    m = ngs.BilinearForm(X)
    m += rho * t * ngs.InnerProduct(u, w) * ngs.dx
    k.Assemble()
    m.Assemble()

    def scipy_matrix(form):
        rows, cols, vals = form.mat.COO()
        return sp.csc_matrix((vals, (rows, cols)), shape=(X.ndof, X.ndof))

    K, M = scipy_matrix(k), scipy_matrix(m)
    shift = -1.0
    lu = splu((K - shift * M).tocsc())
    op = LinearOperator(K.shape, matvec=lu.solve, dtype=float)
    vals = eigsh(K, k=a.n, M=M, sigma=shift, which="LM", OPinv=op, tol=1e-12, return_eigenvectors=False)
    vals = np.sort(vals)
    return {
        "order": order,
        "refinements": refinements,
        "elements": mesh.ne,
        "unknowns": X.ndof,
        "omega2": [float(v) for v in vals],
        "hz": [float(np.sqrt(max(v, 0.0)) / (2 * np.pi)) for v in vals],
    }


def with_reference(result, rows):
    """Puts the finest row into result["reference"] (its first eigenvalue the rigid rotation, the
    rest the elastic modes) with the relative change of every frequency from the previous
    refinement of the same order, an estimate of its remaining discretisation error."""
    finest = max(rows, key=lambda r: (r["order"], r["refinements"]))
    previous = [r for r in rows if r["order"] == finest["order"] and r["refinements"] == finest["refinements"] - 1]
    ref = {"order": finest["order"], "refinements": finest["refinements"], "unknowns": finest["unknowns"],
           "rigid_hz": finest["hz"][0], "elastic_hz": finest["hz"][1:], "elastic_omega2": finest["omega2"][1:]}
    if previous:
        ref["relative_change_from_previous_refinement"] = [
            abs(a - b) / a for a, b in zip(finest["hz"][1:], previous[0]["hz"][1:])]
    result["reference"] = ref
    result["table"] = rows
    return result


def main():
    a = options()
    import netgen.occ as ng
    import ngsolve as ngs

    rows = []
    for order in [int(s) for s in a.orders.split(",")]:
        for r in [int(s) for s in a.refine.split(",")]:
            start = time.perf_counter()
            row = frequencies(ng, ngs, a, order, r)
            row["seconds"] = time.perf_counter() - start
            rows.append(row)
            print(json.dumps({k: (v if k != "omega2" else None) for k, v in row.items() if k != "omega2"}), flush=True)
    result = {
        "description": "Natural frequencies of the pinned pendulum (NGSolve tutorial 'FEM Pendulum: Basics'), "
        "linear elasticity (plane stress) about the undeformed state, hinge = mean displacement of the "
        "'rotation' edge; NGSolve " + ngs.__version__ + " assembly, SciPy eigsh shift-invert (sigma = -1 rad^2/s^2) "
        "on the saddle-point pencil. Made by scripts/ngsolve/pendulum_modes.py " + " ".join(sys.argv[1:]),
        "material": {"E": a.E, "nu": a.nu, "rho": a.rho, "thickness": a.thickness, "plane": "stress"},
        "maxh": a.maxh,
    }
    with_reference(result, rows)
    text = json.dumps(result, indent=1)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text + "\n")
    for row in rows:
        print(row["order"], row["refinements"], row["unknowns"], " ".join(f"{h:.4f}" for h in row["hz"]))


if __name__ == "__main__":
    main()
