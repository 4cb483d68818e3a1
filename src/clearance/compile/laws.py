"""Encode contact laws for the compiled kernels: a law description -> (code, par).

The model (`clearance.model.contact_laws`) describes a law by its parameters; here it
becomes the integer code of `clearance.kinds.NormalLaw` / `FrictionLaw` and the float64
parameter array `par` (NPAR,) laid out as in `clearance.contact.laws`. Parameters that
depend on the joint (the Hertz stiffness from the radii and materials, Kelvin-Voigt damping
from the effective mass, the Winkler modulus) are computed from a `ContactGeometry`.

    code, par = encode_normal(Flores(restitution=0.9), ContactGeometry(0.015, 0.0153))
    code, par = encode_friction(LuGre())

Adding a law: its kernel in `clearance.contact.laws` (code in `clearance.kinds`), its
dataclass and registry name in `clearance.model.contact_laws`, and one encoder here
(`_NORMAL` / `_FRICTION`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from clearance.compile.calibration import (
    effective_modulus,
    hertz_stiffness,
    kelvin_voigt_damping,
    winkler_kf,
)
from clearance.contact.laws import hysteresis_factor
from clearance.kinds import NPAR, FrictionLaw, NormalLaw
from clearance.model.contact_laws import (
    DEFAULT_DELTA_REF,
    NORMAL_LAWS,
    STEEL,
    Coulomb,
    Flores,
    FrictionContactLaw,
    Gonthier,
    HerbertMcWhannell,
    Hertz,
    HuGuo,
    HuntCrossley,
    Impact,
    Johnson,
    KelvinVoigt,
    LankaraniNikravesh,
    LeeWang,
    Liu,
    LuGre,
    Material,
    NoFriction,
    NonlinearStiffness,
    NormalContactLaw,
    Pereira,
    Stribeck,
    Threlfall,
    ZhiyingQishao,
    law_name,
)
from clearance.model.errors import ModelError

__all__ = ["ContactGeometry", "encode_friction", "encode_normal", "friction_code", "normal_code"]


@dataclass(frozen=True)
class ContactGeometry:
    """What a normal law may need from its joint.

    R_inner / R_outer: radii of the inner body (ball, journal) and of the outer surface
    (socket, bearing) [m], R_outer > R_inner (internal, conformal contact); the internal
    Hertz stiffness (physics.md g.1) is computed from them and the materials when a law's
    stiffness is None. m_eff: effective mass of the two bodies [kg] (Kelvin-Voigt damping
    from the restitution), None if unknown.
    """

    R_inner: float
    R_outer: float
    inner_material: Material = STEEL
    outer_material: Material = STEEL
    m_eff: float | None = None
    length: float | None = None  # contact length of a journal [m] (line-contact laws)


def _pack(*values: float) -> np.ndarray:
    par = np.zeros(NPAR, dtype=np.float64)
    par[: len(values)] = values
    return par


def _stiffness(law: NormalContactLaw, g: ContactGeometry) -> float:
    """The law's stiffness, or the internal Hertz K of physics.md g.1 from the geometry."""
    k = getattr(law, "stiffness", None)
    if k is not None:
        return float(k)
    a, b = _materials(law, g)
    return hertz_stiffness(a.E, a.nu, b.E, b.nu, g.R_inner, g.R_outer)


def _materials(law, g: ContactGeometry) -> tuple[Material, Material]:
    """(inner, outer) materials of the geometry, checked."""
    for name, m in (("ball_material", g.inner_material), ("socket_material", g.outer_material)):
        if not isinstance(m, Material):
            raise ModelError(type(law).__name__, name, m, "expected a Material(E, nu)")
    return g.inner_material, g.outer_material


def _hertz(law: Hertz, g: ContactGeometry) -> np.ndarray:
    return _pack(_stiffness(law, g), law.exponent)


def _dissipative(law, g: ContactGeometry) -> np.ndarray:
    return _pack(_stiffness(law, g), law.exponent, law.restitution)


def _kelvin_voigt(law: KelvinVoigt, g: ContactGeometry) -> np.ndarray:
    if law.damping is not None:
        return _pack(law.stiffness, law.damping)
    m = law.effective_mass if law.effective_mass is not None else g.m_eff
    if m is None or not (math.isfinite(m) and m > 0.0):
        raise ModelError(
            "KelvinVoigt",
            "effective_mass",
            m,
            "give damping, or a finite effective_mass > 0 for the "
            "restitution-based damping (physics.md g.3)",
        )
    return _pack(law.stiffness, kelvin_voigt_damping(law.stiffness, m, law.restitution))


def _impact(law: Impact, g: ContactGeometry) -> np.ndarray:
    return _pack(_stiffness(law, g), law.exponent, law.cmax, law.penetration_depth)


def _winkler(law: NonlinearStiffness, g: ContactGeometry) -> np.ndarray:
    k_f = law.k_f
    if k_f is None:
        k = _stiffness(law, g)
        d_ref = law.delta_ref if law.delta_ref is not None else DEFAULT_DELTA_REF
        k_f = winkler_kf(k, g.R_inner, g.R_outer - g.R_inner, d_ref, form=law.form)
    return _pack(k_f, g.R_inner, law.restitution)


def _modulus(law, g: ContactGeometry) -> float:
    """E* [Pa]: the law's modulus or 1/E* = sum (1 - nu^2)/E of the two materials."""
    if law.modulus is not None:
        return float(law.modulus)
    a, b = _materials(law, g)
    return effective_modulus(a.E, a.nu, b.E, b.nu)


def _line(law, g: ContactGeometry) -> tuple[float, float, float, float]:
    """(E*, dR, L, xi) of a line-contact law in a journal geometry."""
    who = type(law).__name__
    if g.length is None or not math.isfinite(g.R_outer):
        raise ModelError(
            who,
            "law",
            law_name(law),
            "a line-contact law needs a journal in a bearing of given length "
            "(RevoluteClearance with length=...)",
        )
    xi = 0.0
    if law.damping != "none":  # the factor of that g.2 law (a default instance gives its code)
        xi = hysteresis_factor(int(normal_code(NORMAL_LAWS[law.damping]())), law.restitution)
    return _modulus(law, g), g.R_outer - g.R_inner, float(g.length), float(xi)


def _pereira(law: Pereira, g: ContactGeometry) -> np.ndarray:
    """Pereira et al. (2011), internal contact, in SI: the fitted constants hold in mm, N and
    MPa, so F = (a dR_mm + b)/dR_mm L E* delta^n 10^(3 (n - 1)) (DERIVED from the unit
    convention that reproduces Johnson's law, docs/clearance-joints.md)."""
    Es, dR, L, xi = _line(law, g)
    d = 1000.0 * dR  # mm
    if not 0.005 <= d <= 10.0:
        raise ModelError("Pereira", "radial_clearance", dR, "the fit covers 0.005 mm <= c <= 10 mm")
    Y = 1.51 * math.log(1000.0 * d) ** -0.151 if d < 0.34954 else 0.0151 * d + 1.151
    n = Y * d**-0.005
    K = (0.965 * d + 0.0965) / d * L * Es * 10.0 ** (3.0 * (n - 1.0))
    return _pack(K, n, xi)


# law class -> (code or code function, parameter encoder)
_NORMAL: dict[type, tuple[Callable, Callable]] = {
    Hertz: (lambda law: NormalLaw.HERTZ, _hertz),
    KelvinVoigt: (lambda law: NormalLaw.KELVIN_VOIGT, _kelvin_voigt),
    HuntCrossley: (lambda law: NormalLaw.HUNT_CROSSLEY, _dissipative),
    LankaraniNikravesh: (lambda law: NormalLaw.LANKARANI_NIKRAVESH, _dissipative),
    Flores: (lambda law: NormalLaw.FLORES, _dissipative),
    Gonthier: (lambda law: NormalLaw.GONTHIER, _dissipative),
    HuGuo: (lambda law: NormalLaw.HU_GUO, _dissipative),
    HerbertMcWhannell: (lambda law: NormalLaw.HERBERT_MCWHANNELL, _dissipative),
    LeeWang: (lambda law: NormalLaw.LEE_WANG, _dissipative),
    ZhiyingQishao: (lambda law: NormalLaw.ZHIYING_QISHAO, _dissipative),
    Impact: (lambda law: NormalLaw.IMPACT, _impact),
    NonlinearStiffness: (
        lambda law: NormalLaw.WINKLER_FORM1 if law.form == 1 else NormalLaw.WINKLER_FORM2,
        _winkler,
    ),
    Pereira: (lambda law: NormalLaw.POWER, _pereira),
    Johnson: (lambda law: NormalLaw.JOHNSON, lambda law, g: _pack(*_line(law, g))),
    Liu: (lambda law: NormalLaw.LIU, lambda law, g: _pack(*_line(law, g))),
}

_FRICTION: dict[type, tuple[Callable, Callable]] = {
    NoFriction: (lambda law: FrictionLaw.NONE, lambda law: _pack()),
    Coulomb: (
        lambda law: FrictionLaw.COULOMB if law.ramp == "linear" else FrictionLaw.COULOMB_SMOOTH,
        lambda law: _pack(law.mu, law.v0, law.v1),
    ),
    Threlfall: (lambda law: FrictionLaw.THRELFALL, lambda law: _pack(law.mu, law.v0)),
    Stribeck: (
        lambda law: FrictionLaw.STRIBECK,
        lambda law: _pack(law.mu_s, law.mu_d, law.v_s, law.v_tr),
    ),
    LuGre: (
        lambda law: FrictionLaw.LUGRE,
        lambda law: _pack(
            law.sigma0,
            law.sigma1,
            law.sigma2,
            law.mu_c,
            law.mu_s,
            law.v_s,
            law.v_s if law.v_d is None else law.v_d,
            1.0 if law.velocity_damping else 0.0,
        ),
    ),
}


def _entry(table: dict, law: object, base: type, what: str) -> tuple[Callable, Callable]:
    entry = table.get(type(law))
    if entry is None or not isinstance(law, base):
        raise ModelError("encode", "law", law, f"expected a registered {what} law")
    return entry


def normal_code(law: NormalContactLaw) -> NormalLaw:
    """The compiled code of a normal law."""
    return _entry(_NORMAL, law, NormalContactLaw, "normal contact")[0](law)


def friction_code(law: FrictionContactLaw) -> FrictionLaw:
    """The compiled code of a friction law."""
    return _entry(_FRICTION, law, FrictionContactLaw, "friction")[0](law)


def encode_normal(law: NormalContactLaw, geometry: ContactGeometry) -> tuple[int, np.ndarray]:
    """(NormalLaw code, par (NPAR,)) of `law` in a joint of the given geometry."""
    code, par = _entry(_NORMAL, law, NormalContactLaw, "normal contact")
    who = type(law).__name__
    if not (math.isfinite(geometry.R_inner) and geometry.R_inner > 0.0):
        raise ModelError(who, "R_ball", geometry.R_inner, "expected a finite radius > 0")
    if not geometry.R_outer > geometry.R_inner:
        raise ModelError(
            who, "R_socket", geometry.R_outer, f"must exceed R_ball = {geometry.R_inner} m"
        )
    return int(code(law)), par(law, geometry)


def encode_friction(law: FrictionContactLaw) -> tuple[int, np.ndarray]:
    """(FrictionLaw code, par (NPAR,)) of `law`."""
    code, par = _entry(_FRICTION, law, FrictionContactLaw, "friction")
    return int(code(law)), par(law)
