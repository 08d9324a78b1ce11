"""Answers own their words: the plain view the command line prints, the answer's `message` and the
report's sentence come from the answer's own `lines`/`summary` (runtime/physics/stability/view.py),
so that a field changed in the answer shows in all three."""
from __future__ import annotations

from dataclasses import replace

from levitron.runtime.physics.stability.answer import Stability
from levitron.runtime.ui.human import Units
from levitron.runtime.words import render

SI = Units(si=True)
# a stability answer as `levitron stability --json` gives it (the fields the words read)
JSON = {"scene": "x", "z_s": 0.1065, "mass": 0.0515, "scene_mass": 0.0515, "height_given": False,
        "spin_interval": [459.6, 2740.0], "all_intervals": {"discriminant": [[459.6, 2740.0]],
                                                            "eigenvalues": [[459.6, 2740.0]]},
        "approximations": {}, "reason": None, "stiffness": 2.555, "resonances": None}


def _cli(answer: Stability) -> str:
    from levitron.runtime.cli.commands.stability import human
    return render(human(answer.as_json()), "cli")


def test_one_field_changes_the_command_lines_view_and_the_message_alike():
    a = Stability.from_json(JSON)
    b = replace(a, z_s=0.1234)
    assert "at z_s = 10.65 cm for the 51.5 g top" in _cli(a) and "at z_s = 10.65 cm" in a.message
    assert "at z_s = 12.34 cm for the 51.5 g top" in _cli(b) and "at z_s = 12.34 cm" in b.message
    assert "10.65" not in _cli(b) + b.message + repr(b)
    assert b.summary(SI) in b.message and a.lines(SI)[1] in _cli(a)
    # no interval: the reason, written with its quantity, in the view and the message
    c = replace(a, spin_interval=None, reason="no root at z = ‹0.15|m›")
    assert "reason: no root at z = 15 cm" in _cli(c) and c.message == "no stable spin interval: no root at z = 15 cm"
    d = replace(c, reason="no root at z = ‹0.2|m›")
    assert "z = 20 cm" in _cli(d) + d.message and "15 cm" not in _cli(d) + d.message


def test_the_reports_sentence_is_the_answers(monkeypatch):
    """The report places the answer's summary: the same answer with another z_s reads otherwise."""
    import levitron as lev
    from levitron.runtime.report import page
    model = lev.load("reduced_only").model       # no full model: no map and no launch (quick)
    real = Stability.of
    pages = []
    for z in (0.123, 0.135):
        def of(m, z=z, **kw):
            return replace(real(m, **kw), spin_interval=(400.0, 900.0), z_s=z)
        monkeypatch.setattr(page, "Stability", type("S", (), {"of": staticmethod(of)}))
        html, _ = page.build(model)
        answer = of(model)
        assert render(answer.summary(Units.of_scene(model.scene)), "cli") in html
        assert answer.message.split(" (")[0] in html
        pages.append(html)
    assert "at z_s = 12.3 cm for the 28.4 g top" in pages[0] and "12.3 cm" not in pages[1]
    assert "at z_s = 13.5 cm for the 28.4 g top" in pages[1]
