"""Design with CasADi: the mass (washers) that gives the thesis's plate the widest spin range.

Run: python examples/design_spin_range.py [SCENE]
IPOPT maximises sigma_hi - sigma_lo (thesis 3.3.16) over top.mass with the vertical stiffness
kept >= 0.5 N/m; the answer is verified by a 20-point grid and the exact float routes.
"""
import sys

import levitron as lev

scene = sys.argv[1] if len(sys.argv) > 1 else "thesis_stable"
study = lev.load(scene)
m0 = study.value("top.mass")
before = study.stability()
res = study.optimize("spin-range", {"top.mass": (0.98 * m0, 1.01 * m0)}, ["stiffness>=0.5"])
print(f"scene {scene}: top.mass {m0:.6g} kg, spin interval {before.spin_interval} rad/s")
print(f"best top.mass {res.optimum['top.mass']:.6g} kg: spin interval "
      f"[{res.spin_interval[0]:.1f}, {res.spin_interval[1]:.1f}] rad/s, range {res.value:.1f} rad/s "
      f"(IPOPT {res.solver_status}, {res.iterations} iterations; grid best "
      f"{res.verification['grid_best']:.1f} over {res.verification['grid_points']} points)")
