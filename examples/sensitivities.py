"""Exact sensitivities of the hover height and the spin limits to scene keys (CasADi, implicit
function theorem through the rootfinders of runtime/physics/stability/differentiable.py; thesis 3.3).

Run: python examples/sensitivities.py [SCENE]
"""
import sys

import levitron as lev

scene = sys.argv[1] if len(sys.argv) > 1 else "thesis_stable"
study = lev.load(scene)
keys = ["top.mass", "top.A", "top.C"]
st = study.stability()
print(f"scene {scene}: z_s = {st.z_s:.6g} m, spin interval {st.spin_interval} rad/s")
for q in ("z_s", "sigma_lo", "sigma_hi"):
    grad = study.gradient(q, keys)
    print(q, "  ".join(f"d/d {k} = {v:.6g}" for k, v in grad.items()))
f = study.functions()["spin"]
print("CasADi Function:", f.name(), f.name_in(), "->", f.name_out())
