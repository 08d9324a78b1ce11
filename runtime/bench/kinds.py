"""The benchmarks' one seam: `levitron bench SCENE --kind NAME` (benchmarks are never timed tests).

A benchmark is a module with one function,

    bench(model, out: Path, quick: bool) -> dict     (the scene's overrides: model.scene.overrides)

that measures, writes its report files into `out` (a table and a plot) and returns a JSON-able
dict with "files" (the paths written) and "headline" (one line for a person); plus one entry in
KINDS below, with the scenes `make bench` runs it on and its report folder. So a new benchmark
takes two files: its module and this registry. `python -m levitron.runtime.bench.kinds` runs every kind on
its scenes: the Makefile's `bench` target.
"""
from __future__ import annotations

import importlib
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Kind:
    name: str
    module: str          # defines bench(model, out, quick)
    doc: str
    scenes: tuple        # what `make bench` runs it on
    out: str             # its report folder; "{scene}" is the scene's name


KINDS = {k.name: k for k in (
    Kind("work-precision", "levitron.runtime.bench.work_precision", "speed against error of every backend and "
         "integrator (heyoka beside ours when the [bench] extra is installed)",
         ("thesis_stable", "ring_magnet", "square", "loop", "reduced_only"), "reports/{scene}"),
    Kind("maps", "levitron.runtime.bench.maps", "points per second of a stability map on 1 and 2 workers, the "
         "C driver against the Python path", ("thesis_stable",), "reports/maps"),
    Kind("design", "levitron.runtime.bench.design", "wall time of verified IPOPT designs", ("thesis_stable",),
         "reports/design"),
    Kind("launch", "levitron.runtime.bench.launch", "a long flight in air and a launch Monte Carlo",
         ("thesis_air",), "reports/launch"),
    Kind("launch-design", "levitron.runtime.bench.launch_design", "wall time of a design by the launch "
         "odds over the top's mass (300 launches an evaluation) on 1 and 2 workers, with the machine's load",
         ("thesis_air",), "reports/launch_design"),
    Kind("advice", "levitron.runtime.bench.advice", "CPU and wall time of the advice a person waits for "
         "(trim, launch-odds designs, the level tolerance with a tilted magnet, a launch), before and after",
         ("thesis_air",), "reports/advice"),
    Kind("verdict-tolerance", "levitron.runtime.bench.verdict_tolerance", "the launch odds' verdicts and "
         "CPU time against the integrator tolerance, 1000 launches against tol 1e-10",
         ("thesis_air", "levitron_toy"), "reports/verdict_tolerance/{scene}"),
    Kind("search-horizon", "levitron.runtime.bench.search_horizon", "when a launch-odds design's search may "
         "judge its launches: the same launches judged at fractions of the success time, across the band",
         ("thesis_air", "levitron_toy"), "reports/search_horizon/{scene}"),
    Kind("functions", "levitron.runtime.bench.functions", "ns per call of every generated function",
         ("thesis_stable", "ring_magnet"), "reports/{scene}/functions"),
    Kind("startup", "levitron.runtime.bench.startup", "wall time of warm one-shot commands (the version, the help, "
         "stability, equilibrium) in fresh processes, against their budgets", ("thesis_stable",),
         "reports/startup"),
    Kind("api", "levitron.runtime.bench.api", "the Python that Study.simulate adds around the C integration "
         "it reports, a short run per part, against its 1 ms budget", ("thesis_stable", "ring_magnet"),
         "reports/{scene}/api"),
)}
DEFAULT = "work-precision"
QUICK_OUT = "out/bench-quick/{kind}"      # a quick run never overwrites a report


def out_dir(kind: str, scene: str, quick: bool) -> Path:
    return Path((QUICK_OUT if quick else KINDS[kind].out).format(scene=scene, kind=kind))


def run(kind: str, model, out: Path, quick: bool) -> dict:
    """One benchmark through the protocol of the module docstring."""
    res = importlib.import_module(KINDS[kind].module).bench(model, Path(out),
                                                            quick)
    res["kind"] = kind
    return res


def main() -> int:
    """Every kind on its scenes, each through the `levitron bench` command (the Makefile's bench)."""
    for kind in KINDS.values():
        for scene in kind.scenes:
            cmd = [sys.executable, "-m", "levitron.runtime", "bench", scene, "--kind", kind.name]
            print("$ levitron " + " ".join(cmd[3:]), flush=True)
            if subprocess.run(cmd, check=False).returncode != 0:
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
