"""Conservation in the full model along integrated trajectories, in both coordinate sets.

Energy (thesis eq. 2.3.9), L.n (= p_psi in Euler angles, = -p_zeta in Dullin's angles, computed here
from the velocities, not read off the momentum) and the z-component of the total angular momentum
J_z = m (x ydot - y xdot) + (R I omega)_z hold to the integrator's tolerance.
"""
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from levitron.derive.mechanics import hamiltonian_system
from levitron.derive.symbols import A, C, m

RTOL = 1e-12


def stable_height(model):
    mass, g, mu = model.param("m"), model.param("g"), model.param("mu")
    f = lambda z: mass * g + mu * model.onaxis(z)[2]  # noqa: E731  (thesis eq. 3.3.2)
    zs = np.linspace(0.02, 0.4, 400)
    vals = [f(z) for z in zs]
    roots = [brentq(f, zs[i], zs[i + 1], xtol=1e-14) for i in range(len(zs) - 1)
             if np.sign(vals[i]) != np.sign(vals[i + 1])]
    return max(roots)


def invariants(coords, params):
    sysm = hamiltonian_system(coords, 2)
    rot = sysm.rotation
    I = sp.diag(A, A, C)
    L_space = rot.R_bs * I * rot.omega
    x, y = sysm.q[0], sysm.q[1]
    xd, yd = sysm.qdot[0], sysm.qdot[1]
    Jz = m * (x * yd - y * xd) + L_space[2]
    Ln = (I * rot.omega)[2]                       # body frame: n = e_3
    sub = {A: params["A"], C: params["C"], m: params["m"]}
    args = list(sysm.q) + list(sysm.qdot)
    fJ = sp.lambdify(args, Jz.xreplace(sub))
    fL = sp.lambdify(args, Ln.xreplace(sub))
    fp = sp.lambdify(args, list(sysm.momenta.xreplace(sub)))
    return fJ, fL, fp


@pytest.mark.parametrize("coords", ["tait-bryan", "euler-zxz"])
def test_conservation_full_model(derived_model, coords):
    # A top of 51.5 g hovers in the thesis plate's stable band; 1000 rad/s is inside its spin
    # interval, so the top precesses and bounces rather than flipping over within the run.
    model = derived_model("thesis", f"model.coordinates=\"{coords}\"", "top.mass=0.0515")
    part = model.part("full")
    params = dict(zip(part.params, part.p))
    fJ, fL, fp = invariants(coords, params)
    zs = stable_height(model)
    tilt, spin = 0.05, 1000.0
    q = [0.002, -0.001, zs, 0.0, tilt, 0.0]     # theta (Euler) or vartheta (Dullin) = tilt
    qd = [0.0, 0.0, 0.0, 0.0, 0.0, spin]
    x0 = np.array(q + list(fp(*q, *qd)), dtype=float)
    sol = solve_ivp(lambda t, x: part.rhs(x), (0.0, 0.5), x0, method="DOP853", rtol=RTOL,
                    atol=1e-14, dense_output=False, t_eval=np.linspace(0, 0.5, 6))
    assert sol.success
    X = sol.y.T
    E = np.array([part.energy(x) for x in X])
    qdots = np.array([part.rhs(x)[:6] for x in X])
    J = np.array([fJ(*x[:6], *v) for x, v in zip(X, qdots)])
    Ln = np.array([fL(*x[:6], *v) for x, v in zip(X, qdots)])
    # energy: relative to the size of its terms (kinetic spin energy dominates)
    e_scale = abs(E[0]) + 0.5 * params["C"] * spin**2
    assert np.max(np.abs(E - E[0])) / e_scale < 1e-9
    assert np.max(np.abs(Ln - Ln[0])) / abs(Ln[0]) < 1e-9
    assert np.max(np.abs(J - J[0])) / abs(Ln[0]) < 1e-9
    spin_momentum = X[:, 11]
    sign = 1.0 if coords == "euler-zxz" else -1.0           # L.n = p_psi, or -p_zeta
    assert np.allclose(Ln, sign * spin_momentum, rtol=1e-10, atol=0)
    # the motion is not trivial: the top moves and precesses
    assert np.ptp(X[:, 0]) > 1e-5 and np.ptp(X[:, 3]) + np.ptp(X[:, 4]) > 1e-3
