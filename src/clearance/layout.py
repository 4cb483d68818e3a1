"""The state layout and the output channels, declared once as data.

State vector of the integrator (physics.md d.1, j):

    y = [ q (7 nb) | v (6 nb) | z (3 ncp) | W (NWORK) | D_n (nclr) | D_t (nclr) ]

q per body: r (3), Euler parameters p (4); v per body: r_dot (3), omega' (3) body frame;
z: LuGre bristle vector of each contact point of the clearance joints (zero for other
friction laws); W: the work integrals named in WORK; D_n / D_t: normal-damping dissipation
and friction work of each clearance joint (summed over its contact points).
`StateLayout` gives the offsets; the compiled model carries them (`Model.y_*`).

Output channels of clearance joints. The contact kernel writes two diagnostic arrays per
right-hand side evaluation: one row per clearance joint (JOINT_COLUMNS, `Result.contact`)
and one row per contact point (POINT_COLUMNS, `Result.contact_points`). Each column group
is declared here with its dataset variable name, width, units, long name and description;
`clearance.store.result.Result.channel`, the Dataset conversion (`clearance.io.dataset`, both
directions) and the CSV/MAT exports are generated from these tables. Adding a channel: one
entry here (its column offset constant follows) and the line of the kernel that writes it.
"""

from __future__ import annotations

from dataclasses import dataclass

# --------------------------------------------------------------------------- state vector

#: work integrals after the bristle states: name (Result.energy key) and description
WORK = (
    ("work_constraints", "work W_c of all constraint forces (drivers included)"),
    ("work_drivers", "work W_d of the drivers"),
    ("work_applied", "work W_a of applied non-conservative forces"),
    ("work_moving", "work W_m of contact forces through moving attachment points"),
    ("work_inertia", "lumped-limb inertia power integral W_L"),
)
NWORK = len(WORK)
W_C, W_D, W_A, W_M, W_L = range(NWORK)


@dataclass(frozen=True)
class StateLayout:
    """Offsets of the parts of y for nb moving bodies, ncp contact points (each with a
    3-vector bristle state) and nclr clearance joints."""

    nb: int
    ncp: int = 0
    nclr: int = 0

    @property
    def iv(self) -> int:
        """Start of the velocities v."""
        return 7 * self.nb

    @property
    def iz(self) -> int:
        """Start of the bristle states z (3 per contact point)."""
        return 13 * self.nb

    @property
    def iw(self) -> int:
        """Start of the work integrals (WORK)."""
        return self.iz + 3 * self.ncp

    @property
    def idn(self) -> int:
        """Start of the normal-damping dissipation D_n (one per clearance joint)."""
        return self.iw + NWORK

    @property
    def idt(self) -> int:
        """Start of the friction work D_t (one per clearance joint)."""
        return self.idn + self.nclr

    @property
    def ny(self) -> int:
        return self.idt + self.nclr

    @property
    def nerr(self) -> int:
        """Entries that steer the step size: q, v and z (not the work integrals)."""
        return self.iw

    def model_fields(self) -> dict[str, int]:
        """The offsets as stored in the compiled model (`Model.y_*`)."""
        return dict(
            y_iv=self.iv,
            y_iz=self.iz,
            y_iw=self.iw,
            y_idn=self.idn,
            y_idt=self.idt,
            y_ny=self.ny,
        )


# --------------------------------------------------------------------------- output channels


@dataclass(frozen=True)
class Columns:
    """A group of columns of a diagnostic array: `width` columns from `start`.

    name: dataset variable; units (UDUNITS style, "1" dimensionless); sign: the dataset holds
    sign * the kernel's value (e.g. the friction force on the inner body is -F_T_vec).
    """

    name: str
    width: int
    units: str
    long_name: str
    description: str = ""
    sign: float = 1.0
    start: int = 0

    @property
    def cols(self) -> slice:
        return slice(self.start, self.start + self.width)

    def take(self, data):
        """The dataset's values of this group in a diagnostic array (..., ncols): its
        columns times `sign`, without the last axis for a width-1 group."""
        x = data[..., self.cols]
        x = x if self.sign == 1.0 else self.sign * x
        return x[..., 0] if self.width == 1 else x


def _table(*groups: Columns) -> tuple[tuple[Columns, ...], int]:
    out, k = [], 0
    for g in groups:
        out.append(Columns(g.name, g.width, g.units, g.long_name, g.description, g.sign, k))
        k += g.width
    return tuple(out), k


# Per clearance joint (`Result.contact`, dims (time, clearance[, axis])). The inner body is
# the ball / journal / slider, the outer one the socket / bearing / guide. For a joint with
# several contact points the scalar penetration and the normal, rate and slip velocity are
# those of its deepest point; forces are sums over its points.
JOINT_COLUMNS, NCOUT = _table(
    Columns(
        "eccentricity",
        3,
        "m",
        "eccentricity",
        "inner centre relative to the outer centre, outer marker frame",
    ),
    Columns(
        "penetration",
        1,
        "m",
        "penetration",
        "largest penetration of the joint's contact points (negative: free flight)",
    ),
    Columns("penetration_rate", 1, "m s-1", "penetration rate delta_dot", "deepest point"),
    Columns("contact_force", 1, "N", "normal contact force F_N", "sum over the contact points"),
    Columns("elastic_force", 1, "N", "elastic part of F_N", "sum over the contact points"),
    Columns("contact_normal", 3, "1", "contact normal n", "deepest point, unit, world frame"),
    Columns(
        "friction_force",
        3,
        "N",
        "friction force on the inner body",
        "opposes slip, sum over the contact points, world frame",
        sign=-1.0,
    ),
    Columns("slip_velocity", 3, "m s-1", "tangential slip velocity", "deepest point, world frame"),
    Columns("ball_centre", 3, "m", "inner centre", "ball / journal / slider centre, world"),
    Columns(
        "normal_force",
        3,
        "N",
        "normal contact force on the inner body",
        "-sum F_N n, world frame",
        sign=-1.0,
    ),
)
(
    CO_E,
    CO_DELTA,
    CO_DDOT,
    CO_FN,
    CO_FEL,
    CO_N,
    CO_FT,
    CO_VT,
    CO_PB,
    CO_FNV,
) = (c.start for c in JOINT_COLUMNS)

# Per contact point (`Result.contact_points`, dims (time, contact[, axis])).
POINT_COLUMNS, NPOUT = _table(
    Columns("point_penetration", 1, "m", "penetration delta", "negative: no contact"),
    Columns("point_penetration_rate", 1, "m s-1", "penetration rate delta_dot"),
    Columns("point_contact_force", 1, "N", "normal contact force F_N"),
    Columns("point_elastic_force", 1, "N", "elastic part of F_N"),
    Columns("point_normal", 3, "1", "contact normal n", "unit, world frame"),
    Columns(
        "point_friction_force",
        3,
        "N",
        "friction force on the inner body",
        "opposes slip, world frame",
        sign=-1.0,
    ),
    Columns("point_slip_velocity", 3, "m s-1", "tangential slip velocity", "world frame"),
    Columns("point_location", 3, "m", "contact point", "on the outer surface, world frame"),
)
PO_DELTA, PO_DDOT, PO_FN, PO_FEL, PO_N, PO_FT, PO_VT, PO_Q = (c.start for c in POINT_COLUMNS)

# Contact event log (`Result.events`): one row per onset or separation.
EVENT_COLUMNS = ("time", "point", "kind", "penetration_rate", "eccentricity")
EV_T, EV_POINT, EV_KIND, EV_DDOT, EV_E = 0, 1, 2, 3, 4
NLOG = 7  # EV_E has 3 columns: the joint's eccentricity (outer marker frame) at the event
