"""The thesis's figures of sections 3.2-3.3 that depend on the scene, redrawn from a loaded model
(matplotlib, Agg). Figures 3.2 and 3.3 (Euler against RK4 on a point held on a circle, thesis
3.1.3) do not depend on the scene: runtime/bench/solver_compare.py draws them.

* fig. 3.4: the reduced model's phase portrait p_z(z) (thesis 3.2.12), one closed orbit per energy
  between the bottom of the well at the vertically stable equilibrium and the barrier at the
  unstable one, each integrated with the generated reduced Hamilton equations.
* fig. 3.5: the equilibrium condition (thesis 3.3.2): m g (green) against -mu Phi_2(z) (red), left
  without the hole, right with it; intersections are the equilibria.
* fig. 3.6: the same forces at larger z: gravity (blue), magnetic force with hole (red), without
  hole (green), from just below the lowest equilibrium on, so that every crossing shows.
* fig. 3.7: the critical spin rates against g21 at g31 = 0 (thesis 3.3.16-3.3.23): the exact roots of
  L(l) and the thesis's small-g21 approximations, for the top that hovers at z_c.
* fig. 3.8: the stable launches over spin and tilt: a stability map of the scene's top through the
  scan (runtime/scan), over the spins around its linear interval (or, where it has none, around
  the interval of the top that hovers in the middle of the stable band).

"Without the hole" is the same annulus model with plate_w = 0 (the thin disk, thesis eq. 2.2.11 with
w = 0); plates without a hole parameter draw one panel. No sympy here.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.ui import progress
from levitron.runtime.ui.human import Units, sig, span
from levitron.runtime.ui.plain_text import shown
from levitron.runtime.ui.plotting import band, canvas, in_style, save_figure
from levitron.runtime.physics.routes.ray_algebra import l_cubic


class NotDrawn(Exception):
    """A figure that this scene cannot have, and why (make_figures reports it, writes nothing)."""


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


ZOOM_BELOW = 0.3     # a zoom row when the crossings and the band span less than this share of z


def _features(rep, z_max: float) -> list[float]:
    """The heights a reader looks for in fig. 3.5: the crossings and the stable bands' edges."""
    out = [e.z for e in rep.equilibria if e.z <= z_max]
    for b in rep.stable_bands:
        out += [b.z[0], min(b.z[1], z_max)]
    return out


def _panel_3_5(ax, model, p, rep, z, m, g, mu, u, kz, kf, legend: bool) -> None:
    on = eqm.model_onaxis(model, p)
    force = np.array([-mu * on(float(zz))[2] for zz in z])
    for b in rep.stable_bands:
        band(ax, b.z[0] * kz, b.z[1] * kz,
             f"stable band {u.length_span(b.z[0], b.z[1])} ({span(b.mass[0], b.mass[1], u.mass)})"
             if legend else None)
    ax.plot(z * kz, force * kf, "r-", label=r"magnetic lift $-\mu\Phi_2(z)$" if legend else None)
    ax.axhline(m * g * kf, color="b", label=f"weight m g (m = {u.mass(m)})" if legend else None)
    for e in rep.equilibria:
        if z[0] <= e.z <= z[-1]:
            kind = "stable" if e.vertically_stable else "unstable"
            ax.plot([e.z * kz], [m * g * kf], "ko" if e.vertically_stable else "kx", ms=7,
                    mfc="k" if e.vertically_stable else "none", ls="none",
                    label=f"vertically {kind} equilibrium: {u.length(e.z)}" if legend else None)
    top = 1.15 * max(float(force.max()), m * g)
    if legend:
        ax.set_ylim(max(float(force.min()), -0.5 * top) * kf, top * kf)   # the deep dip near the hole is cut
    else:      # the zoom: the weight's line and the lift around it
        lo, hi = float(force.min()), float(force.max())
        pad = 0.1 * max(hi - lo, 1e-12 * abs(m * g))
        ax.set_ylim((lo - pad) * kf, (hi + pad) * kf)
        ax.set_xlim(z[0] * kz, z[-1] * kz)


@in_style
def figure_3_5(model, path: Path) -> Path:
    """Thesis fig. 3.5: m g against -mu Phi_2(z) (thesis 3.3.2); the equilibria are the crossings,
    named in the legend (so that close roots never collide), the stable band shaded. Where the
    crossings and the band sit in a small part of the heights (less than ZOOM_BELOW of them), a
    second row zooms in on them."""
    P = eqm.params_of(model)
    scale = eqm.scale_of(model)
    m, g, mu = P["m"], P["g"], P["mu"]
    u, kz, lu, kf, fu = _units(model, P)
    variants = _variants(model)
    z = np.linspace(0.02 * scale, 2.0 * scale, 600)
    reps = [eqm.equilibria_of(model, p, bands=True) for _, p in variants]
    zooms = []
    for rep in reps:
        f = _features(rep, z[-1])
        lo, hi = (min(f), max(f)) if f else (0.0, 0.0)
        zooms.append((lo, hi) if f and hi - lo < ZOOM_BELOW * (z[-1] - z[0]) else None)
    rows = 2 if any(zooms) else 1
    fig, axes = canvas(nrows=rows, ncols=len(variants), figsize=(6.4 * len(variants), 5.6 + 3.4 * (rows - 1)),
                             squeeze=False, gridspec_kw={"height_ratios": [5, 3][:rows]})
    for k, ((label, p), rep) in enumerate(zip(variants, reps)):
        ax = axes[0][k]
        _panel_3_5(ax, model, p, rep, z, m, g, mu, u, kz, kf, True)
        ax.set_xlabel(f"height above the plate z ({lu})")
        ax.set_ylabel(f"vertical force ({fu})")
        ax.set_title(f"{model.scene.name}, {label}: equilibria (thesis 3.3.2, fig. 3.5)")
        if rows == 2:
            zax = axes[1][k]
            if zooms[k] is None:
                zax.set_axis_off()
                continue
            lo, hi = zooms[k]
            pad = 0.25 * max(hi - lo, 0.01 * scale)
            zz = np.linspace(max(lo - pad, z[0]), hi + pad, 400)
            _panel_3_5(zax, model, p, rep, zz, m, g, mu, u, kz, kf, False)
            ax.axvspan(zz[0] * kz, zz[-1] * kz, fill=False, ec="0.4", ls=":", lw=0.8)
            zax.set_xlabel(f"zoom: z ({lu})")
            zax.set_ylabel(f"vertical force ({fu})")
    for k in range(len(variants)):      # below the column: never on a curve
        handles, labels = axes[0][k].get_legend_handles_labels()
        axes[rows - 1][k].legend(handles, labels, loc="upper center", ncol=2,
                                 bbox_to_anchor=(0.5, -0.16 if rows == 1 else -0.25))
    fig.tight_layout()
    return save_figure(fig, path)


def _range_36(model, scale: float) -> tuple[float, float]:
    """Thesis fig. 3.6's heights: from 0.8 x the lowest equilibrium (of either variant) to
    3 x the highest (at least 4 plate scales), so that every crossing lies inside."""
    zs = [e.z for _, p in _variants(model) for e in eqm.equilibria_of(model, p).equilibria]
    if not zs:
        return 1.0 * scale, 4.0 * scale
    return 0.8 * min(zs), max(3.0 * max(zs), 4.0 * scale)


@in_style
def figure_3_6(model, path: Path) -> Path:
    """Thesis fig. 3.6: gravity against the magnetic force with and without the hole, over heights
    from below the lowest equilibrium (the crossings, marked) to far above it."""
    P = eqm.params_of(model)
    scale = eqm.scale_of(model)
    m, g, mu = P["m"], P["g"], P["mu"]
    u, kz, lu, kf, fu = _units(model, P)
    z = np.linspace(*_range_36(model, scale), 400)
    fig, ax = canvas(figsize=(6.4, 4.4))
    ax.axhline(m * g * kf, color="b", label=f"gravitational force m g (m = {u.mass(m)})")
    colours = {"without hole": "g"}
    for label, p in _variants(model):
        on = eqm.model_onaxis(model, p)
        ax.plot(z * kz, [-mu * on(float(zz))[2] * kf for zz in z], colours.get(label, "r"),
                label=f"magnetic force, {label}")
        for e in eqm.equilibria_of(model, p).equilibria:
            if z[0] <= e.z <= z[-1]:
                ax.plot([e.z * kz], [m * g * kf], "ko" if e.vertically_stable else "kx", ms=6,
                        mfc="k" if e.vertically_stable else "none")
    ax.set_xlabel(f"height above the plate z ({lu})")
    ax.set_ylabel(f"vertical force ({fu})")
    ax.set_title(f"{model.scene.name}: forces at larger z (thesis fig. 3.6); "
                 "o stable, x unstable crossing", fontsize=9)
    ax.legend()
    fig.tight_layout()
    return save_figure(fig, path)


@in_style
def figure_3_4(model, path: Path, orbits: int = 7) -> Path:
    """Thesis fig. 3.4: the phase portrait p_z(z) of the reduced model (thesis 3.2.12, on the
    invariant set), one closed orbit per energy. The energies run from just above the bottom of
    the well U = m g z + mu Phi_1 at the vertically stable equilibrium z_s up to 95 % of the way to
    the barrier at the unstable equilibrium below it (the separatrix, dashed, from the energy
    alone: p_z = +-sqrt(2 m (E - U(z))); without an unstable equilibrium below z_s, up to 95 % of
    U(z_s / 2) - U(z_s), and no separatrix is drawn: there is none). Each orbit starts at z_s with
    p_z > 0 and is integrated
    over one period and a half with the generated reduced Hamilton equations (DOP853, tol 1e-10);
    the spin (p_psi) does not enter z's motion and is 0."""
    import matplotlib

    from levitron.runtime.integrate import integrate
    P = eqm.params_of(model)
    m, g, mu = P["m"], P["g"], P["mu"]
    u, kz, lu, _, _ = _units(model, P)
    kp, pu = (1e5, "g cm/s") if u.si else (1.0, "scene units")
    on = eqm.model_onaxis(model, model.p)
    rep = eqm.equilibria_of(model)

    def U(z):
        return m * g * z + mu * float(on(float(z))[1])

    stable = rep.stable
    if "reduced" not in model.parts:
        raise NotDrawn("the scene has no reduced model (add \"reduced\" to model.needs)")
    if not stable:
        raise NotDrawn("no vertically stable equilibrium, no closed orbit: "
                       + shown(rep.no_hover_reason(m), u))
    fig, ax = canvas(figsize=(6.4, 5.6))
    zs = stable[0].z
    below = [e.z for e in rep.equilibria if e.z < zs and not e.vertically_stable]
    z_lo = below[-1] if below else 0.5 * zs
    barrier = U(z_lo) - U(zs)
    T0 = 2 * math.pi * math.sqrt(m / stable[0].stiffness)
    part = model.part("reduced")
    colours = matplotlib.colormaps["viridis"](np.linspace(0.05, 0.9, orbits))
    for k, f in enumerate(np.linspace(0.05, 0.95, orbits)):
        E = f * barrier
        x0 = np.array([zs, 0.0, math.sqrt(2 * m * E), 0.0])
        # the period grows towards the separatrix (logarithmically): 1.5 periods of
        # the small oscillation, times the factor of the energy's nearness to it
        t_end = 1.5 * T0 * (1 + math.log(1 / (1 - f)))
        r = integrate(part, x0, t_end, method="dop853", tol=1e-10, n_out=800)
        ax.plot(r.X[:, 0] * kz, r.X[:, 2] * kp, color=colours[k], lw=1.2,
                label=(f"E - U(z_s) = {sig(f, 2)} x " + ("barrier" if below else "(U(z_s / 2) - U(z_s))"))
                if k in (0, orbits - 1) else None)
    if below:          # a separatrix only where there is an unstable equilibrium to pass through
        zz = np.linspace(z_lo, 5 * zs - 4 * z_lo, 1600)
        Ez = np.array([U(v) for v in zz]) - U(zs)
        pz = np.sqrt(np.clip(2 * m * (barrier - Ez), 0, None))
        keep = Ez <= barrier
        for sign in (1, -1):
            ax.plot(zz[keep] * kz, sign * pz[keep] * kp, "k--", lw=0.8,
                    label="separatrix (energy of the unstable equilibrium)" if sign > 0 else None)
    ax.plot([zs * kz], [0], "ko", ms=5, label=f"z_s = {u.length(zs)} (vertically stable)")
    ax.plot([z_lo * kz], [0], "kx", ms=6,
            label=f"{u.length(z_lo)} (unstable)" if below else None)
    ax.set_xlabel(f"height z ({lu})")
    ax.set_ylabel(f"vertical momentum p_z ({pu})")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    ax.set_title(f"{model.scene.name}, {u.top(m)}: phase portrait p_z(z) of the reduced model\n"
                 "(thesis 3.2.12, fig. 3.4), one orbit per energy", fontsize=9)
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


@in_style
def figure_3_7(model, path: Path) -> Path:
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
    fig, ax = canvas(figsize=(6.4, 4.6))
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
    who = (f"for the top that hovers at z_c = {u.length(z_c)}, of mass m(z_c) = {u.mass(m)}"
           if m_c else f"for the scene's top, m = {u.mass(m)}")
    ax.set_title(f"{model.scene.name}: critical spin rates (thesis fig. 3.7)\n{who}", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def figure_3_8(model, path: Path, quick: bool = False) -> Path:
    """Thesis fig. 3.8: stable launches over spin and tilt, a stability map of the scene's own top
    (runtime/scan, one slow period per run; 8 x 6 runs with quick, else 16 x 10). Spins: 0.5 x
    the lower to 1.25 x the upper end of its linear interval (thesis 3.3), or, where it has none,
    of the interval of the top that hovers in the middle of the stable band (the map then shows
    the scene's top falling there). NotDrawn without a full model or a stable band."""
    from levitron.runtime.physics.stability.analysis import stability_of
    from levitron.runtime.scan import stability_map as sc
    from levitron.runtime.scan.physics import slow_period, spins_around
    u = Units.of_scene(model.scene)
    m = model.param("m")
    if "full" not in model.parts:
        raise NotDrawn("the scene has no full model (add \"full\" to model.needs): the map "
                       "simulates the whole top")
    try:
        res = stability_of(model)
        iv, z_s = res.spin_interval, res.z_s
    except UserError as exc:           # no hover height at all: nothing to launch from
        raise NotDrawn(f"{u.top(m)} cannot hover: {shown(str(exc), u)}") from None
    if z_s is None:
        raise NotDrawn(f"{u.top(m)} has no vertically stable height to launch from: "
                       + shown(res.reason, u))
    title = f"{model.scene.name}, {u.top(m)}: launches over spin and tilt (thesis fig. 3.8)"
    z_ref, m_ref = z_s, m
    if iv is None:
        band_ = eqm.equilibria_of(model, bands=True).stable_band
        if band_ is None:
            raise NotDrawn("the plate has no stable band: no spin to scan around")
        mid = 0.5 * (band_.z[0] + band_.z[1])
        other = stability_of(model, height=mid)
        if other.spin_interval is None:
            raise NotDrawn("no spin interval in the middle of the stable band to scan around")
        iv, z_ref, m_ref = other.spin_interval, mid, other.mass
        title += (f"\nno spin stabilises it; spins around the interval of {u.top(m_ref)} "
                  f"(mid-band, {u.length(mid)})")
    n_spin, n_tilt = (8, 6) if quick else (16, 10)
    spins = spins_around(iv, n_spin)
    tilts = np.linspace(0.005, 0.1, n_tilt)
    # one slow period of the scanned top itself (at its own hover height where it has one)
    T = slow_period(model, m, z_s, math.sqrt(iv[0] * iv[1])) if z_s else \
        slow_period(model, m_ref, z_ref, math.sqrt(iv[0] * iv[1]))
    result = sc.scan(model, spins, "tilt", tilts, t_end=T, quiet=True)
    result.plot(path, title)
    return Path(path)


SCENE_FIGURES = (("3.4", "fig3_4_phase_portrait"), ("3.5", "fig3_5_equilibrium"),
                 ("3.6", "fig3_6_forces"), ("3.7", "fig3_7_critical_spins"),
                 ("3.8", "fig3_8_stability_map"))


def make_figures(outdir, model, quick: bool = False) -> tuple[list[Path], dict[str, str]]:
    """Draw the scene's thesis figures 3.4-3.8 into outdir as <scene>_fig3_N_*.png; returns the
    paths written and {figure: why} of those this scene cannot have (NotDrawn: 3.4 without a
    vertically stable height, 3.8 without a full model or a stable band); the scan's workers load
    the same model from model.ref."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    name = model.scene.name
    draw = {"3.4": figure_3_4, "3.5": figure_3_5, "3.6": figure_3_6, "3.7": figure_3_7,
            "3.8": lambda mdl, path: figure_3_8(mdl, path, quick)}
    written, not_drawn = [], {}
    for number, stem in progress.track(SCENE_FIGURES, f"figures of {name}", stage=lambda j: f"fig. {j[0]}"):
        try:
            written.append(Path(draw[number](model, outdir / f"{name}_{stem}.png")))
        except NotDrawn as why:
            not_drawn[number] = str(why)
    return written, not_drawn
