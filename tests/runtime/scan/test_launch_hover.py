"""runtime/scan/launch_hover.py: a batch of launches' hover heights equal the full search's
(runtime.physics.equilibrium.finder.hover_height, thesis 3.3.2-3.3.3) double for double, and take it
where the shortcut cannot be trusted."""
import math

import numpy as np
import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium.finder import equilibria_of, hover_height
from levitron.runtime.scan import launch_hover


def _full_search(model, ps):
    model.__dict__.pop("_hover_heights", None)       # no answer remembered from the batch
    out = []
    for p in ps:
        try:
            out.append(hover_height(model, p))
        except UserError:
            out.append(math.nan)
    return np.array(out)


@pytest.mark.parametrize("name", ["thesis_air", "levitron_toy", "loop"])
def test_equal_to_the_full_search_double_for_double(derived_model, name):
    """Tops all over the stable band and past both its edges (some cannot hover), with spread
    magnets, and the band's two edges exactly: the same doubles, the same NaNs."""
    model = derived_model(name)
    rep = equilibria_of(model, bands=True)
    lo, hi = rep.stable_band.mass
    rng = np.random.default_rng(7)
    m = np.concatenate([rng.uniform(0.97 * lo, 1.03 * hi, 300), [lo, hi, rep.max_mass]])
    mu = model.param("mu") * np.concatenate([1 + rng.normal(0, 0.01, 300), [1.0, 1.0, 1.0]])
    ps = np.array([model.with_params({"m": a, "mu": b}) for a, b in zip(m, mu)])
    fast = launch_hover.hover_heights(model, ps)
    full = _full_search(model, ps)
    assert np.array_equal(np.isnan(fast), np.isnan(full))
    assert 0 < np.isnan(fast).sum() < len(ps)            # both kinds of top are in the sample
    assert np.array_equal(fast[~np.isnan(fast)], full[~np.isnan(full)])


def test_the_full_search_decides_a_double_root(derived_model, monkeypatch):
    """A top of the largest mass that hovers (a double root at z_c, marginal) is not the shortcut's:
    it asks the full search, which says it cannot hover (thesis 3.3.3: U'' = 0 there)."""
    model = derived_model("thesis_air")
    asked = []
    monkeypatch.setattr(launch_hover, "hover_height", lambda mdl, p: asked.append(p) or hover_height(mdl, p))
    m_c = equilibria_of(model).max_mass
    z = launch_hover.hover_heights(model, np.array([model.with_params({"m": m_c})]))
    assert len(asked) == 1 and math.isnan(z[0])
    asked.clear()
    launch_hover.hover_heights(model, np.array([model.p]))
    assert not asked                                     # the scene's own top: the shortcut alone
