"""The words of a Simulation (runtime/simulate/simulation.py): its plain view, line by line, from
its keys (`details`, the JSON's), in the scene's display units: what `levitron simulate` prints and
what the answer's message, repr and notebook table say.
"""
from __future__ import annotations

from levitron.runtime.integrate.verdict import UP, stopped_early
from levitron.runtime.ui.human import Units, duration, sig
from levitron.runtime.ui.plain_text import shown
from levitron.scene.plates.symmetry import symmetry


def flight_line(r: dict, u: Units) -> list[str]:
    """A flight in air as a person says it: "floats 1 min 57 s; falls at 457 rad/s, 0.8 s after the
    spin crosses the linear limit" (runtime/physics/apparatus/friction.py)."""
    fl = r["flight"]
    iv = fl["spin_interval"]
    if iv is None:
        limits = "no spin interval of linear stability at this height: no spin holds the top"
    else:
        limits = f"linear limits {u.rate_span(iv[0], iv[1])}"
    pred = (f"adiabatic prediction {u.time(fl['t_cross'])} (tau ln(omega_0 / sigma_lo))"
            if fl["t_cross"] else "")
    above = ""
    if fl["launched_above"]:
        above = (f"launched above the upper limit: the spin decays into the interval after "
                 f"{u.time(fl['t_enter'])}; "
                 + ("the top fell before that" if fl["fell_before_interval"] else "the top survived that"))
    if fl["fell"]:
        after = fl["after_cross"]
        when = "" if after is None or fl["fell_before_interval"] else (
            f", {u.time(abs(after))} {'after' if after >= 0 else 'before'} the spin crosses the lower limit")
        head = f"floats {u.time(fl['flight_time'])}; falls at {u.rate(fl['fall_spin'])}{when}"
    elif stopped_early(r["status"]):     # no verdict: neither "still floating" nor a fall
        head = (f"no verdict: the run stopped early ({r['status']}) after {u.time(r['t_survived'])} "
                f"of {u.time(r['t_end'])}, spin then {u.rate(fl['spin_final'])}")
    elif past_its_window(r):             # up at the end, but its spin left the window (verdict.py past_window)
        head = (f"no verdict: up after {u.time(r['t_survived'])} (the whole run), but its spin "
                f"{u.rate(fl['spin_final'])} is past the stable window")
    else:
        head = (f"still floating after {u.time(r['t_survived'])} (the whole run), spin now "
                f"{u.rate(fl['spin_final'])}")
    taus = ", ".join(f"{name} {u.time(v)}" for name, v in fl["decay_times"].items() if v)
    return [line for line in (head, f"{limits}; {pred}" if pred else limits, above,
                              f"air friction: decay times {taus}") if line]


def linear_line(r: dict, u: Units) -> str:
    """What linear theory says of this spin (runtime/simulate/start.py linear_context): inside the
    stable interval, or outside it with the e-folding time of a tilt, so that a run shorter than a
    few of them is not read as a verdict."""
    lin = r.get("linear")
    if not lin:
        return ""
    spin, iv = u.value(r["spin"]["rad_s"], "rad/s"), lin["spin_interval"]
    if lin.get("refused"):
        return f"linear theory: none ({lin['refused'].split(': ')[0]})"
    if iv is None:
        return "linear theory: no spin holds this top at its hover height (`«levitron=stability»` says why)"
    span = u.rate_span(*iv).split(" (")[0]
    if lin["inside"]:
        return f"linear theory: {spin} lies inside the stable interval {span} (thesis 3.3.9-3.3.16)"
    side = "below" if r["spin"]["rad_s"] < iv[0] else "above"
    te = lin["e_folding_time"]
    grow = ("" if te is None else f": a tilt grows by e every {u.time(te)} "
            f"({sig(r['t_end'] / te, 2)} e-foldings in this run)")
    return f"linear theory: {spin} lies {side} the stable interval {span}{grow}"


def _not_conserved(name: str, scene) -> str:
    """" (not conserved: ...)" for L_z over a plate without axial symmetry (scene/plates/symmetry.py)."""
    if name != "L_z" or scene is None:
        return ""
    sym = symmetry(scene.data["plate"], scene.params)
    return "" if "L_z" in sym.conserved else f" (not conserved by a plate of {sym.name} symmetry)"


def past_its_window(r: dict) -> bool:
    """A run that reached t_end with its spin below the window (runtime/integrate/verdict.py
    past_window): no verdict, not "untested" (a launch on the invariant set, which tests nothing)."""
    on_invariant_set = r.get("part") == "reduced" or (r["tilt"] == 0 and r["offset"] == 0)
    return r["levitating"] is None and r["status"] == UP and not on_invariant_set


def verdict(r: dict) -> str:
    """"yes", "no (fell: ...)", "untested: ..." or "no verdict: ...": does the top stay up."""
    if r["levitating"] is None:
        word = ("no verdict" if stopped_early(r["status"]) else "no verdict (past its stable window)"
                if past_its_window(r) else "untested")
        return f"{word}: {r['untested']}"
    return "yes" if r["levitating"] else f"no ({r['status']}: {r['message']})"


def summary(r: dict, u: Units) -> str:
    """"levitating: yes, 0.5 s of flight (of 0.5 s)": the answer in one sentence."""
    return f"levitating: {verdict(r)}, {u.time(r['t_survived'])} of flight (of {u.time(r['t_end'])})"


def head(r: dict, u: Units) -> str:
    """"levitating: yes, 0.5 s of flight (of 0.5 s), 12 ms of wall time": the answer first."""
    return f"{summary(r, u)}, {duration(r['wall_s'])} of wall time"


def lines(r: dict, u: Units, scene=None) -> list[str]:
    """Answer first: does it stay up, for how long; then the launch, the excursions, the invariants
    (r: the run's keys, Simulation.details, with what a command added: linear, plot, saved,
    animation; scene: for the plate's symmetry)."""
    dev = r.get("conserved_max_deviation") or {}
    if "flight" in r:
        inv = [f"energy balance {sig(dev.get('energy_balance'), 2)}",
               f"L_n against exp(-t/tau) {sig(dev.get('L_n_decay'), 2)}"]
    else:
        inv = [f"energy {sig(r['energy_drift'], 2)}"]
        inv += [f"{k} {sig(dev[k], 2)}{_not_conserved(k, scene)}" for k in ("L_z", "L_n")
                if dev.get(k) is not None]
    azi = r.get("tilt_azimuth")
    toward = f" toward azimuth {u.angle(azi)}" if azi is not None else ""
    return [line for line in (
        *(flight_line(r, u) if "flight" in r else ()),
        head(r, u),
        linear_line(r, u),
        f"launch: spin {u.rate(r['spin']['rad_s'])}, tilt {u.angle(r['tilt'])}"
        f"{' (the default perturbation)' if r.get('tilt_default') else ''}{toward}, offset "
        f"{u.length(r['offset'])}, from z_s = {u.length(r['z_s'])}",
        f"largest excursion: height {u.length(r['max_height_deviation'])}, radial "
        f"{u.length(r['max_radial_offset'])}, tilt {u.angle(r['max_tilt'])}",
        f"invariants, largest relative deviation over the run: {', '.join(inv)}",
        shown(r["note"], u) if r.get("note") else "",
        f"integrator: {r['integrator']} ({r['backend']}"
        f"{', chosen by auto' if r.get('integrator_requested') == 'auto' else ''}), "
        f"{sig(r['rhs_evals'], 6)} rhs evaluations",
        u.note,
        f"plot: {r['plot']}" if r.get("plot") else "",
        f"samples: {r['saved']}" if r.get("saved") else "",
        f"animation: {r['animation']}" if r.get("animation") else "") if line]
