"""A study from scene to design, through the Python API (docs/api.md), on a plate of our own.

Run: python examples/study_walkthrough.py [SCENE] [OUT_DIR]
(default examples/scenes/small_ring.toml: a 100 x 40 x 15 mm ferrite ring, a 29.2 g top).

1. load the scene and ask where its top can hover (thesis 3.3.2-3.3.3: equilibria, the stable band);
2. the spin interval of linear stability at the hover height (thesis 3.3.16-3.3.23);
3. a loop over masses with NumPy: how the interval moves as washers are added;
4. one launch in the middle of the interval, its trajectory saved as data (CSV);
5. a small stability map over spin and tilt (thesis fig. 3.8);
6. the design: the mass of the widest spin range, kept at a vertical stiffness >= 1 N/m, verified.
"""
import sys
from pathlib import Path

import numpy as np

import levitron as lev

HERE = Path(__file__).resolve().parent
scene = sys.argv[1] if len(sys.argv) > 1 else str(HERE / "scenes" / "small_ring.toml")
out = Path(sys.argv[2] if len(sys.argv) > 2 else "out/walkthrough")
out.mkdir(parents=True, exist_ok=True)

# 1. where can the top hover?
study = lev.load(scene)
eq = study.equilibria()
m0 = study.value("top.mass")
print(f"1. {Path(scene).stem}: top.mass {m0 * 1e3:.4g} g; equilibria "
      + ", ".join(f"{e.z * 100:.4g} cm ({'stable' if e.vertically_stable else 'unstable'})"
                  for e in eq.equilibria))
lo_m, hi_m = eq.stable_band_mass
print(f"   stable band {eq.stable_band_z[0] * 100:.4g}-{eq.stable_band_z[1] * 100:.4g} cm, "
      f"for tops of {lo_m * 1e3:.4g}-{hi_m * 1e3:.4g} g")

# 2. the spin interval at the hover height
st = study.stability()
print(f"2. {st!r}")

# 3. a NumPy loop over masses inside the band
print("3. mass (g)   z_s (cm)   spin interval (rad/s)")
for m in np.linspace(lo_m, hi_m, 5)[1:-1]:
    s = lev.load(scene, {"top.mass": m}).stability()
    iv = s.spin_interval
    print(f"   {m * 1e3:8.4g}   {s.z_s * 100:8.4g}   " + (f"{iv[0]:.1f}-{iv[1]:.1f}" if iv else "none"))

# 4. one launch, saved as data
spin = float(np.sqrt(st.spin_interval[0] * st.spin_interval[1]))
run = study.simulate(spin, tilt=0.01, t_end=5.0)
csv = run.save(out / "launch.csv")
print(f"4. spin {spin:.1f} rad/s, tilt 0.01 rad: {run.message}; trajectory {csv}")

# 5. a small map over spin and tilt (each run 2 s)
spins = np.linspace(0.6 * st.spin_interval[0], 1.2 * st.spin_interval[1], 6)
tilts = np.array([0.005, 0.02, 0.05])
m = study.scan(spins, "tilt", tilts, t_end=2.0)
print(f"5. map: {m.message}")

# 6. design: the mass of the widest spin range at a stiffness of at least 1 N/m
best = study.optimize("spin-range", {"top.mass": (lo_m, hi_m)}, ["stiffness>=1"])
print(f"6. {best!r}")
print(f"   verified: grid best {best.verification['grid_best']:.1f} rad/s over "
      f"{best.verification['grid_points']} points; success {best.success}")
