"""What the code does not say of a command's `--json` keys, declared once (runtime/cli/schema.py reads
the rest from the answer types' `as_json`; docs/contract.md says what each key means).

VARIANTS: command -> its answer's shapes, each (title, the answer types' methods that write its keys as
"module:Class.method", the keys declared here). The notation (schema.spec_schema): "number", "integer",
"string", "boolean", "array", "object", "any", joined by "|", "?" for "or null"; a key written "~key" is
not always present; a dict is an object with those keys, a one-element list an array of that item;
the key "..." lets the top level take keys it does not name (bench's kinds other than work-precision).
A declaration wins over what the answer type's code says.
"""
from __future__ import annotations

# every answer's own two keys (runtime/cli/main.py, runtime/ui/provenance.py)
FACE = {
    "provenance": {"package": "string", "version": "string", "command": "string", "time": "string",
                   "python": "string"},
    "success": "boolean",
}

_ODDS = {"probability": "number", "probability_ci95": ["number"], "n": "integer", "seed": "integer",
         "~paired_with": "string"}
_INPUTS = "object"      # input -> its spread as text (runtime/scan/launch_inputs.py)

_STABILITY_RESULT = {      # runtime/physics/routes/result.py as_dict: the keys it builds from locals
    "spin_interval": "array?", "spin_interval_hz": "array?", "spin_interval_rpm": "array?",
    "~notes": ["string"],
}

_SIMULATE = {              # runtime/simulate/run.py summarize and run (Simulation.as_json is its details)
    "levitating": "boolean?", "t_survived": "number", "max_excursion": "number?", "energy_drift": "number?",
    "rhs_evals": "integer", "wall_s": "number", "final_state": "object", "status": "string",
    "message": "string", "z_s": "number", "spin": {"rad_s": "number", "hz": "number", "rpm": "number"},
    "tilt": "number", "offset": "number", "t_end": "number", "integrator": "string", "backend": "string",
    "tol": "number?", "step": "number?", "box": {"z": ["number"], "r_max": "number?"},
    "max_height_deviation": "number?", "max_radial_offset": "number?", "max_tilt": "number?",
    "energy_drift_final": "number?", "energy_scale": "number?", "conserved": "object",
    "conserved_max_deviation": "object", "part": "string?", "coordinates": "string?",
    "tilt_azimuth": "number", "tilt_default": "boolean", "integrator_requested": "string",
    "~integrator_choice": "string", "~note": "string", "~untested": "string",
    "~flight": "object", "~fall_spin": "number?", "~t_cross": "number?",
    # the command's own (runtime/cli/commands/simulate.py)
    "plot": "string?", "~saved": "string", "~animation": "string", "~linear": "object",
}

_LAUNCH = {                # runtime/scan/launch_odds.py summarize (LaunchOdds.details), launch_summary.cannot_hover
    "probability": "number", "probability_ci95": ["number"], "successes": "integer", "n": "integer",
    "no_verdict": "integer", "seed": "integer", "success_time": "number", "t_end": "number",
    "flight_time": {"median": "number", "q1": "number", "q3": "number", "~censored": "integer",
                    "~values": ["number?"]},
    "outcomes": "object", "ranking": [{"input": "string", "effect": "number?"}], "inputs": _INPUTS,
    "defaulted": ["string"], "z_s": "number?", "spin_interval": "array?", "~spin_decay_time": "number?",
    "~integrator": "string", "~tol": "number", "verdicts": ["boolean"], "warnings": ["string"],
    "~reason": "string", "~past_window": {"launches": "integer", "reason": "string?"},
    # the command's own (runtime/cli/commands/launch.py)
    "saved": "object?",
    "out": "string?",
}

_DESIGN_FACE = {"scene": "string", "~written": "string"}    # runtime/cli/commands/optimize.py adds them

VARIANTS = {
    "scenes": [("scenes", (), {
        "folder": "string",
        "scenes": [{"name": "string", "plate": "string", "description": "string?", "units": "string",
                    "file": "string"}]})],
    "keys": [("a plate kind's keys", (), {
        "kind": "string", "doc": "string", "keys": ["object"], "plate_common": ["object"],
        "decisions": "object", "can_be_part": "boolean", "example": "string"}),
             ("the kinds and the sections", (), {
        "kind": "null", "kinds": "object", "sections": "object", "plate_common": ["object"]})],
    "derive": [("derive", (), {"scenes": [{"name": "string", "~files": ["string"], "~seconds": "number"}]})],
    "info": [("info", (), {
        "scene": "string", "file": "string", "parameters": "object", "derived_parameters": "object",
        "notes": ["string"], "symmetry": "object", "generated": "string", "input_hash": "string",
        "plate": "string", "coordinates": "string?", "field_order": "integer", "parts": "object",
        "functions": "object", "taylor": "object", "decay_times": "object?", "friction_rates": "object?"})],
    "field": [("field", (), {
        "scene": "string", "plate": "string", "field_order": "integer",
        "points": [{"r": ["number"], "B": ["number?"], "B_exact": "array?", "~relative_difference": "number?",
                    "~note": "string"}],
        "~exact": "string", "~notes": ["string"]})],
    "equilibrium": [("equilibrium", ("levitron.runtime.physics.equilibrium.answer:Equilibria",), {
        "equilibria": [{"z": "number", "vertically_stable": "boolean"}], "singularities": "array",
        "stable_band": "object?", "adiabatic_band": "object?", "adiabatic_note": "string",
        "reason": "string?", "~plot": "string"})],
    "stability": [("stability", ("levitron.runtime.physics.stability.answer:Stability",
                                 "levitron.runtime.physics.routes.result:StabilityResult.as_dict"), {
        "mass": "number?", **_STABILITY_RESULT,
        "~modes": "object", "~tilt_tolerance": "object", "~plot": "string"})],
    "optimize": [
        ("a design (spin-range, spin-ratio, mass-window)", ("levitron.runtime.design.design_answer:Design",), {
            "objective_formula": "string", "spin_interval": "array?",
            "~launch_odds": "object", "~start_launch_odds": "object", "~launch_odds_optimum": "object",
            **_DESIGN_FACE}),
        ("a design by the launch odds", ("levitron.runtime.design.launch_design_answer:LaunchDesign",), {
            "search": "object", **_DESIGN_FACE}),
        ("a design by the yield of a production run", ("levitron.runtime.design.yield_answer:YieldDesign",), {
            "yield": "object", "start_yield": "object", "as_shipped": "object", "start_as_shipped": "object",
            "untrimmable": "number", "washers_used": ["object"], "owner_curve": "object?", "production": "object",
            "search": "object", "inputs": "object", "sharpness": "object?", **_DESIGN_FACE}),
        ("a fit (--fit)", ("levitron.runtime.design.fit_answer:Fit",), {
            "covariance": "array?", "correlation": "array?", **_DESIGN_FACE}),
        ("a height fit (--fit-height)", ("levitron.runtime.design.fit_height:HeightFit",), {
            "optimum": "object", "scene": "string"})],
    "figures": [("figures", (), {
        "scene": "string", "files": ["string"], "scene_files": ["string"], "solver_files": "array?",
        "solver_files_kept": "boolean", "solver_files_cached": "boolean", "not_drawn": "object"})],
    "simulate": [("simulate", (), _SIMULATE)],
    "bench": [("work-precision", (), {
        "kind": "string", "rows": ["object"], "goals": "object", "models": "object", "setup": "object",
        "files": "array|integer", "quick": "boolean", "wall_s": "number", "~reference_check": "any",
        "~reference_vs_taylor": "any"}),
              ("another kind: its report's own keys", (), {"kind": "string", "...": "any"})],
    "scan": [("scan", ("levitron.runtime.scan.scan_answer:Scan",), {
        "spin_hz": ["number"], "levitating": [["boolean"]], "t_survived": [["number?"]],
        "fraction_levitating": "number", "spin_interval": "array?",
        # Scan.extra["public"] (runtime/scan/stability_map.py)
        "integrator": "string", "integrator_requested": "string", "tol": "number?", "base_tilt": "number?",
        "~equilibrium": "object", "past_window": {"points": "integer", "reason": "string?"},
        "out": "string?", "~saved": "string"})],      # the command's own (runtime/cli/commands/scan.py)
    "launch": [("launch", ("levitron.runtime.scan.launch_answer:LaunchOdds",), _LAUNCH)],
    "trim": [("trim", ("levitron.runtime.design.trim_answer:Trim",), {
        "band_mass": ["number"], "launch_odds": _ODDS, "start_launch_odds": _ODDS, "inputs": _INPUTS,
        "success_time": "number", "t_end": "number", "design": "object",
        "scene": "string", "out": "string?"})],      # the command's own (runtime/cli/commands/trim.py)
    "compare": [("compare", ("levitron.runtime.design.compare:Comparison",), {})],
    "report": [("report", (), {
        "scene": "string", "units": "string", "equilibria": "array", "stable_band": "object?",
        "spin_interval": "array?", "z_s": "number?", "hints": ["string"], "~tilted_base": "object",
        "~map": "object?", "~launch": "object?", "~not_drawn": "string", "~animation": "object",
        "~air": "object", "rebuild": "object", "out": "string", "bytes": "integer"})],
    "schema": [("one command's schema", (), {"command": "string", "schema": "object"}),
               ("the commands", (), {"commands": [{"command": "string", "description": "string"}]})],
}
