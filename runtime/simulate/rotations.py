"""The top's orientation in numpy: the elementary rotations of thesis eqs. 2.1.6-2.1.8 (z-x-z) and
3.2.3-3.2.5 (Tait-Bryan), R_bs and its derivatives, the generator of a rotation about the lab z
axis, and the angles of a tilted axis. Mirrors of derive/kinematics.py, checked against the
generated `full_axis` at random angles (tests/derive/test_invariants.py)."""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def _ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])


ANGLES = {"tait-bryan": ("phi", "vartheta", "zeta"), "euler-zxz": ("phi", "theta", "psi")}


SPIN_ANGLE = {"tait-bryan": "zeta", "euler-zxz": "psi"}


TILT_ANGLE = {"tait-bryan": "phi", "euler-zxz": "theta"}


def coordinates_of(part) -> str | None:
    """"tait-bryan", "euler-zxz" (full models) or None (the reduced model)."""
    names = set(part.states)
    for name, angles in ANGLES.items():
        if set(angles) <= names:
            return name
    return None


def _drx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[0, 0, 0], [0, -s, c], [0, -c, -s]])


def _dry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[-s, 0, c], [0, 0, 0], [-c, 0, -s]])


def _drz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[-s, c, 0], [-c, -s, 0], [0, 0, 0]])


def _factors(coords: str, angles: Sequence[float]):
    """R_bs as a product of three elementary matrices (and their derivatives), in order."""
    a, b, c = angles
    if coords == "tait-bryan":       # Rx(phi) Ry(vartheta) Rz(zeta)
        return [(_rx(a), _drx(a)), (_ry(b), _dry(b)), (_rz(c), _drz(c))]
    # (R3(psi) R2(theta) R1(phi))^T = R1(phi)^T R2(theta)^T R3(psi)^T
    return [(_rz(a).T, _drz(a).T), (_rx(b).T, _drx(b).T), (_rz(c).T, _drz(c).T)]


def rotation_bs(coords: str, angles: Sequence[float]) -> np.ndarray:
    """Body -> space rotation: Rx(phi) Ry(vartheta) Rz(zeta) (thesis 3.2.2), or
    (R3(psi) R2(theta) R1(phi))^T (thesis 2.1.9)."""
    f = _factors(coords, angles)
    return f[0][0] @ f[1][0] @ f[2][0]


def rotation_bs_derivatives(coords: str, angles: Sequence[float]) -> list[np.ndarray]:
    """d R_bs / d angle_i, analytic (product rule)."""
    f = _factors(coords, angles)
    return [f[0][1] @ f[1][0] @ f[2][0], f[0][0] @ f[1][1] @ f[2][0], f[0][0] @ f[1][0] @ f[2][1]]


def body_rate_matrix(kind: str, angles: Sequence[float]) -> np.ndarray:
    """J with omega_body = J angle_rates, column i = vee(R_bs^T dR_bs/d angle_i) (thesis eqs.
    2.1.10, 3.2.7-3.2.9; derive/kinematics.py body_angular_velocity)."""
    R = rotation_bs(kind, angles)
    cols = []
    for dR in rotation_bs_derivatives(kind, angles):
        W = R.T @ dR
        cols.append([W[2, 1], W[0, 2], W[1, 0]])
    return np.array(cols).T


def angle_generator_z(coords: str, angles: Sequence[float]) -> np.ndarray:
    """d angles / d alpha under R_bs -> Q_z(alpha) R_bs (active rotation about the lab z axis):
    least squares of dR = sum_i dR/da_i da_i = K R, K = [[0,-1,0],[1,0,0],[0,0,0]]."""
    ang = np.asarray(angles, float)
    R = rotation_bs(coords, ang)
    K = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    cols = [d.ravel() for d in rotation_bs_derivatives(coords, ang)]
    sol, *_ = np.linalg.lstsq(np.array(cols).T, (K @ R).ravel(), rcond=None)
    return sol


DEFAULT_AZIMUTH = math.pi / 2    # the tilt towards +y


def tilt_angles(kind: str, tilt: float, azimuth: float = DEFAULT_AZIMUTH) -> list[float]:
    """The three angles whose body axis is n = (sin tilt cos az, sin tilt sin az, cos tilt), with
    no rotation about n (module docstring)."""
    if kind == "tait-bryan":     # n = (sin vartheta, sin phi cos vartheta, cos phi cos vartheta)
        return [math.atan2(math.sin(tilt) * math.sin(azimuth), math.cos(tilt)),
                math.asin(math.sin(tilt) * math.cos(azimuth)), 0.0]
    return [azimuth + math.pi / 2, tilt, 0.0]    # n = (sin phi sin theta, -cos phi sin theta, cos theta)
