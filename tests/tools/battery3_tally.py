"""Count the third battery's classes (issue 31) that hold: `python tests/tools/battery3_tally.py [REF]`.

Runs tests/battery/test_hostile_conditions.py (with tests/helpers/hostile.py, its runner) against
this checkout, or, given a git REF (e.g. `main`), against that commit's code in a temporary
worktree with these three test files copied in: the "before" of the classes. Prints one line per
class: its cases (parametrized tests counted one by one), how many pass, and the failing ones; then
the totals. Exit 0.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
ROOT = TESTS.parent
# the battery, its runner and the battery machinery, copied into an older tree at the same paths
FILES = ("battery/test_hostile_conditions.py", "helpers/hostile.py", "helpers/battery.py")
# each test of tests/battery/test_hostile_conditions.py and the class of defects it stands for (issue 31)
CLASSES = {
    "outputs whole (tmp + rename), mode, sweeps": (
        "test_a_write_that_fails", "test_a_kill_mid_write", "test_concurrent_saves", "test_debris_of_killed",
        "test_generated_debris", "test_the_written_table", "test_every_write_of_the_runtime"),
    "one validation per quantity; no verdict, no odds": (
        "test_a_temperature_spread", "test_runs_without_a_verdict", "test_a_run_that_stops_early"),
    "every size bounded": ("test_every_size_has_a_bound",),
    "numbers read one way": ("test_a_number_is_read_one_way",),
    "child processes die with their parent": ("test_workers_are_capped", "test_a_script_without"),
    "API arguments checked": ("test_api_mistakes",),
    "errors name what to fix": ("test_errors_name_what_to_fix", "test_a_scheduler_that_answers",
                                "test_a_killed_derive_child", "test_a_damaged_object", "test_a_scene_with_a_byte",
                                "test_a_formula_that_is_one_over_zero"),
    "the energy balance measures the run": ("test_the_energy_balance",),
}


def run(root: Path) -> dict[str, bool]:
    """{test id: passed} of tests/battery/test_hostile_conditions.py run in `root`."""
    with tempfile.TemporaryDirectory(prefix="levitron-tally-") as tmp:
        report = Path(tmp) / "report.xml"
        env = dict(os.environ, PYTHONPATH=str(root))
        subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:xdist", "-p", "no:cacheprovider",
                        f"--junitxml={report}", "tests/battery/test_hostile_conditions.py"], cwd=root, env=env,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        cases = ET.parse(report).getroot().iter("testcase")
        return {c.get("name"): not any(ch.tag in ("failure", "error") for ch in c) for c in cases}


def tally(results: dict[str, bool]) -> list[str]:
    out, total, held = [], 0, 0
    for name, prefixes in CLASSES.items():
        mine = {k: v for k, v in results.items() if k.startswith(prefixes)}
        ok = sum(mine.values())
        total, held = total + len(mine), held + ok
        failing = ", ".join(k for k, v in mine.items() if not v)
        out.append(f"{name}: {ok} of {len(mine)} cases hold" + (f" (failing: {failing})" if failing else ""))
    other = set(results) - {k for p in CLASSES.values() for k in results if k.startswith(p)}
    assert not other, f"tests of no class: {sorted(other)} (add them to CLASSES)"
    classes = sum(all(v for k, v in results.items() if k.startswith(p)) for p in CLASSES.values())
    out.append(f"total: {held} of {total} cases hold; {classes} of {len(CLASSES)} classes hold whole")
    return out


def main(argv: list[str]) -> int:
    if not argv:
        print("\n".join(tally(run(ROOT))))
        return 0
    with tempfile.TemporaryDirectory(prefix="levitron-tally-ref-") as tmp:
        tree = Path(tmp) / "tree"
        subprocess.run(["git", "worktree", "add", "--detach", "-q", str(tree), argv[0]], cwd=ROOT, check=True)
        try:
            for name in FILES:
                (tree / "tests" / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(TESTS / name, tree / "tests" / name)
            print(f"at {argv[0]}:")
            print("\n".join(tally(run(tree))))
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=False)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
