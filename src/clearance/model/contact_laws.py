"""Normal-contact and friction laws of a clearance joint, as the user describes them.

Frozen, validated dataclasses (physics.md g, h): every field is checked when the law is
made, and an invalid value raises ModelError naming the law, the field and what is allowed.

    normal = Flores(restitution=0.9)               # stiffness from materials (Hertz, g.1)
    normal = Hertz(stiffness=1.33e11)              # K [N/m^1.5] given
    normal = NonlinearStiffness(form=1)            # g.6 reconstruction, calibrated to Hertz
    friction = LuGre(mu_c=0.05)

This module only describes: the compiled code and parameter array of a law are made by
`clearance.compile.laws.encode_normal` / `encode_friction` when a mechanism is compiled.

File boundary: NORMAL_LAWS / FRICTION_LAWS map the registry names written in scenario files,
result attributes and datasets ("flores", "lugre", ...) to the classes; `law_name(law)` and
`law_to_dict(law)` give a law's name and its {law = name, field = value} table. Files are
parsed by the scenario's law parser (`clearance.scenario.schema.parse_law`).

Adding a law: its kernel in `clearance.contact.laws` (with its code in `clearance.kinds`),
one dataclass here with its entry in NORMAL_LAWS or FRICTION_LAWS, and its encoder in
`clearance.compile.laws`. A new member of the g.2 dissipative family is only
`class MyLaw(_Dissipative)` plus its xi(c_r) line in `contact.laws.hysteresis_factor`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from clearance.model.errors import ModelError, finite_real

# ADAMS IMPACT default stiffness 1e5 N/mm^1.5 in SI (physics.md g.4, RECALLED).
ADAMS_IMPACT_STIFFNESS = 1e5 * 1e3**1.5  # 3.162e9 N/m^1.5
# Reference penetration for calibrating the Winkler modulus when neither k_f nor delta_ref
# is given (PROPOSED: the order of the Hertz delta_max of physics.md d.5, 6.2 um).
DEFAULT_DELTA_REF = 5e-6


def _real(
    owner: str,
    name: str,
    x: object,
    *,
    lo: float = -math.inf,
    lo_open: bool = True,
    hi: float = math.inf,
    allowed: str | None = None,
) -> float:
    """x as a float if it is a finite real number in (lo, hi] (or [lo, hi] with lo_open False)."""
    msg = allowed or "expected a finite real number"
    if not finite_real(x):
        raise ModelError(owner, name, x, msg)
    v = float(x)
    if (v <= lo if lo_open else v < lo) or v > hi:
        raise ModelError(owner, name, x, msg)
    return v


def _positive(owner: str, name: str, x: object) -> float:
    return _real(owner, name, x, lo=0.0, allowed="expected a finite number > 0")


def _nonneg(owner: str, name: str, x: object) -> float:
    return _real(owner, name, x, lo=0.0, lo_open=False, allowed="expected a finite number >= 0")


def _restitution(owner: str, x: object) -> float:
    return _real(owner, "restitution", x, lo=0.0, hi=1.0, allowed="expected 0 < restitution <= 1")


def _set(obj: object, name: str, value: object) -> None:
    object.__setattr__(obj, name, value)


@dataclass(frozen=True)
class Material:
    """Elastic material: Young's modulus E [Pa] and Poisson's ratio nu [-]."""

    E: float
    nu: float

    def __post_init__(self) -> None:
        _set(self, "E", _positive("Material", "E", self.E))
        _set(
            self,
            "nu",
            _real("Material", "nu", self.nu, lo=-1.0, hi=0.5, allowed="expected -1 < nu <= 0.5"),
        )


STEEL = Material(207e9, 0.3)  # physics.md g.1


# --------------------------------------------------------------------------- normal laws


@dataclass(frozen=True)
class NormalContactLaw:
    """Base of the normal contact laws."""

    def encode(
        self,
        *,
        R_ball: float,
        R_socket: float,
        ball_material: Material = STEEL,
        socket_material: Material = STEEL,
        m_eff: float | None = None,
    ) -> tuple[int, np.ndarray]:
        """Deprecated: use `clearance.compile.laws.encode_normal(law, ContactGeometry(...))`."""
        warnings.warn(
            "NormalContactLaw.encode is deprecated; use "
            "clearance.compile.laws.encode_normal(law, ContactGeometry(...))",
            DeprecationWarning,
            stacklevel=2,
        )
        from clearance.compile.laws import ContactGeometry, encode_normal  # deprecated shim

        g = ContactGeometry(R_ball, R_socket, ball_material, socket_material, m_eff)
        return encode_normal(self, g)


def _validate_power(obj: Any) -> None:
    who = type(obj).__name__
    if obj.stiffness is not None:
        _set(obj, "stiffness", _positive(who, "stiffness", obj.stiffness))
    _set(obj, "exponent", _positive(who, "exponent", obj.exponent))


@dataclass(frozen=True)
class Hertz(NormalContactLaw):
    """F_N = K delta^n, no damping (g.1, RECALLED). stiffness K [N/m^n], None = from the
    materials (internal Hertz contact); exponent n."""

    stiffness: float | None = None
    exponent: float = 1.5

    def __post_init__(self) -> None:
        _validate_power(self)


@dataclass(frozen=True)
class _Dissipative(NormalContactLaw):
    """F_N = max(0, K delta^n [1 + xi(c_r) delta_dot/delta_dot_minus]) (g.2). stiffness K
    [N/m^n] (None = internal Hertz from the materials), exponent n, restitution c_r."""

    stiffness: float | None = None
    exponent: float = 1.5
    restitution: float = 0.9

    def __post_init__(self) -> None:
        _validate_power(self)
        _set(self, "restitution", _restitution(type(self).__name__, self.restitution))


@dataclass(frozen=True)
class HuntCrossley(_Dissipative):
    """Hunt & Crossley 1975: xi = 3(1 - c_r)/2 (g.2, SOURCED)."""


@dataclass(frozen=True)
class LankaraniNikravesh(_Dissipative):
    """Lankarani & Nikravesh 1990: xi = 3(1 - c_r^2)/4 (g.2, SOURCED)."""


@dataclass(frozen=True)
class Flores(_Dissipative):
    """Flores et al. 2011: xi = 8(1 - c_r)/(5 c_r) (g.2, SOURCED; Papers A and B)."""


@dataclass(frozen=True)
class Gonthier(_Dissipative):
    """Gonthier et al. 2004: xi = (1 - c_r^2)/c_r (g.2, SOURCED)."""


@dataclass(frozen=True)
class HuGuo(_Dissipative):
    """Hu & Guo 2015: xi = 3(1 - c_r)/(2 c_r) (g.2, RECALLED; not DyS's 3(1-c_r)/(4 c_r))."""


@dataclass(frozen=True)
class HerbertMcWhannell(_Dissipative):
    """Herbert & McWhannell 1977: xi = 6(1 - c_r)/((2 c_r - 1)^2 + 3) (g.2, SOURCED)."""


@dataclass(frozen=True)
class LeeWang(_Dissipative):
    """Lee & Wang 1983: xi = 3(1 - c_r)/4 (g.2, SOURCED)."""


@dataclass(frozen=True)
class ZhiyingQishao(_Dissipative):
    """Zhiying & Qishao 2006: xi = (3/4)(1 - c_r^2) exp(2(1 - c_r)) (g.2, SOURCED)."""


@dataclass(frozen=True)
class KelvinVoigt(NormalContactLaw):
    """F_N = max(0, K_l delta + D delta_dot) (g.3; for comparison only: jumps at onset).

    stiffness K_l [N/m] (linear, required); damping D [N s/m], or None to derive it from
    restitution c_r and effective_mass [kg] (None = the m_eff given to encode, i.e. the
    reduced mass of the two bodies): D = 2 zeta sqrt(m K_l) (g.3, DERIVED).
    """

    stiffness: float
    damping: float | None = None
    restitution: float = 0.9
    effective_mass: float | None = None

    def __post_init__(self) -> None:
        who = "KelvinVoigt"
        _set(self, "stiffness", _positive(who, "stiffness", self.stiffness))
        if self.damping is not None:
            _set(self, "damping", _nonneg(who, "damping", self.damping))
        _set(self, "restitution", _restitution(who, self.restitution))
        if self.effective_mass is not None:
            _set(self, "effective_mass", _positive(who, "effective_mass", self.effective_mass))


@dataclass(frozen=True)
class Impact(NormalContactLaw):
    """ADAMS IMPACT: F_N = max(0, K delta^e + STEP(delta, 0, 0, d, cmax) delta_dot) (g.4).

    Defaults are ADAMS-like (RECALLED): stiffness 1e5 N/mm^1.5 = 3.162e9 N/m^1.5 (about 42x
    softer than the internal Hertz K for R_b = 15 mm, c = 0.3 mm; None = internal Hertz from
    the materials, for like-for-like comparisons), exponent e = 1.5, cmax = 10 N s/mm =
    1e4 N s/m, penetration_depth d = 0.1 mm = 1e-4 m.
    """

    stiffness: float | None = ADAMS_IMPACT_STIFFNESS
    exponent: float = 1.5
    cmax: float = 1e4
    penetration_depth: float = 1e-4

    def __post_init__(self) -> None:
        _validate_power(self)
        _set(self, "cmax", _nonneg("Impact", "cmax", self.cmax))
        _set(
            self,
            "penetration_depth",
            _positive("Impact", "penetration_depth", self.penetration_depth),
        )


@dataclass(frozen=True)
class NonlinearStiffness(NormalContactLaw):
    """Winkler-foundation law of the conformal ball in socket (g.6, DERIVED reconstruction
    of Paper A; both forms use the Flores hysteresis factor).

    form 1 (PROPOSED default): F_N = F_el(delta) [1 + xi ...];
    form 2 ("stiffness swap", not homogeneous): F_N = K_n(delta) delta^1.5 [1 + xi ...].
    k_f: Winkler modulus [N/m^3]; None = calibrate (PROPOSED) so that the form's elastic
    force equals stiffness * delta_ref^1.5 at delta_ref [m] (default 5e-6 m), stiffness
    [N/m^1.5] defaulting to the internal Hertz K (see `clearance.compile.calibration.winkler_kf`).
    The foundation radius R is the ball radius (the reconstruction is O(c/R) anyway).
    """

    form: int = 1
    restitution: float = 0.9
    k_f: float | None = None
    delta_ref: float | None = None
    stiffness: float | None = None

    def __post_init__(self) -> None:
        who = "NonlinearStiffness"
        if isinstance(self.form, bool) or self.form not in (1, 2):
            raise ModelError(who, "form", self.form, "expected 1 or 2")
        _set(self, "form", int(self.form))
        _set(self, "restitution", _restitution(who, self.restitution))
        if self.k_f is not None:
            _set(self, "k_f", _positive(who, "k_f", self.k_f))
            for name in ("delta_ref", "stiffness"):
                if getattr(self, name) is not None:
                    raise ModelError(
                        who,
                        name,
                        getattr(self, name),
                        "only used to calibrate k_f; leave it None when k_f is given",
                    )
        for name in ("delta_ref", "stiffness"):
            if getattr(self, name) is not None:
                _set(self, name, _positive(who, name, getattr(self, name)))


#: the g.2 family members whose hysteresis factor xi(c_r) a line-contact law may use
DAMPING_FACTORS = (
    "none",
    "hunt_crossley",
    "lankarani_nikravesh",
    "flores",
    "gonthier",
    "hu_guo",
    "herbert_mcwhannell",
    "lee_wang",
    "zhiying_qishao",
)


@dataclass(frozen=True)
class _LineLaw(NormalContactLaw):
    """A line-contact law of a journal in its bearing: the elastic line load per unit length
    q(delta) of the radial clearance dR and the combined modulus E*, times the bearing length
    L, with the hysteresis damping [1 + xi delta_dot / delta_dot_minus] of the g.2 family
    member named by `damping` ("none": elastic). modulus: E* [Pa] (None: from the journal
    and bearing materials, 1/E* = sum (1 - nu^2)/E). Only in a RevoluteClearance with a
    length (docs/clearance-joints.md)."""

    restitution: float = 0.9
    damping: str = "lankarani_nikravesh"
    modulus: float | None = None

    def __post_init__(self) -> None:
        who = type(self).__name__
        _set(self, "restitution", _restitution(who, self.restitution))
        if self.damping not in DAMPING_FACTORS:
            raise ModelError(who, "damping", self.damping, f"allowed: {', '.join(DAMPING_FACTORS)}")
        if self.modulus is not None:
            _set(self, "modulus", _positive(who, "modulus", self.modulus))


@dataclass(frozen=True)
class Johnson(_LineLaw):
    """Johnson's internal-cylinder law (Johnson 1985, "Contact Mechanics", ESDU 78035):
    delta = (q/(pi E*)) [ln(4 pi E* dR / q) - 1], solved exactly for q (SOURCED form as used
    by Pereira et al. 2011; explicit solution DERIVED). Valid for delta < 0.54 dR."""


@dataclass(frozen=True)
class Pereira(_LineLaw):
    """Pereira, Ramalho & Ambrosio (2011), internal contact: F = (a dR + b)/dR L E*
    delta^n with a = 0.965, b = 0.0965, n = Y dR^-0.005 and Y piecewise in dR, the fitted
    constants in mm, N and MPa (converted to SI exactly; SOURCED constants, unit convention
    DERIVED: docs/clearance-joints.md). Valid for 0.005 mm <= dR <= 10 mm."""


@dataclass(frozen=True)
class Liu(_LineLaw):
    """Liu, Zhang & Yang (2007): q = (pi/2) E* delta sqrt(delta / (2 (dR + delta)))
    (SOURCED as implemented in the DyS code; E* the combined modulus)."""


# --------------------------------------------------------------------------- friction laws


@dataclass(frozen=True)
class FrictionContactLaw:
    """Base of the friction laws."""

    def encode(self) -> tuple[int, np.ndarray]:
        """Deprecated: use `clearance.compile.laws.encode_friction(law)`."""
        warnings.warn(
            "FrictionContactLaw.encode is deprecated; use clearance.compile.laws.encode_friction",
            DeprecationWarning,
            stacklevel=2,
        )
        from clearance.compile.laws import encode_friction  # deprecated shim

        return encode_friction(self)


@dataclass(frozen=True)
class NoFriction(FrictionContactLaw):
    """Frictionless contact."""


@dataclass(frozen=True)
class Coulomb(FrictionContactLaw):
    """F_T = mu c_d(|v_t|) F_N with Ambrosio's dynamic correction (h.1, RECALLED).

    c_d ramps from 0 at v0 to 1 at v1 [m/s]: ramp "linear" (Flores default) or "cubic"
    (c_d = STEP(|v_t|, v0, 0, v1, 1)). No stiction: zero friction below v0.
    """

    mu: float = 0.1
    v0: float = 1e-4
    v1: float = 1e-3
    ramp: str = "linear"

    def __post_init__(self) -> None:
        _set(self, "mu", _nonneg("Coulomb", "mu", self.mu))
        _set(self, "v0", _nonneg("Coulomb", "v0", self.v0))
        _set(
            self,
            "v1",
            _real("Coulomb", "v1", self.v1, lo=self.v0, allowed=f"must exceed v0 = {self.v0} m/s"),
        )
        if self.ramp not in ("linear", "cubic"):
            raise ModelError("Coulomb", "ramp", self.ramp, "expected 'linear' or 'cubic'")


@dataclass(frozen=True)
class Threlfall(FrictionContactLaw):
    """F_T = mu F_N (1 - exp(-3|v_t|/v0)) up to v0, mu F_N above (h.2, RECALLED, verify)."""

    mu: float = 0.1
    v0: float = 1e-3

    def __post_init__(self) -> None:
        _set(self, "mu", _nonneg("Threlfall", "mu", self.mu))
        _set(self, "v0", _positive("Threlfall", "v0", self.v0))


@dataclass(frozen=True)
class Stribeck(FrictionContactLaw):
    """ADAMS-style stiction: mu(v) = STEP(v, -v_s, -1, v_s, 1) STEP(v, v_s, mu_s, v_tr, mu_d)
    at v = |v_t| (h.3, SOURCED form; defaults PROPOSED, h.5)."""

    mu_s: float = 0.15
    mu_d: float = 0.1
    v_s: float = 1e-3
    v_tr: float = 1e-2

    def __post_init__(self) -> None:
        _set(self, "mu_s", _nonneg("Stribeck", "mu_s", self.mu_s))
        _set(self, "mu_d", _nonneg("Stribeck", "mu_d", self.mu_d))
        if self.mu_s < self.mu_d:
            raise ModelError(
                "Stribeck",
                "mu_s",
                self.mu_s,
                f"expected mu_s >= mu_d = {self.mu_d} (static >= dynamic)",
            )
        _set(self, "v_s", _positive("Stribeck", "v_s", self.v_s))
        _set(
            self,
            "v_tr",
            _real(
                "Stribeck",
                "v_tr",
                self.v_tr,
                lo=self.v_s,
                allowed=f"must exceed v_s = {self.v_s} m/s",
            ),
        )


@dataclass(frozen=True)
class LuGre(FrictionContactLaw):
    """LuGre normalised by F_N (h.4): sigma0 [1/m], sigma1 [s/m], sigma2 [s/m] (SOURCED:
    Canudas de Wit 1995 Table I), mu_c, mu_s (PROPOSED), Stribeck speed v_s [m/s] (SOURCED).

    velocity_damping True (PROPOSED default): sigma1(v) = sigma1 exp(-(v/v_d)^2), v_d [m/s]
    (None = v_s), which removes the onset impulse of h.4; False: constant sigma1 (papers).
    """

    sigma0: float = 1e5
    sigma1: float = 316.0
    sigma2: float = 0.4
    mu_c: float = 0.1
    mu_s: float = 0.15
    v_s: float = 1e-3
    velocity_damping: bool = True
    v_d: float | None = None

    def __post_init__(self) -> None:
        _set(self, "sigma0", _positive("LuGre", "sigma0", self.sigma0))
        for name in ("sigma1", "sigma2"):
            _set(self, name, _nonneg("LuGre", name, getattr(self, name)))
        # g(v) >= min(mu_c, mu_s) divides z_dot: both must be > 0
        for name in ("mu_c", "mu_s", "v_s"):
            _set(self, name, _positive("LuGre", name, getattr(self, name)))
        if self.mu_s < self.mu_c:
            raise ModelError(
                "LuGre",
                "mu_s",
                self.mu_s,
                f"expected mu_s >= mu_c = {self.mu_c} (static >= Coulomb)",
            )
        if not isinstance(self.velocity_damping, bool):
            raise ModelError(
                "LuGre", "velocity_damping", self.velocity_damping, "expected True or False"
            )
        if self.v_d is not None:
            _set(self, "v_d", _positive("LuGre", "v_d", self.v_d))


# --------------------------------------------------------------------------- file boundary

NORMAL_LAWS: dict[str, type[NormalContactLaw]] = {
    "hertz": Hertz,
    "kelvin_voigt": KelvinVoigt,
    "hunt_crossley": HuntCrossley,
    "lankarani_nikravesh": LankaraniNikravesh,
    "flores": Flores,
    "gonthier": Gonthier,
    "hu_guo": HuGuo,
    "herbert_mcwhannell": HerbertMcWhannell,
    "lee_wang": LeeWang,
    "zhiying_qishao": ZhiyingQishao,
    "impact": Impact,
    "nonlinear_stiffness": NonlinearStiffness,
    "johnson": Johnson,
    "pereira": Pereira,
    "liu": Liu,
}

FRICTION_LAWS: dict[str, type[FrictionContactLaw]] = {
    "none": NoFriction,
    "coulomb": Coulomb,
    "threlfall": Threlfall,
    "stribeck": Stribeck,
    "lugre": LuGre,
}


def _parse(d: object, kind: str):
    warnings.warn(
        f"{kind}_law_from_dict is deprecated; use clearance.scenario.schema.parse_law",
        DeprecationWarning,
        stacklevel=3,
    )
    from clearance.scenario.schema import parse_law  # deprecated shim

    return parse_law(d, kind)


def normal_law_from_dict(d: dict) -> NormalContactLaw:
    """Deprecated: `clearance.scenario.schema.parse_law(d, "normal")`."""
    return _parse(d, "normal")


def friction_law_from_dict(d: dict) -> FrictionContactLaw:
    """Deprecated: `clearance.scenario.schema.parse_law(d, "friction")`."""
    return _parse(d, "friction")


def law_name(law: NormalContactLaw | FrictionContactLaw) -> str:
    """The registry name of a law ("flores", "lugre", ...): the spelling of files and datasets."""
    for table in (NORMAL_LAWS, FRICTION_LAWS):
        for name, cls in table.items():
            if type(law) is cls:
                return name
    raise ModelError("law_name", "law", law, "expected a registered contact or friction law")


def law_to_dict(law: NormalContactLaw | FrictionContactLaw) -> dict:
    """The table of a law as written in files: {"law": name, field: value, ...}."""
    out: dict = {"law": law_name(law)}
    out.update({f.name: getattr(law, f.name) for f in dataclasses.fields(law)})
    return out
