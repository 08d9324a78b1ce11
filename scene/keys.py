"""The scene's vocabulary: the keys of every section but [plate], and the words they take.

Pure Python (no sympy). scene/load.py checks a scene against these tables; docs/scenes.md is
generated from them and the plate registry (`python -m levitron.scene.plates.docs`); the runtime
reads them where it names a key (the report's tables, the air friction's rates).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .plates.base import Key

NEEDS = ("reduced", "full", "linear")
COORDINATES = ("tait-bryan", "euler-zxz")
UNITS = ("SI", "dimensionless")
T_REF = 20.0            # degC: the reference temperature of the temperature coefficients
ABSOLUTE_ZERO = -273.15

# The keys of every section but [plate] (whose keys are the plate kinds', scene/plates/); the
# contract docs/scenes.md is generated from these and the registry (`python -m levitron.scene.plates.docs`).
SCENE_KEYS = (
    Key("name", "", "the scene's name (letters, digits, '-', '_'; default: the file's stem)"),
    Key("description", "", "free text"),
    Key("g", "m/s^2", "gravity (default 9.81; 1 in a dimensionless scene)"),
    Key("temperature", "degC", f"the temperature of the magnets (default {T_REF:g} degC, the "
        "reference of the temperature coefficients; `--temperature` on every command)"),
    Key("units", "", f"how numbers are shown to a person, one of {list(UNITS)} (default: \"SI\" "
        "when 9 <= g <= 10.5, else \"dimensionless\"); never how they are computed"),
)
REFERENCE_KEYS = (
    Key("source", "", "where the stated values come from (e.g. \"thesis\"), shown beside them"),
    Key("z_stable", "m", "a stated height of the vertically stable equilibrium, shown beside ours "
        "(a number, or [value, uncertainty])"),
    Key("spin_interval", "rad/s", "a stated spin interval of stability, [low, high]"),
    Key("mass_window", "kg", "a stated range of masses that hover, [lightest, heaviest]"),
    Key("flight_time", "s", "a stated flight time in air (a number, or [value, uncertainty])"),
)
TEMPERATURE_KEY = Key("temperature_coefficient", "1/K", "relative change of the magnet's "
                      "remanence per kelvin from 20 degC (ferrite about -0.002, NdFeB about -0.0012; "
                      "default 0); in [top] and in [plate]")
TOP_KEYS = (
    Key("mass", "kg", "mass m of the top"),
    Key("A", "kg m^2", "transverse moment of inertia"),
    Key("C", "kg m^2", "axial moment of inertia (C <= 2 A)"),
    Key("moment", "A m^2", "magnetic moment mu along the symmetry axis, signed (mu < 0: upright "
        "over a field that points up); may be left out with plate.murho"),
    Key("spin_decay_time", "s", "air friction: the e-folding time tau of the spin of a free top, "
        "omega_3(t) = omega_3(0) exp(-t / tau) (measure it with a tachometer); any decay time makes "
        "the full model dissipative (derive/friction.py)"),
    Key("tilt_decay_time", "s", "air friction: the e-folding time of the transverse (tumbling) "
        "angular velocity of a free top (default: none)"),
    Key("translation_decay_time", "s", "air friction: the e-folding time of the velocity of the "
        "centre of mass of a free top (default: none)"),
    TEMPERATURE_KEY,
    Key("moment_offset", "m", "the magnet's centre along the symmetry axis from the centre of mass "
        "(positive towards the moment's end of the axis n; default: none, the magnet at the centre "
        "of mass): the moment feels the field at r + d n (derive/mechanics.py); the scene then "
        "has no reduced model"),
    Key("moment_tilt", "rad", "the angle b between the magnetic moment and the symmetry axis, the "
        "moment fixed in the body (it turns with the spin): mu (cos b n + sin b e1), e1 the body's "
        "first transverse axis (derive/mechanics.py; default: none, the moment along the axis); the "
        "steady motion is then periodic (runtime/physics/apparatus/multipliers.py) and the scene has no reduced "
        "model"),
)

# The base's tilt: keys of [plate] that every plate kind takes; they put gravity along a
# tilted vector in the full model (derive/mechanics.py), as runtime parameters base_tilt and
# base_tilt_azimuth (their values never change the generated code; their presence does).
TILT_KEYS = (
    Key("tilt", "rad", "the base's tilt from level (0 <= tilt < pi/2): gravity in the plate's frame is "
        "g (sin tilt cos az, sin tilt sin az, -cos tilt), az = tilt_azimuth; breaks the axial "
        "symmetry, so the scene has no reduced model (derive/mechanics.py)"),
    Key("tilt_azimuth", "rad", "the downhill direction in the plate's frame, from +x towards +y "
        "(default 0: downhill is +x, the base tilted about the y axis); needs tilt"),
)
TILT_PARAMS = {"tilt": "base_tilt", "tilt_azimuth": "base_tilt_azimuth"}


@dataclass(frozen=True)
class Bound:
    """The values a scene key takes, lo to hi (each end open or closed), read as `text`: the one
    statement a key's value (scene/load.py) and a launch spread of the key (runtime/scan/spreads.py,
    its whole support) are both checked against. `mirrored`: the bound of |value| (a launch's base
    tilt of -t is the tilt t downhill the other way)."""
    lo: float
    hi: float
    lo_open: bool = False
    hi_open: bool = False
    text: str = ""

    def admits(self, value: float) -> bool:
        return ((self.lo < value if self.lo_open else self.lo <= value)
                and (value < self.hi if self.hi_open else value <= self.hi))

    def first_outside(self, lo: float, hi: float) -> float | None:
        """The end of [lo, hi] that the bound does not admit (lo first), or None if it admits both."""
        return next((v for v in (lo, hi) if not self.admits(v)), None)

    def mirrored(self, text: str) -> Bound:
        """The bound of a signed value whose size this bound limits: |value| in [lo, hi)."""
        return Bound(-self.hi, self.hi, self.hi_open, self.hi_open, text)


# keys with bounds beyond finiteness and size (scene/checks.py number): "section.key" -> Bound
KEY_BOUNDS = {
    "plate.tilt": Bound(0.0, math.pi / 2, hi_open=True, text="0 <= tilt < pi/2"),
    "top.moment_tilt": Bound(-math.pi / 2, math.pi / 2, True, True, "|moment_tilt| < pi/2"),
}

# decay-time key of [top] -> the runtime parameter it sets, the rate 1 / tau (0 where not given)
FRICTION_KEYS = {"spin_decay_time": "k_spin", "tilt_decay_time": "k_tilt",
                 "translation_decay_time": "k_trans"}
FIELD_KEYS = (
    Key("order", "", "even order in r of the Laplace expansion, 2..12 (default 2)"),
    Key("tolerance", "", "instead of order: the largest relative error of the expanded field, "
        "with radius"),
    Key("radius", "m", "the distance from the axis within which tolerance must hold"),
)
LAUNCH_KEYS = tuple(Key(k, u, d) for k, u, d in (
    ("spin", "rad/s", "the launch spin: \"normal:MEAN,SD\", \"uniform:LO,HI\" or a number"),
    ("tilt", "rad", "the tilt of the axis (same forms)"),
    ("tilt_azimuth", "rad", "the direction of the tilt (same forms)"),
    ("offset", "m", "the offset of the centre of mass along x (same forms)"),
    ("velocity", "m/s", "the horizontal velocity along y (same forms)"),
    ("mass", "", "the relative deviation of the mass (same forms)"),
    ("strength", "", "the relative deviation of the magnets' strength (same forms)"),
    ("temperature", "degC", "the magnets' temperature (same forms)"),
    ("base_tilt", "rad", "the base's tilt from level, sampled per launch (same forms; needs plate.tilt)"),
    ("base_tilt_azimuth", "rad", "the base's downhill direction, sampled per launch (same forms; "
     "needs plate.tilt)"),
    ("moment_tilt", "rad", "the magnet's tilt from the top's axis, sampled per launch (same forms; needs "
     "top.moment_tilt)"),
    ("success_time", "s", "a launch succeeds when the top floats at least this long"),
    ("t_end", "s", "the run length of each launch"),
    ("n", "", "the number of launches"),
    ("seed", "", "the seed of the sampler"),
))
PRODUCTION_KEYS = tuple(Key(k, u, d) for k, u, d in (
    ("kit", "", "the kits' manufacturing spread, a table: strength and mass relative (\"rel:normal:0,0.02\"), "
     "any scene key that is a model parameter as a deviation (plate.thickness = \"abs:normal:0,0.0002\", "
     "plate.remanence = \"rel:normal:0,0.02\"); default strength 2 %, mass 0.3 %"),
    ("washers", "kg", "the washers in each box, a list of masses (default none)"),
    ("kits", "", "the kits of the production run, one launch each (default 300)"),
))
MODEL_KEYS = (
    Key("needs", "", f"what derive emits, a list drawn from {list(NEEDS)} (default all; "
        "\"linear\" needs \"full\")"),
    Key("coordinates", "", f"angles of the full model, one of {list(COORDINATES)} (default "
        "\"tait-bryan\", regular at the upright top; \"euler-zxz\" as in the thesis)"),
)
TILT_KEYS_NAMES = tuple(k.name for k in TILT_KEYS)
