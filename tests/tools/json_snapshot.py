"""Every command's answer on every scene, kept to compare two versions of the code (issue 29).

    python tests/tools/json_snapshot.py OUT_DIR [--jobs 2] [--only SUBSTRING] [--skip SUBSTRING] [--resume]
    python tests/tools/json_snapshot.py --compare BEFORE_DIR AFTER_DIR           # diff two snapshots

A snapshot runs each case of `cases()` (equilibrium, stability, simulate, scan, launch, optimize,
trim, field, info, fit on every scene of scenes/ and on a dimensionless scene written here; short
runs: small --n, --t-end and grids) through the real command line, once with --json and once for
its plain view, and writes one file per case: {"argv", "exit", "stderr" (its last line), "json",
"text"}. Only what differs from run to run is taken out: the timing keys (TIMING: wall and CPU
times, the provenance's clock), the temporary folder's path (written <TMP>) and, in the plain
view, the wall times. Everything else, every number to the last bit, must be the same.

--compare prints, per case, every key path whose value differs (and the cases only one side has),
and says where only the order of the keys differs; it exits 1 on any difference in value.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))          # run as a script: the checkout's tests.helpers

from tests.helpers.dimensionless import SCENE as DIMENSIONLESS  # noqa: E402

TIMING = {"wall_s", "cpu_s", "seconds", "time", "wall_s_per_point", "cpu_s_per_point",
          "wall_per_launch_s", "elapsed_s", "timings_s"}
TIMEOUT_S = 300         # a case slower than this is recorded as timed out
WALL = re.compile(r"(\d+(\.\d+)? ?(us|ms|s|min)( \d+ s)?|\d+ h \d+ min) of wall time")

FIT_CSV = """quantity,value,sigma,overrides
z_s,0.1065,1e-4,top.mass=0.0515
z_s,0.1052,1e-4,top.mass=0.0518
z_s,0.1078,1e-4,top.mass=0.0512
"""


def run(argv: list[str], tmp: Path, json_too: bool = True) -> dict:
    env = dict(os.environ, PYTHONHASHSEED="0", COLUMNS="100")
    out = {"argv": [strip_text(a, tmp) for a in argv]}
    for mode in (("json", ["--json"]), ("text", [])) if json_too else (("text", []),):
        try:
            p = subprocess.run([sys.executable, "-m", "levitron", *argv, *mode[1]], capture_output=True,
                               text=True, env=env, cwd=tmp, timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:     # recorded as such, never a crash of the snapshot
            out.setdefault("exit", {})[mode[0]] = "timeout"
            out.setdefault("stderr", {})[mode[0]] = f"timed out after {TIMEOUT_S} s"
            out[mode[0]] = None
            continue
        out.setdefault("exit", {})[mode[0]] = p.returncode
        last = p.stderr.strip().splitlines()[-1:] if p.returncode else []
        out.setdefault("stderr", {})[mode[0]] = strip_text(last[0] if last else "", tmp)
        if mode[0] == "json":
            out["json"] = strip(json.loads(p.stdout), tmp) if p.returncode == 0 and p.stdout.strip() else None
        else:
            out["text"] = strip_text(p.stdout, tmp)
    return out


def strip(obj, tmp: Path):
    """The answer without what changes between runs: timing keys, the temporary folder."""
    if isinstance(obj, dict):
        return {k: strip(v, tmp) for k, v in obj.items() if k not in TIMING}
    if isinstance(obj, list):
        return [strip(v, tmp) for v in obj]
    if isinstance(obj, str):
        return strip_text(obj, tmp)
    return obj


def strip_text(text: str, tmp: Path) -> str:
    text = text.replace(str(tmp), "<TMP>").replace(str(ROOT), "<ROOT>")
    return WALL.sub("<WALL> of wall time", text)


def stability_of(scene: str, tmp: Path) -> dict | None:
    p = subprocess.run([sys.executable, "-m", "levitron", "stability", scene, "--json"], capture_output=True,
                       text=True, cwd=tmp, env=dict(os.environ, PYTHONHASHSEED="0"))
    return json.loads(p.stdout) if p.returncode == 0 else None


def cases(scene: str, st: dict | None, tmp: Path) -> dict[str, list[str]]:
    """The commands run on one scene, by case name; the spin from its stable interval."""
    iv = (st or {}).get("spin_interval")
    spin = (iv[0] * iv[1]) ** 0.5 if iv else 1000.0
    lo, hi = (0.8 * iv[0], 1.2 * iv[1]) if iv else (200.0, 3000.0)
    z = (st or {}).get("z_s") or 0.1
    mass = (st or {}).get("mass") or 0.05
    air = scene == "thesis_air"
    t = "2" if air else "0.5"         # short runs; in air the run would go on to the fall
    c = {
        "info": ["info", scene],
        "field": ["field", scene, "--at", f"0,0,{z!r}", "--at", f"{0.05 * z!r},0,{z!r}"],
        "equilibrium": ["equilibrium", scene],
        "equilibrium_plot": ["equilibrium", scene, "--plot", str(tmp / f"{scene}_eq.png")],
        "stability": ["stability", scene],
        "simulate": ["simulate", scene, "--spin", repr(spin), "--t-end", t, "--n-out", "50"],
        "simulate_tilt0": ["simulate", scene, "--spin", repr(spin), "--tilt", "0", "--t-end", t, "--n-out", "20"],
        "simulate_reduced": ["simulate", scene, "--spin", repr(spin), "--part", "reduced", "--t-end", t,
                             "--n-out", "20"],
        "simulate_rk4": ["simulate", scene, "--spin", repr(spin), "--integrator", "rk4", "--t-end", t,
                         "--n-out", "20", "--offset", repr(0.01 * z)],
        "simulate_files": ["simulate", scene, "--spin", repr(spin), "--t-end", t, "--n-out", "30",
                           "--plot", str(tmp / f"{scene}_run.png"), "--save", str(tmp / f"{scene}_run.csv")],
        "scan_tilt": ["scan", scene, "--spin", f"{lo!r}:{hi!r}:3", "--tilt", "0.01:0.05:2", "--t-end", t],
        "scan_mass": ["scan", scene, "--spin", f"{lo!r}:{hi!r}:2", "--mass",
                      f"{0.99 * mass!r}:{1.01 * mass!r}:2", "--t-end", t,
                      "--out", str(tmp / f"{scene}_map.png")],
        "launch": ["launch", scene, "--n", "12", "--t-end", t, "--seed", "3"],
        "optimize_spin_range": ["optimize", scene, "--maximize", "spin-range", "--vary",
                                f"top.mass={0.98 * mass!r}:{1.02 * mass!r}"],
        "optimize_fit_height": ["optimize", scene, "--fit-height", repr(1.01 * z)],
        "trim": ["trim", scene, "--n", "8", "--t-end", t],
        # refusals: their one error line, its quantities in the scene's units
        "refuse_step": ["simulate", scene, "--spin", repr(spin), "--integrator", "rk4", "--step", "10",
                        "--t-end", "1"],
        "refuse_offset": ["simulate", scene, "--spin", repr(spin), "--offset", repr(5 * z)],
        "refuse_t_end": ["simulate", scene, "--spin", repr(spin), "--t-end", "1e9"],
        "refuse_height": ["stability", scene, "--height", repr(1e-9 * z)],
        "refuse_point": ["field", scene, "--at", "1,2"],
    }
    if scene == "thesis_stable":
        c["optimize_fit"] = ["optimize", scene, "--fit", str(tmp / "fit.csv"), "--vary",
                             "plate.murho=-0.003:-0.0023"]
        c["optimize_mass_window"] = ["optimize", scene, "--maximize", "mass-window", "--vary",
                                     "plate.hole=0.02:0.04"]
        c["optimize_launch_odds"] = ["optimize", scene, "--maximize", "launch-odds", "--vary",
                                     f"top.mass={0.98 * mass!r}:{1.02 * mass!r}", "--n", "8", "--t-end", t]
        c["stability_height"] = ["stability", scene, "--height", repr(1.01 * z)]
        c["simulate_animate"] = ["simulate", scene, "--spin", repr(spin), "--t-end", t, "--n-out", "30",
                                 "--animate", str(tmp / "run.html")]
    return c


def take(out: Path, jobs: int, only: str | None, resume: bool = False, skip: tuple = ()) -> None:
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="levitron-snapshot-") as t:
        tmp = Path(t)
        (tmp / "unit_annulus.toml").write_text(DIMENSIONLESS)
        (tmp / "fit.csv").write_text(FIT_CSV)
        scenes = sorted(p.stem for p in (ROOT / "scenes").glob("*.toml")) + [str(tmp / "unit_annulus.toml")]
        todo = []
        for scene in scenes:
            name = Path(scene).stem
            for case, argv in cases(scene, stability_of(scene, tmp), tmp).items():
                done = resume and (out / f"{name}.{case}.json").exists()
                if (only is None or only in f"{name}.{case}") and not done \
                        and not any(s in f"{name}.{case}" for s in skip):
                    todo.append((f"{name}.{case}", argv))

        def one(item):
            key, argv = item
            res = run(argv, tmp)
            (out / f"{key}.json").write_text(json.dumps(res, indent=1) + "\n")
            print(f"{key}: exit {res['exit']}", flush=True)

        with ThreadPoolExecutor(jobs) as pool:
            list(pool.map(one, todo))


def diff(a, b, path: str = "") -> list[str]:
    """The key paths where a and b differ in value (floats compared bit for bit, via their repr)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{path}.{k}: only before" for k in a if k not in b]
        out += [f"{path}.{k}: only after" for k in b if k not in a]
        for k in a:
            if k in b:
                out += diff(a[k], b[k], f"{path}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} -> {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in diff(x, y, f"{path}[{i}]")]
    if type(a) is not type(b) or repr(a) != repr(b):
        return [f"{path}: {str(a)[:80]!r} -> {str(b)[:80]!r}"]
    return []


def order_changes(a, b, path: str = "") -> list[str]:
    """Where the keys of two equal dicts come in another order."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [path or "."] if list(a) != list(b) and set(a) == set(b) else []
        for k in a:
            if k in b:
                out += order_changes(a[k], b[k], f"{path}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        return [d for x, y in zip(a, b) for d in order_changes(x, y, path + "[]")]
    return []


def untimed(obj):
    """The case without the TIMING keys, at any depth."""
    if isinstance(obj, dict):
        return {k: untimed(v) for k, v in obj.items() if k not in TIMING}
    if isinstance(obj, list):
        return [untimed(v) for v in obj]
    return obj


INPUT_HASH = re.compile(r"(input hash:? )[0-9a-f]{12,64}")


def without_hashes(obj):
    """The case with every `input_hash` key and every "input hash <hex>" of a text taken out: what
    differs between two versions whose derive/ sources differ (the hash covers all of derive/),
    though every generated function computes the same numbers."""
    if isinstance(obj, dict):
        return {k: without_hashes(v) for k, v in obj.items() if k != "input_hash"}
    if isinstance(obj, list):
        return [without_hashes(v) for v in obj]
    if isinstance(obj, str):
        return INPUT_HASH.sub(r"\1<HASH>", obj)
    return obj


def compare(before: Path, after: Path, except_hash: bool = False) -> int:
    """Every key path whose value differs, per case (module docstring); except_hash: the input
    hashes apart, each case counted once where they were all that differed."""
    names = sorted({p.name for p in before.glob("*.json")} | {p.name for p in after.glob("*.json")})
    bad = hash_only = 0
    for name in names:
        pa, pb = before / name, after / name
        if not (pa.exists() and pb.exists()):
            print(f"{name}: only in {'before' if pa.exists() else 'after'}")
            bad += 1
            continue
        a, b = json.loads(pa.read_text()), json.loads(pb.read_text())
        for case in (a, b):        # a snapshot taken before argv was stripped: its temporary folder
            case["argv"] = [re.sub(r"/tmp/levitron-snapshot-[^/]+", "<TMP>", t) for t in case["argv"]]
        a, b = untimed(a), untimed(b)      # a snapshot taken before a timing key joined TIMING
        if except_hash:
            hashed = diff(a, b) != []
            a, b = without_hashes(a), without_hashes(b)
            hash_only += hashed and diff(a, b) == []
        diffs = diff(a, b)
        if diffs:
            bad += 1
            print(f"{name}:")
            for d in diffs[:40]:
                print(f"  {d}")
        order = sorted(set(order_changes(a.get("json"), b.get("json"))))
        if order and not diffs:
            print(f"{name}: same values, key order differs at {', '.join(order)}")
    print(f"{len(names)} cases, {bad} differ" + (f"; {hash_only} differ in their input hashes only"
                                                 if except_hash else ""))
    return 1 if bad else 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", type=Path, help="the folder to write the snapshot to")
    ap.add_argument("--compare", nargs=2, type=Path, metavar=("BEFORE", "AFTER"))
    ap.add_argument("--except-hash", action="store_true",
                    help="with --compare: leave the input hashes out (derive/ changed, the numbers must not)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default=None, help="only the cases whose 'scene.case' contains this")
    ap.add_argument("--resume", action="store_true", help="skip the cases OUT_DIR already holds")
    ap.add_argument("--skip", action="append", default=[],
                    help="leave out the cases whose 'scene.case' contains this (repeatable)")
    a = ap.parse_args()
    if a.compare:
        return compare(*a.compare, except_hash=a.except_hash)
    if a.out is None:
        ap.error("give OUT_DIR or --compare BEFORE AFTER")
    take(a.out, a.jobs, a.only, a.resume, tuple(a.skip))
    return 0


if __name__ == "__main__":
    sys.exit(main())
