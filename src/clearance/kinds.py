"""Every kind code, slot constant, array size and status code of the package, in one place.

The describe layer (`clearance.model`) names things with these enums, compile encodes them
into the kernel arrays, the compiled kernels dispatch on them (numba freezes module-level
ints and IntEnum members as compile-time constants), and the storage layer labels its
output with them. Nothing else defines a code: a new joint, primitive, law or status is one
line here plus its implementation.

Strings appear only at the file boundary (`clearance.scenario`, datasets): the registry
names of the laws and clearance kinds below are the ones written in scenario files, result
attributes and datasets alike.
"""

from __future__ import annotations

from enum import IntEnum

# --------------------------------------------------------------------------- joints


class JointType(IntEnum):
    """Ideal joint kinds (physics.md c.3)."""

    SPHERICAL = 0
    UNIVERSAL = 1
    REVOLUTE = 2
    CYLINDRICAL = 3
    PRISMATIC = 4
    FIXED = 5


#: constraint rows of each ideal joint (Newton-Euler velocity form)
JOINT_ROWS = {
    JointType.SPHERICAL: 3,
    JointType.UNIVERSAL: 4,
    JointType.REVOLUTE: 5,
    JointType.CYLINDRICAL: 4,
    JointType.PRISMATIC: 5,
    JointType.FIXED: 6,
}


class DriverType(IntEnum):
    PRISMATIC = 0
    DISTANCE = 1
    POSITION = 2
    ORIENTATION = 3
    OFFSET = 4
    REVOLUTE = 5


class ForceType(IntEnum):
    POINT_FORCE = 0
    TORQUE = 1
    SPRING_DAMPER = 2


# --------------------------------------------------------------------------- time functions


class FnKind(IntEnum):
    """Kind codes of encoded functions; the data layout of each is given in brackets."""

    CONSTANT = 0  # [value]
    POLYNOMIAL = 1  # [t0, c_0, c_1, ..., c_n]
    SINUSOID = 2  # [amplitude, omega, phase, offset]
    RAMP = 3  # [start_value, end_value, t_start, t_end, profile code (RAMP_PROFILES index)]
    TABULATED = 4  # [m, x_0..x_m, then per segment i: c3, c2, c1, c0 of sum c_k (t - x_i)^k]
    SUM = 5  # [offset, n_terms, then per term: kind, weight, length, leaf data...]
    PPOLY = 6  # [m, k, x_0..x_m, then per segment i: c_k..c_0 of sum c_j (t - x_i)^j]


RAMP_PROFILES = ("quintic", "cycloidal", "cosine")

# --------------------------------------------------------------------------- constraint primitives


class PrimKind(IntEnum):
    """Constraint primitives of physics.md c.2 (`clearance.constraints.primitives`)."""

    SPHERICAL = 0  # 3 rows: d = 0
    DOT1 = 1  # a_i . a_j - f(t)
    DOT2 = 2  # a_i . d - f(t)
    DISTANCE = 3  # |d| - l(t)
    DISTANCE2 = 4  # d . d - l(t)^2
    DOT1_MOVING = 5  # a_j . c(t), c(t) = R(t) e_m a rheonomic ground vector (pose driver)


PRIM_ROWS = {
    PrimKind.SPHERICAL: 3,
    PrimKind.DOT1: 1,
    PrimKind.DOT2: 1,
    PrimKind.DISTANCE: 1,
    PrimKind.DISTANCE2: 1,
    PrimKind.DOT1_MOVING: 1,
}

# Primitives whose Jacobian rows have no translational columns (J[r, 0:3] = J[r, 6:9] = 0):
# the Schur assembly skips those terms (compile.compiled._schur_structure). Keep in step
# with constraints.primitives.eval_primitives.
ROTATION_ONLY = frozenset({PrimKind.DOT1, PrimKind.DOT1_MOVING})

# prim_v slots (body components of the owning body; world components for the ground)
SB_I, SB_J, AB_I, AB_J, AX_I, AX_J = 0, 1, 2, 3, 4, 5
NPV = 6
NPIX = 8  # int parameters per primitive (prim_ix: orientation driver functions and axes)

# --------------------------------------------------------------------------- contact laws

#: parameters per law (float64 `par` arrays; unused slots are 0)
NPAR = 8


class NormalLaw(IntEnum):
    """Normal contact law codes (physics.md g); par layouts in `clearance.contact.laws`."""

    HERTZ = 0
    KELVIN_VOIGT = 1
    HUNT_CROSSLEY = 2
    LANKARANI_NIKRAVESH = 3
    FLORES = 4
    GONTHIER = 5
    HU_GUO = 6
    HERBERT_MCWHANNELL = 7
    LEE_WANG = 8
    ZHIYING_QISHAO = 9
    IMPACT = 10
    WINKLER_FORM1 = 11
    WINKLER_FORM2 = 12
    POWER = 13  # K delta^n [1 + xi ...] with xi given (Pereira et al. 2011 encodes to it)
    JOHNSON = 14  # line contact of a journal in a bearing (Johnson 1985)
    LIU = 15  # line contact (Liu, Zhang & Yang 2007)


class FrictionLaw(IntEnum):
    """Friction law codes (physics.md h); par layouts in `clearance.contact.laws`."""

    NONE = 0
    COULOMB = 1
    COULOMB_SMOOTH = 2
    THRELFALL = 3
    STRIBECK = 4
    LUGRE = 5


# --------------------------------------------------------------------------- clearance joints


class ClearanceKind(IntEnum):
    """Geometry of a clearance joint (`clearance.model.clearance`): which ideal joint it
    replaces and which contact points it has."""

    SPHERICAL = 0  # ball in socket: one point contact (physics.md f)
    REVOLUTE = 1  # journal in bearing: stations along the bearing (+ thrust faces)
    CYLINDRICAL = 2  # journal in bearing, sliding freely along its axis
    PRISMATIC = 3  # slider in guide: slider corners against the guide walls


class ContactKind(IntEnum):
    """Geometry of one contact point of a clearance joint; each has its kernel in
    `clearance.contact` with the same signature (contact geometry -> gap, normal, contact
    points on both bodies, gap rate)."""

    SPHERE = 0  # ball surface in spherical socket (contact.spherical)
    JOURNAL_STATION = 1  # bearing cross-section circle vs journal cylinder (contact.journal)
    THRUST_POINT = 2  # journal collar point vs bearing end face (contact.journal)
    SLIDER_CORNER = 3  # slider corner vs guide wall (contact.slider)


# Compiled clearance joints and contact points are packed into few arrays (Model.clr_*,
# Model.cp_*): numba passes every array of the Model named tuple separately to each
# non-inlined call, and 24 more small arrays cost 3 % of a right-hand side (measured).
# Model.clr_ix (nclr, NCLRI) int columns:
CI_KIND, CI_BS, CI_BB, CI_MVS, CI_MVB, CI_P0, CI_NP = range(7)  # ClearanceKind, outer body,
# inner body, slide functions of the outer / inner centre (-1: fixed), points; then the
# joint's rows of Model.clr_wear (a worn socket: first row, count; 0 rows: unworn)
CI_W0, CI_NW = 7, 8
NCLRI = 9
# Model.clr_geo (nclr, NCLRG) float columns: common, then kind-specific from CG_K0
CG_C, CG_VFLOOR, CG_OTOL, CG_K0 = 0, 1, 2, 3  # clearance [m], impact-velocity floor [m/s],
NCLRG = 8  # onset tolerance (fraction of the clearance); kind columns: contact kernels
# Model.clr_vec (nclr, 4, 3): outer centre, inner centre (body frames), slide axes
CV_PS, CV_PB, CV_AXS, CV_AXB = 0, 1, 2, 3
# Model.cp_ix (ncp, NCPI) int columns: ContactKind, clearance joint, NormalLaw, FrictionLaw,
# and PI_ORDER: not of point i but the i-th point in the order of ContactKind (the index sets
# per kind: points kp[kind] .. kp[kind + 1] - 1 of that order, kp = Model.cp_kptr)
PI_KIND, PI_CLR, PI_LAW, PI_FRIC, PI_ORDER = range(5)
NCPI = 5
# Model.cp_geo (ncp, NCPG) float columns: share of the joint's normal law, event tolerance
PG_W, PG_TOL, PG_K0 = 0, 1, 2  # on delta [m]; kind columns from PG_K0: contact kernels
NCPG = 6

# --------------------------------------------------------------------------- solver, integrator


class Solver(IntEnum):
    """Linear solve of the augmented system (`clearance.dynamics.solve`)."""

    SCHUR = 0
    DENSE = 1
    LSTSQ = 2


class Status(IntEnum):
    """Why an integration stopped (0: it reached the final time)."""

    SUCCESS = 0
    SINGULAR = 1
    STEP_UNDERFLOW = 2
    MAX_STEPS = 3
    NONFINITE = 4
    INTERRUPTED = 5  # stopped from outside: Ctrl-C, or a stop request (simulate's `stop`)
    WALL_TIME = 6  # simulate's max_wall_time ran out
    PAUSED = 7  # internal: a loop handed control back and resumes (state.py); never final


STATUS_MESSAGE = {
    Status.SUCCESS: "integration reached the final time",
    Status.SINGULAR: "the constraint matrix became singular (a singular configuration, or "
    "redundant constraints: try solver='lstsq')",
    Status.STEP_UNDERFLOW: "step size underflow: the step needed fell below the minimum "
    "(stiffness, a singular configuration, or an impossible motion)",
    Status.MAX_STEPS: "the maximum number of steps was reached",
    Status.NONFINITE: "the state became non-finite (NaN or inf)",
    Status.INTERRUPTED: "interrupted",
    Status.WALL_TIME: "the wall-time limit (max_wall_time) was reached",
    Status.PAUSED: "paused (internal: the loop resumes)",
}

# integrator statistics: slots of the `stats` array
ST_NFEV, ST_NACC, ST_NREJ, ST_NPROJ, ST_HMIN, ST_HMAX, ST_HLAST, ST_NEVT = 0, 1, 2, 3, 4, 5, 6, 7
NSTATS = 8
STAT_NAMES = ("nfev", "naccept", "nreject", "nproject", "hmin", "hmax", "hlast", "nevents")

# loop control: slots of `Outputs.ctl` (integrate/state.py). In: the step budget of one
# call. Kept between calls by a loop that hands control back (Status.PAUSED): whether it
# has started, and the scalars of its state (the arrays are in `Outputs.ys` / `ks`).
# Out, on every return: the status, and with t, outputs and events (CT_T, CT_IOUT,
# CT_NLOG) what the call returned, so that a caller interrupted just as it returned
# still knows (CT_STATUS is -1 while a call runs).
CT_BUDGET, CT_STARTED, CT_T, CT_H, CT_FACOLD, CT_REJECTED, CT_NSTEPS = 0, 1, 2, 3, 4, 5, 6
CT_IOUT, CT_NLOG, CT_SUBSTEP, CT_TPREV, CT_STATUS = 7, 8, 9, 10, 11
NCTL = 12
