"""The Python API as a physicist uses it in a notebook (second audit): each wrong input is one
`lev.UserError` saying what is wrong, never a TypeError, IndexError, AttributeError or a sentence
that blames the wrong thing; and a question that would test nothing is refused, not answered."""
from __future__ import annotations

import numpy as np
import pytest

import levitron as lev


def one_line(exc_info) -> str:
    text = str(exc_info.value)
    assert "\n" not in text
    return text


def test_quantities_are_listed_once(study):
    q = study.quantities()
    assert len(q) == len(set(q)) and {"z_s", "sigma_lo", "mass_window"} <= set(q)


def test_a_need_that_is_not_a_part_is_named_as_unknown(study):
    # "linear" is in model.needs, so "has no linear model ... add linear" was false
    for call in (lambda: study.simulate(1500.0, part="linear", t_end=0.1),
                 lambda: study.simulate_many([1500.0], part="linear", t_end=0.1)):
        with pytest.raises(lev.UserError) as e:
            call()
        assert "part 'linear' is unknown" in one_line(e) and "reduced" in str(e.value)


def test_a_structural_key_is_not_differentiated(study, tmp_path):
    # field.order = 2 * 1.01 was reported as "the scene is not valid: narrow the --vary bounds"
    with pytest.raises(lev.UserError) as e:
        study.gradient("sigma_hi", ["field.order"])
    assert "field.order is structure" in one_line(e)
    data = tmp_path / "z.csv"
    data.write_text("quantity,value,sigma\nz_s,0.1065,0.0005\n")
    with pytest.raises(lev.UserError) as e:
        study.fit(data, {"field.order": (2, 4)})
    assert "field.order is structure" in one_line(e)


def test_fit_refuses_a_quantity_that_cannot_be_negative(study, tmp_path):
    # a negative height went to 60 Gauss-Newton iterations and "max_iter"
    data = tmp_path / "neg.csv"
    data.write_text("quantity,value,sigma\nz_s,-0.1065,0.0005\n")
    with pytest.raises(lev.UserError) as e:
        study.fit(data, {"plate.murho": (-0.003, -0.0023)})
    assert "z_s = -0.1065 must be positive" in one_line(e) and "line 2" in str(e.value)


def test_unknown_scan_option_is_a_user_error(study):
    with pytest.raises(lev.UserError) as e:
        study.scan([1500.0], "tilt", [0.01], tend=0.5)
    assert "scan option 'tend' is unknown" in one_line(e) and "t_end" in str(e.value)


def test_simulations_final_state_index_out_of_range(study):
    many = study.simulate_many([1000.0, 1500.0], tilt=0.01, t_end=0.05)
    assert many.final_state(-1) == many.final_state(1)
    with pytest.raises(lev.UserError) as e:
        many.final_state(2)
    assert "from 0 to 1" in one_line(e)


def test_values_length_mismatch_names_the_scene_key(study):
    # it named "p", an internal vector the user never passed
    with pytest.raises(lev.UserError) as e:
        study.simulate_many(np.array([1000.0, 1500.0, 2000.0]),
                            values={"top.mass": np.array([0.0515, 0.051])}, t_end=0.05)
    text = one_line(e)
    assert "top.mass 2" in text and "spin 3" in text and " p " not in text


def test_propagator_p_assignment_copies_or_says_what_is_wrong(study):
    prop = study.propagator("reduced", "dop853", 1e-9)
    x0 = [0.108, 0.0, 0.0, 1e-3]
    before = prop(x0, 0.2)
    prop.p = study.p_of({"top.mass": 0.051})          # as prop.p[:] = ...
    moved = prop(x0, 0.2)
    prop.p[:] = study.p_of()
    assert np.array_equal(prop(x0, 0.2), before) and not np.array_equal(moved, before)
    for bad in (np.zeros(3), "0.05", [np.nan] * prop.p.size):
        with pytest.raises(lev.UserError) as e:
            prop.p = bad
        assert f"prop.p must be {prop.p.size} finite numbers" in one_line(e)
    assert np.array_equal(prop(x0, 0.2), before)


def test_launch_on_the_invariant_set_is_refused(study):
    # every sample at tilt 0, offset 0, velocity 0 floats forever: "100% float" tested nothing
    with pytest.raises(lev.UserError) as e:
        study.launch(n=3, seed=1, inputs={"tilt": 0, "offset": "normal:0,0", "velocity": "uniform:0,0"},
                     t_end=0.1)
    assert "invariant set" in one_line(e)


def test_flight_plot_title_stays_inside_the_figure(tmp_path):
    # a dimensionless flight's one-line title ran past the right edge ("rad/time" cut off)
    from levitron.runtime.simulate.plot import draw_flight
    from levitron.runtime.ui.human import Units
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    t = np.linspace(0.0, 394.1, 50)
    info = {"flight": {"spin_interval": [30.28, 119.1], "t_cross": 388.6, "flight_time": 394.1,
                       "fell": True, "fall_spin": 29.87}, "spin": {"rad_s": 80.0}, "t_survived": 394.1}
    fig = draw_flight(t, -1e-3 * t, 80 * np.exp(-t / 400), tmp_path / "f.png", info, Units(si=False),
                      "dimless_air")
    box = fig.axes[0].title.get_window_extent(FigureCanvasAgg(fig).get_renderer())
    assert 0 <= box.x0 and box.x1 <= fig.bbox.x1


def test_a_study_says_what_it_is():
    """A notebook's cell that shows a Study: its scene, overrides, units, parts and plate (it was
    '<levitron.study.Study object at 0x...>')."""
    assert repr(lev.load("thesis_stable", {"top.mass": 0.051})) == (
        "Study(scene='thesis_stable', overrides=['top.mass=0.051'], SI, parts=['full', 'reduced'], "
        "annulus plate)")
    assert repr(lev.load("reduced_only")).startswith("Study(scene='reduced_only', SI, parts=['reduced'],")


@pytest.mark.parametrize("text,cli,api", [
    ("t_end=-1.0 must be positive; pass e.g. «t_end=1»", "t_end=-1.0 must be positive; pass e.g. --t-end 1",
     "t_end=-1.0 must be positive; pass e.g. t_end=1"),
    ("«n_out» = 0 must be at least 1", "--n-out = 0 must be at least 1", "n_out = 0 must be at least 1"),
    ("«n=-5» must be a whole number", "--n -5 must be a whole number", "n=-5 must be a whole number"),
    ("pass e.g. «tol=1e-9»", "pass e.g. --tol 1e-9", "pass e.g. tol=1e-9"),
    ("give a tilt (e.g. «tilt=0.005») or an offset", "give a tilt (e.g. --tilt 0.005) or an offset",
     "give a tilt (e.g. tilt=0.005) or an offset"),
    ("«tilt=0.001:0.3:10»", "--tilt 0.001:0.3:10", "tilt=0.001:0.3:10"),
    ("add it with «set=field.order=12»", "add it with --set field.order=12",
     "add it with overrides={'field.order': 12}"),
    ("«set» {key}=0", "--set {key}=0", "overrides {key}=0"),
    ("run the full model («part=full»)", "run the full model (--part full)", "run the full model (part='full')"),
    ("«temperature_spread» normal:20,5", "--temperature-spread normal:20,5", "inputs['temperature'] normal:20,5"),
    ("see `«levitron=equilibrium»`", "see `levitron equilibrium`", "see `Study.equilibria()`"),
    ("«Tilt» and «two words» are no markers", "«Tilt» and «two words» are no markers",
     "«Tilt» and «two words» are no markers"),
    ("a 2-3 mm top at 1e-9 s", "a 2-3 mm top at 1e-9 s", "a 2-3 mm top at 1e-9 s"),
    ("«t_end» = ‹-1|s›, at z = ‹0.1574|m› in ‹|m›", "--t-end = -1 s, at z = 0.1574 m in m",
     "t_end = -1 s, at z = 0.1574 m in m"),
])
def test_a_runtime_sentence_is_worded_by_each_face(text, cli, api):
    """runtime/words.py render: the settings a runtime sentence names by marker are the command
    line's flags on the CLI and the keyword arguments in the API (a Study method's UserError and
    answer pass through it)."""
    from levitron.runtime.words import render
    assert (render(text, "cli"), render(text, "api")) == (cli, api)


def test_no_study_error_names_a_command_line_flag(study):
    """The API's errors name its keyword arguments, not flags (simulate validates with the
    command line's checks, whose sentences say --spin, --t-end, ...)."""
    bad = [lambda: study.simulate(spin=float("nan")), lambda: study.simulate(1000.0, t_end=-1.0),
           lambda: study.simulate(1000.0, n_out=0), lambda: study.simulate(1000.0, tol=2.0),
           lambda: study.simulate(1000.0, integrator="rk4", step=-1.0),
           lambda: study.propagator(tol=-1.0), lambda: study.launch(n=-5),
           lambda: study.scan([100.0, 200.0], "tilt", [0.1], workers=0)]
    for call in bad:
        with pytest.raises(lev.UserError) as exc:
            call()
        assert "--" not in str(exc.value) and len(str(exc.value).splitlines()) == 1, str(exc.value)


def test_an_unknown_function_name_is_one_line_with_a_hint(study):
    fns = study.functions()
    with pytest.raises(lev.UserError, match=r"function 'full_rsh' is unknown: did you mean 'full_rhs'\?"):
        fns["full_rsh"]
    assert "full_rhs" in fns and fns.get("nope") is None


def test_a_part_the_scene_did_not_derive_is_named_as_missing_not_unknown():
    """Third audit: on a reduced-only scene, study.propagator("full") said "part 'full' is unknown:
    use one of reduced", while simulate says what is true: the scene has no full model, add "full"
    to model.needs. A misspelt part is still unknown, with a hint."""
    red = lev.load("reduced_only")
    for call in (lambda: red.propagator("full"), lambda: red.simulate(1000.0, part="full", t_end=0.1)):
        with pytest.raises(lev.UserError) as e:
            call()
        assert "has no full model" in one_line(e) and "model.needs" in str(e.value), str(e.value)
    with pytest.raises(lev.UserError) as e:
        red.propagator("ful")
    assert "part 'ful' is unknown: did you mean 'full'?" in one_line(e)


def test_the_apis_sentences_name_its_methods_not_the_commands():
    """Third audit: a Study's error and a Stability's message sent a notebook user to the command
    line ("(see `levitron equilibrium`)", "(`levitron equilibrium` gives it)"); the API names its
    own method, Study.equilibria() (runtime/words.py, as it does for flags)."""
    from levitron.runtime.words import render
    assert render("outside the band (see `«levitron=equilibrium»`)", "api") == \
        "outside the band (see `Study.equilibria()`)"
    assert render("run `«levitron=stability»` first", "api") == "run `Study.stability()` first"
    texts = [lev.load("thesis").stability().message]
    for call in (lambda: lev.load("thesis_stable", {"top.mass": 0.06}).simulate(1000.0),
                 lambda: lev.load("thesis_stable").stability(height=-1.0)):
        with pytest.raises(lev.UserError) as e:
            call()
        texts.append(one_line(e))
    for text in texts:
        assert "`levitron" not in text and "Study.equilibria()" in text, text


def test_a_reduced_only_scene_says_what_it_lacks_in_the_apis_words():
    """On a scene derived without the full model, functions()['full_rhs'] names the missing part
    (not 'unknown'), and simulate(spin) offers part='reduced' as the API writes it."""
    st = lev.load("reduced_only")
    with pytest.raises(lev.UserError, match=r"function 'full_rhs': scene 'reduced_only' has no full model.*"
                                            r"add \"full\" to model.needs"):
        st.functions()["full_rhs"]
    with pytest.raises(lev.UserError, match=r"has no full model.*pass part='reduced' for the vertical motion"):
        st.simulate(250.0)
    with pytest.raises(lev.UserError, match="did you mean 'reduced_rhs'"):
        st.functions()["reduced_rsh"]


def test_a_stability_without_interval_gives_its_height_with_a_unit():
    """Stability.message restates its reason in the scene's units: 'at z_s = 15.74 cm', not the JSON's
    bare 'z_s = 0.157391'."""
    study = lev.load("thesis")
    msg = study.stability().message
    assert "at z_s = 15.74 cm the top is vertically stable" in msg and "0.157391" not in msg
    # the runtime's own sentence carries its SI unit (the JSON's, as every face shows it by default)
    from levitron.runtime.physics.stability.analysis import stability_of
    from levitron.runtime.words import in_units, render
    reason = stability_of(study.model).reason
    assert "at z_s = 0.157391 m the top is vertically stable" in in_units(reason), reason
    assert study.stability().as_json()["reason"] == render(reason, "api")
