#!/usr/bin/env python3
"""The pendulum of the NGSolve tutorial "FEM Pendulum: Basics", run headless in NGSolve, for
side-by-side comparisons with pendulum-fem (`pendulum-fem bench run --ngsolve PYTHON`).

The model is the tutorial's (its own geometry, Netgen mesh, P2 Neo-Hookean plane stress with the
hinge as two multipliers, Newmark average acceleration, NewtonMinimization); the options only
choose what is measured and how NGSolve is tuned:

    python3 -m venv ~/ngs-venv && ~/ngs-venv/bin/pip install ngsolve scipy
    ~/ngs-venv/bin/python scripts/ngsolve/pendulum_basics.py --post 1 --energy 0      # as written
    ~/ngs-venv/bin/python scripts/ngsolve/pendulum_basics.py --post 0 --energy 0 \\
        --compile 1 --threads 2                                                    # tuned

--post 1 computes the von Mises field every step as the tutorial does; --energy 1 the energies;
--compile 1 compiles the energy (Variation(...).Compile()) and runs the loop under a TaskManager;
--thick 1 puts the thickness into the strain energy (the tutorial leaves it out); --a0 1 starts
with the rigid-body angular acceleration instead of zero. Prints one JSON line with the counts and
timings and, with --out FILE, writes θ(t) and the Newton iterations of every step there.
"""
import argparse
import json
import time


def options():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name, default in [("E", 2.1e11), ("nu", 0.3), ("rho", 7800.0), ("theta0", 20.0), ("omega0", 0.0),
                          ("dt", 0.01), ("tend", 1.0), ("maxh", 0.03), ("g", 9.81), ("thickness", 0.01)]:
        p.add_argument("--" + name, type=float, default=default)
    for name, default in [("order", 2), ("post", 1), ("energy", 1), ("thick", 0), ("a0", 0), ("threads", 1),
                          ("compile", 0)]:
        p.add_argument("--" + name, type=int, default=default)
    p.add_argument("--out", default=None)
    return p.parse_args()


def pendulum_geometry(ng, r_rod=0.015, r_head=0.06, r_hole=0.03, l_center=0.24):
    """The tutorial's CSG: a rod with a ring-shaped head, hinge edge 'rotation' at y = 0."""
    rod = ng.MoveTo(-r_rod, 0).Rectangle(2 * r_rod, l_center).Face()
    rod.edges.Min(ng.Y).name = "rotation"
    rod.edges.Min(ng.Y).maxh = r_rod / 10
    rod.faces.maxh = r_rod / 2
    disc = ng.Circle((0, l_center), r_head).Face()
    disc.edges.name = "contact_head"
    disc.edges.maxh = r_head / 20
    disc.faces.maxh = r_head / 5
    hole = ng.Circle((0, l_center), r_hole).Face()
    hole.edges.maxh = r_head / 20
    shape = (disc - hole) + rod - hole
    shape = shape.Rotate(ng.Axis((0, 0, 0), (0, 0, 1)), 180)  # hanging down
    shape.name = "pendulum"
    shape.vertices[0].maxh = r_rod / 20
    shape.vertices[1].maxh = r_rod / 20
    return shape


def main():
    a = options()
    started = time.perf_counter()
    import numpy as np
    import netgen.occ as ng
    import ngsolve as ngs
    from ngsolve.solvers import NewtonMinimization

    ngs.SetNumThreads(a.threads)
    mesh_start = time.perf_counter()
    mesh = ngs.Mesh(ng.OCCGeometry(pendulum_geometry(ng), dim=2).GenerateMesh(maxh=a.maxh))
    mesh.Curve(a.order)
    t_mesh = time.perf_counter() - mesh_start

    # plane-stress Lamé constants, the tutorial's energy (ψ(I) ≠ 0 there; forces are the same)
    lam = a.E * a.nu / (1 - a.nu ** 2)
    mu = a.E / (2 * (1 + a.nu))
    t, rho = a.thickness, a.rho

    V = ngs.VectorH1(mesh, order=a.order)
    Q = ngs.NumberSpace(mesh, definedon=mesh.Boundaries("rotation"))
    X = V * Q ** 2
    (u, lag), (w, mult) = X.TnT()
    state = {k: ngs.GridFunction(X) for k in ("u", "v", "a", "u0", "v0", "a0")}
    cmp = {k: g.components[0] for k, g in state.items()}

    F = ngs.Id(2) + ngs.Grad(u)
    C = F.trans * F
    energy_density = mu / 2 * (ngs.Trace(C - ngs.Id(2)) + 2 * mu / lam * ngs.Det(C) ** (-lam / (2 * mu)) - 1)
    if a.thick:
        energy_density = t * energy_density
    elastic = ngs.Variation(energy_density * ngs.dx("pendulum"))
    if a.compile:
        elastic = elastic.Compile()

    tau = ngs.Parameter(a.dt)
    v_new = 2 / tau * (u - cmp["u0"]) - cmp["v0"]
    a_new = 2 / tau * (v_new - cmp["v0"]) - cmp["a0"]
    form = ngs.BilinearForm(X)
    form += elastic
    form += (ngs.InnerProduct(u, mult) + ngs.InnerProduct(w, lag)) * ngs.ds("rotation")
    form += rho * t * ngs.InnerProduct(a_new, w) * ngs.dx("pendulum")
    form += -rho * t * ngs.InnerProduct(ngs.CF((0, -a.g)), w) * ngs.dx("pendulum")

    # initial state: a rigid rotation by θ₀ about the pivot, ω₀ e_z × x, optionally α₀ e_z × x − ω₀² x
    r = ngs.CF((ngs.x, ngs.y))
    th = np.deg2rad(a.theta0)
    c, s = np.cos(th), np.sin(th)
    xr = ngs.CF((c * r[0] - s * r[1], s * r[0] + c * r[1]))
    area = ngs.Integrate(1, mesh)
    polar = ngs.Integrate(ngs.InnerProduct(r, r), mesh)
    alpha0 = 0.0
    if a.a0:
        moment_arm = ngs.Integrate(xr[0], mesh)  # ∫ x dA in the rotated position
        alpha0 = -a.g * moment_arm / polar
    for key in ("u", "u0"):
        cmp[key].Set(xr - r, definedon=mesh.Materials("pendulum"))
    for key in ("v", "v0"):
        cmp[key].Set(ngs.CF((-a.omega0 * xr[1], a.omega0 * xr[0])), definedon=mesh.Materials("pendulum"))
    for key in ("a", "a0"):
        cmp[key].Set(ngs.CF((-alpha0 * xr[1] - a.omega0 ** 2 * xr[0], alpha0 * xr[0] - a.omega0 ** 2 * xr[1])),
                     definedon=mesh.Materials("pendulum"))

    def proxy_angle():
        ud = cmp["u"]
        sn = ngs.Integrate(r[0] * ud[1] - r[1] * ud[0], mesh) / polar
        cs = ngs.Integrate(ngs.InnerProduct(r, r + ud), mesh) / polar
        return float(np.arctan2(sn, cs))

    sigma_space = ngs.H1(mesh, order=a.order, definedon=mesh.Materials("pendulum"))
    von_mises = ngs.GridFunction(sigma_space)

    def post():
        Fu = ngs.Id(2) + ngs.Grad(cmp["u"])
        Cu = Fu.trans * Fu
        J = ngs.Det(Fu)
        P = mu * (Fu - J ** (-lam / mu) * ngs.Inv(Fu).trans)
        sig = 1 / J * P * Fu.trans
        von_mises.Set(ngs.sqrt(sig[0, 0] ** 2 + sig[1, 1] ** 2 - sig[0, 0] * sig[1, 1] + 3 * sig[0, 1] ** 2))
        return Cu

    def energies():
        kin = ngs.Integrate(0.5 * rho * t * ngs.InnerProduct(cmp["v"], cmp["v"]), mesh)
        grav = ngs.Integrate(rho * t * a.g * (ngs.y + cmp["u"][1]), mesh)
        return kin, grav

    steps = int(round(a.tend / a.dt))
    thetas, iterations, energy_rows = [proxy_angle()], [], []
    loop_start = time.perf_counter()

    def loop():
        for _ in range(steps):
            for key in ("u", "v", "a"):
                state[key + "0"].vec.data = state[key].vec
            result = NewtonMinimization(form, state["u"], printing=False, inverse="sparsecholesky", maxerr=1e-6, maxit=20)
            iterations.append(int(result[1]))
            # Newmark updates of velocity and acceleration
            state["v"].vec.data = 2 / a.dt * (state["u"].vec - state["u0"].vec) - state["v0"].vec
            state["a"].vec.data = 2 / a.dt * (state["v"].vec - state["v0"].vec) - state["a0"].vec
            thetas.append(proxy_angle())
            if a.post:
                post()
            if a.energy:
                energy_rows.append(energies())

    if a.compile:
        with ngs.TaskManager():
            loop()
    else:
        loop()
    t_steps = time.perf_counter() - loop_start
    summary = {
        "elements": mesh.ne,
        "vertices": mesh.nv,
        "unknowns": X.ndof,
        "area": area,
        "newton_iterations": sum(iterations),
        "t_mesh": t_mesh,
        "t_steps": t_steps,
        "t_total": time.perf_counter() - started,
        "theta_end_deg": float(np.rad2deg(thetas[-1])),
    }
    print(json.dumps(summary))
    if a.out:
        with open(a.out, "w") as f:
            f.write("t_s,theta_rad,newton_iterations\n")
            for k, th_k in enumerate(thetas):
                f.write(f"{k * a.dt:.10g},{th_k:.17g},{iterations[k - 1] if k else 0}\n")


if __name__ == "__main__":
    main()
