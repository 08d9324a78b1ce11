"""Write tests/slow.txt, the slow tier, from a pytest run with --durations=0 (call + setup + teardown
per test, THRESHOLD_S and above): `python tests/tools/slow_tier.py DURATIONS.log`."""
from __future__ import annotations

import collections
import re
import sys
from pathlib import Path

THRESHOLD_S = 1.4
SLOW = Path(__file__).resolve().parents[1] / "slow.txt"
LINE = re.compile(r"([\d.]+)s (call|setup|teardown)\s+(.+?)\s*$")


def durations(log: str) -> dict[str, float]:
    per: dict[str, float] = collections.Counter()
    for line in log.splitlines():
        m = LINE.match(line)
        if m:
            per[m.group(3)] += float(m.group(1))
    return per


def main(path: str) -> int:
    per = durations(Path(path).read_text())
    if not per:
        print(f"{path}: no durations (run pytest with --durations=0)", file=sys.stderr)
        return 2
    head = [line for line in SLOW.read_text().splitlines() if line.startswith("#")]
    body = [f"{n}\t{t:.1f}" for n, t in sorted(per.items()) if t >= THRESHOLD_S]
    SLOW.write_text("\n".join(head + body) + "\n")
    print(f"{SLOW}: {len(body)} tests, {sum(per[n.split(chr(9))[0]] for n in body):.0f} s of {sum(per.values()):.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
