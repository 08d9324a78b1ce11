"""The thesis's figures of section 3.3, redrawn from a loaded model (matplotlib, Agg).

* fig. 3.5: the equilibrium condition (thesis 3.3.2): m g (green) against -mu Phi_2(z) (red), left
  without the hole, right with it; intersections are the equilibria.
* fig. 3.6: the same forces at larger z: gravity (blue), magnetic force with hole (red), without
  hole (green).
* fig. 3.7: the critical spin rates against g21 at g31 = 0 (thesis 3.3.16-3.3.23): the exact roots of
  L(l) and the thesis's small-g21 approximations, for the top that hovers at z_c.

"Without the hole" is the same annulus model with plate_w = 0 (the thin disk, thesis eq. 2.2.11 with
w = 0); plates without a hole parameter draw one panel. No sympy here.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from runtime.physics import equilibrium as eqm
from runtime.ui import progress
from runtime.ui.human import Units, sig, span
from runtime.ui.plotting import band, pyplot, save_figure, style
from runtime.physics.ray_algebra import l_cubic


def _variants(model) -> list[tuple[str, np.ndarray]]:
    names = model.param_names
    out = []
    if "plate_w" in names and model.p[names.index("plate_w")] > 0:
        p0 = model.p.copy()
        p0[names.index("plate_w")] = 0.0
        out.append(("without hole", p0))
        w = model.p[names.index("plate_w")]
        out.append((f"with hole (w = {Units.of_scene(model.scene).length(w)})", model.p.copy()))
    else:
        out.append(("plate", model.p.copy()))
    return out


def _units(model, P: dict):
    """(Units, length factor and unit, force factor and unit) for the axes: cm and mN in an SI
    scene, the scene's own units otherwise (runtime/ui/human.py's rule)."""
    u = Units.of_scene(model.scene)
    if u.si:
        return u, 100.0, "cm", 1e3, "mN"
    return u, 1.0, "scene units", 1.0, "scene units"


def figure_3_5(model, path: Path) -> Path:
    """Thesis fig. 3.5: m g against -mu Phi_2(z) (thesis 3.3.2); the equilibria are the crossings,
    named in the legend (so that close roots never collide), the stable band shaded."""
    plt = pyplot()
    style()
    P = eqm.params_of(model)
    scale = eqm.scale_of(model)
    m, g, mu = P["m"], P["g"], P["mu"]
    u, kz, lu, kf, fu = _units(model, P)
    variants = _variants(model)
    fig, axes = plt.subplots(1, len(variants), figsize=(6.4 * len(variants), 5.6), squeeze=False)
    z = np.linspace(0.02 * scale, 2.0 * scale, 600)
    for ax, (label, p) in zip(axes[0], variants):
        on = eqm.model_onaxis(model, p)
        rep = eqm.equilibria_of(model, p, bands=True)
        force = np.array([-mu * on(float(zz))[2] for zz in z])
        for b in rep.stable_bands:
            band(ax, b.z[0] * kz, b.z[1] * kz,
                 f"stable band {span(b.z[0], b.z[1], u.cm)} ({span(b.mass[0], b.mass[1], u.mass)})")
        ax.plot(z * kz, force * kf, "r-", label=r"magnetic lift $-\mu\Phi_2(z)$")
        ax.axhline(m * g * kf, color="b", label=f"weight m g (m = {u.mass(m)})")
        for e in rep.equilibria:
            if e.z <= z[-1]:
                kind = "stable" if e.vertically_stable else "unstable"
                ax.plot([e.z * kz], [m * g * kf], "ko" if e.vertically_stable else "kx", ms=7,
                        mfc="k" if e.vertically_stable else "none", ls="none",
                        label=f"vertically {kind} equilibrium: {u.length(e.z)}")
        top = 1.15 * max(float(force.max()), m * g)
        ax.set_ylim(max(float(force.min()), -0.5 * top) * kf, top * kf)   # the deep dip near the hole is cut
        ax.set_xlabel(f"height above the plate z ({lu})")
        ax.set_ylabel(f"vertical force ({fu})")
        ax.set_title(f"{model.scene.name}, {label}: equilibria (thesis 3.3.2, fig. 3.5)")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)   # below: never on a curve
    fig.tight_layout()
    return save_figure(fig, path)


def figure_3_6(model, path: Path) -> Path:
    plt = pyplot()

    P = eqm.params_of(model)
    scale = eqm.scale_of(model)
    m, g, mu = P["m"], P["g"], P["mu"]
    u, kz, lu, kf, fu = _units(model, P)
    style()
    z = np.linspace(1.0 * scale, 4.0 * scale, 400)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.axhline(m * g * kf, color="b", label=f"gravitational force m g (m = {u.mass(m)})")
    colours = {"without hole": "g"}
    for label, p in _variants(model):
        on = eqm.model_onaxis(model, p)
        ax.plot(z * kz, [-mu * on(float(zz))[2] * kf for zz in z], colours.get(label, "r"),
                label=f"magnetic force, {label}")
    ax.set_xlabel(f"height above the plate z ({lu})")
    ax.set_ylabel(f"vertical force ({fu})")
    ax.set_title(f"{model.scene.name}: forces at larger z (thesis fig. 3.6)")
    ax.legend()
    fig.tight_layout()
    return save_figure(fig, path)


def critical_spins_g31_zero(g21: np.ndarray, g: float, A: float, C: float, m: float) -> np.ndarray:
    """Exact critical rates at g31 = 0: roots l of L(l) (thesis 3.3.16, corrected) mapped by
    sigma^2 = g / (2 rho^2 l g21 alpha) (3.3.21). Returns (len(g21), 2) [lower, upper], NaN where
    g21^2 > 1/12 (no real roots, 3.3.15)."""
    rho, alpha = C / A, math.sqrt(A / m)
    out = np.full((len(g21), 2), np.nan)
    for i, x in enumerate(g21):
        a = l_cubic(x, 0.0)          # a0 + a1 l + a2 l^2 + a3 l^3, a0 = 0 at g31 = 0
        roots = np.roots(a[::-1][:-1])      # divide by l
        roots = np.sort(roots[np.abs(roots.imag) <= 1e-9 * np.abs(roots)].real)
        roots = roots[roots > 0]
        if len(roots) == 2:
            out[i] = np.sqrt(g / (2 * rho ** 2 * roots[::-1] * x * alpha))
    return out


def figure_3_7(model, path: Path) -> Path:
    plt = pyplot()

    P = eqm.params_of(model)
    g, A, C, mu = P["g"], P["A"], P["C"], P["mu"]
    scale = eqm.scale_of(model)
    on = eqm.model_onaxis(model, model.p)
    z_c, m_c = eqm.critical_height(on, g, mu, scale)
    m = m_c if m_c else P["m"]
    rho, alpha = C / A, math.sqrt(A / m)
    x = np.linspace(1e-3, 1 / math.sqrt(12) * (1 - 1e-9), 400)
    exact = critical_spins_g31_zero(x, g, A, C, m)
    s1 = np.sqrt(g / (2 * rho ** 2 * 0.25 * x * alpha))                 # l1 ~ 1/4 (3.3.17)
    s2 = np.sqrt(g / (2 * rho ** 2 * (27 / 4) * x ** 2 * x * alpha))    # l2 ~ 27 g21^2/4 (3.3.18)
    u = Units.of_scene(model.scene)
    hz = 1 / (2 * math.pi) if u.si else 1.0
    rate_unit = "Hz" if u.si else "rad per time unit"
    style()
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    ax.semilogy(x, exact[:, 0] * hz, "b-", label=r"$\sigma_1$ exact (roots of $L$)")
    ax.semilogy(x, exact[:, 1] * hz, "r-", label=r"$\sigma_2$ exact")
    ax.semilogy(x, s1 * hz, "b--", label=r"$\sigma_1$, $l_1 \approx 1/4$ (3.3.22)")
    ax.semilogy(x, s2 * hz, "r--", label=r"$\sigma_2$, $l_2 \approx 27 g_{21}^2/4$ (3.3.23)")
    if z_c is not None:
        ph = on(z_c)
        g21c = -alpha * ph[2] / (2 * ph[1])
        ax.axvline(g21c, color="k", lw=0.8, ls=":", label=f"this plate at z_c: g21 = {sig(g21c, 3)} (dimensionless)")
    ax.set_xlabel(r"$g_{21}$ (dimensionless, thesis 3.3.13; $g_{31} = 0$)")
    ax.set_ylabel(f"critical spin rate ({rate_unit})")
    ax.set_title(f"{model.scene.name}: critical spin rates (thesis fig. 3.7), m = {u.mass(m)}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def make_figures(outdir, model) -> list[Path]:
    """Draw thesis figures 3.5, 3.6 and 3.7 for the model's scene into outdir; returns the paths."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    name = model.scene.name
    jobs = [(figure_3_5, "fig3_5_equilibrium"), (figure_3_6, "fig3_6_forces"),
            (figure_3_7, "fig3_7_critical_spins")]
    return [draw(model, outdir / f"{name}_{stem}.png") for draw, stem in progress.track(jobs, "figures")]
