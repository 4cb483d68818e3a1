"""Contact event location on a step's dense output (clearance.integrate.events), against
dense outputs built by hand so that the gap along the step is known in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

import clearance as cl
from clearance.contact.element import make_contact_state
from clearance.dynamics.rhs import make_work
from clearance.integrate.events import locate_event
from clearance.integrate.tableau import DP5_P, TS5_P
from clearance.integrate.tableau_dop853 import P as D8_P
from clearance.integrate.tableau_vern7 import P as V7_P

C, RB, H = 1e-4, 0.01, 1e-3  # clearance, ball radius [m], step [s]


def free_ball(n: int = 1) -> cl.Compiled:
    """n ball bodies, each free in its own ground socket (no gravity): the gaps are
    |r_b - s_b| - c, socket b at (b, 0, 0)."""
    m = cl.Mechanism("free balls", gravity=(0.0, 0.0, 0.0))
    for b in range(n):
        m.add(
            cl.Body(f"ball{b}", 1.0, (1e-4, 1e-4, 1e-4), position=(b, 0.0, 0.0)),
            cl.Marker(f"socket{b}", "ground", (b, 0.0, 0.0)),
            cl.Marker(f"centre{b}", f"ball{b}"),
            cl.Spherical(
                f"S{b}",
                f"socket{b}",
                f"centre{b}",
                clearance=cl.Clearance(ball_radius=RB, radial_clearance=C, normal=cl.Hertz()),
            ),
        )
    return cl.compile_mechanism(m)


def step_with_gap(c: cl.Compiled, P: np.ndarray, *polys: np.ndarray):
    """(y, K) of a step whose dense output moves ball b along x so that its distance from
    its socket centre is polys[b](x) = sum_j polys[b][j] x^j (degree <= 4), x in [0, 1]."""
    y = np.array(c.y0, dtype=float)
    K = np.zeros((P.shape[0], c.ny))
    for b, poly in enumerate(polys):
        y[7 * b : 7 * b + 3] = (b + poly[0], 0.0, 0.0)
        # h sum_k K[k] b_k(x) = poly(x) - poly(0), b_k(x) = sum_j P[k, j] x^(j+1)
        coef = np.zeros(P.shape[1])  # x^1 .. x^degree
        coef[:4] = np.asarray(poly[1:5], float) / H
        K[:, 7 * b] = np.linalg.lstsq(P.T, coef, rcond=None)[0]
    return y, K


def locate(c, P, *polys, flag=0, xtol=1e-12):
    y, K = step_with_gap(c, P, *polys)
    cs = make_contact_state(c.model)
    cs.flag[:] = flag
    return locate_event(c.model, make_work(c.model), cs, 0.0, y, K, P, H, xtol)


def bump(peak: float, x0: float = 0.1, q: float = 1e-6) -> np.ndarray:
    """Distance C + peak - q (x - x0)^2 as polynomial coefficients (x^0 .. x^4)."""
    return np.array([C + peak - q * x0 * x0, 2 * q * x0, -q, 0.0, 0.0])


@pytest.mark.parametrize(
    "P", [DP5_P, TS5_P, D8_P, V7_P], ids=["dopri5", "tsit5", "dop853", "vern7"]
)
def test_a_graze_between_probes_is_found_at_its_crossing(P):
    """The gap rises to +1e-9 m at x = 0.1 and falls back, every probe (x = 0, 1/4, ...,
    1) below zero: the onset is found at the first root, x = 0.1 - sqrt(1e-9 / 1e-6)."""
    c = free_ball()
    x, p = locate(c, P, bump(1e-9))
    assert p == 0 and x == pytest.approx(0.1 - math.sqrt(1e-3), abs=1e-9)


def test_a_near_miss_is_not_an_event():
    """The same bump peaking at -1e-9 m: no contact, no event (the quartic is exact here:
    no probe is needed to see it)."""
    x, p = locate(free_ball(), DP5_P, bump(-1e-9))
    assert (x, p) == (2.0, -1)


def test_a_brief_separation_between_probes_is_found():
    """In contact (flag 1), the gap dips to -1e-9 m around x = 0.6 and returns: the
    separation is located at the first root."""
    poly = -bump(1e-9, x0=0.6) + 2 * np.array([C, 0, 0, 0, 0])  # C - 1e-9 + q (x - 0.6)^2
    x, p = locate(free_ball(), DP5_P, poly, flag=1)
    assert p == 0 and x == pytest.approx(0.6 - math.sqrt(1e-3), abs=1e-9)


def test_a_crossing_at_a_probe_interval_is_located_to_the_time_tolerance():
    """A plain onset (the gap rising through 0 between probes 2 and 3) is located within
    xtol past the root, whatever the penetration tolerance."""
    root = 0.6
    poly = np.array([C - 1e-6 * root, 1e-6, 0.0, 0.0, 0.0])  # gap 1e-6 (x - root)
    for xtol in (1e-4, 1e-8, 1e-12):
        x, p = locate(free_ball(), DP5_P, poly, xtol=xtol)
        assert p == 0 and root - 1e-13 <= x <= root + max(xtol, 1e-13)


def test_the_first_of_two_grazes_is_found():
    """Two bumps between probes, 1e-9 m at x = 0.11 and 3e-9 m at x = 0.59 (every probe
    below zero): the earlier one is the event, though the later one is higher."""
    P = np.polynomial.polynomial
    two = P.polymul(P.polyfromroots([0.11, 0.11]), P.polyfromroots([0.59, 0.59]))
    gap = P.polyadd(P.polyadd([1e-9 - 2e-9 * 0.11 / 0.48, 2e-9 / 0.48], -1e-5 * two), [0])
    assert all(P.polyval(x, gap) < 0 for x in (0, 0.25, 0.5, 0.75, 1))
    roots = np.sort(P.polyroots(gap).real)
    assert roots[0] < 0.11 < roots[1] < roots[2] < 0.59 < roots[3]
    x, p = locate(free_ball(), DP5_P, gap + np.array([C, 0, 0, 0, 0]))
    assert p == 0 and x == pytest.approx(roots[0], abs=1e-9)


def test_a_graze_of_a_later_joint_comes_before_a_crossing_of_an_earlier_one():
    """Joint 0 crosses at x = 0.6 (between probes), joint 1 grazes at x = 0.07: the graze is
    the step's first event, whichever joint comes first in the search."""
    cross = np.array([C - 1e-6 * 0.6, 1e-6, 0.0, 0.0, 0.0])
    x, p = locate(free_ball(2), DP5_P, cross, bump(1e-9))
    # (ball 1's socket is at x = 1 m: its gap carries rounding of ~1e-16 m, ~2e-9 in x)
    assert p == 1 and x == pytest.approx(0.1 - math.sqrt(1e-3), abs=1e-8)
    x, p = locate(free_ball(2), DP5_P, bump(1e-9), cross)
    assert p == 0 and x == pytest.approx(0.1 - math.sqrt(1e-3), abs=1e-8)
