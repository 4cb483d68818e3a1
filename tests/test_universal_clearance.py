"""Clearance in a revolute pair of a universal joint: the joint becomes its cross (a body)
and two revolute joints, one with the clearance (`Mechanism.with_clearance` with a
UniversalClearance).

Oracles: the ideal universal joint itself. With both pairs ideal and a cross of vanishing
mass, the expanded mechanism moves as the universal joint (the cross has no degree of
freedom of its own: its inertia only adds to the bodies'), so the trajectories agree to the
order of the cross's inertia; with the clearance, c -> 0 approaches the ideal joint."""

from __future__ import annotations

import numpy as np
import pytest

import clearance as cl

G = (0.0, -3.0, -9.81)


def chain(u_at_ground: bool) -> cl.Mechanism:
    """A spatial double pendulum: rod 1 hangs from the ground by a spherical joint (or by
    the universal joint under test), rod 2 hangs from rod 1 by the universal joint (or by a
    spherical joint). The U axes: h_i on the upper body, h_j on the lower one, both normal
    to the rods. It starts at rest, assembled (so the expanded mechanism starts in the same
    state); the sideways gravity makes the motion spatial."""
    m = cl.Mechanism("u-chain", gravity=G)
    m.add(
        cl.Body("rod1", 1.0, (0.08, 0.08, 0.002), (0.3, 0.0, -0.2)),
        cl.Body("rod2", 0.7, (0.05, 0.05, 0.001), (0.8, 0.1, -0.3)),
        cl.Marker.on_axis("top", "ground", (0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)),
        cl.Marker.on_axis("r1_top", "rod1", (-0.3, 0.0, 0.2), axis=(0.0, 1.0, 0.0)),
        cl.Marker.on_axis("r1_bot", "rod1", (0.2, 0.0, 0.0), axis=(0.0, 0.0, 1.0)),
        cl.Marker.on_axis("r2_top", "rod2", (-0.3, -0.1, 0.1), axis=(0.0, 1.0, 0.0)),
    )
    if u_at_ground:
        m.add(cl.Universal("U", "top", "r1_top"), cl.Spherical("S", "r1_bot", "r2_top"))
    else:
        m.add(cl.Spherical("S", "top", "r1_top"), cl.Universal("U", "r1_bot", "r2_top"))
    return m


def _journal(c: float, **kw) -> dict:
    law = cl.LankaraniNikravesh(stiffness=1e11, restitution=0.5)
    return dict(journal_radius=0.004, radial_clearance=c, normal=law, **kw)


def _ideal_pairs(m: cl.Mechanism, name: str) -> cl.Mechanism:
    """The expanded mechanism with the clearance pair made ideal again."""
    return m.with_clearance(name, None)


@pytest.mark.parametrize("pair", ["i", "j"])
@pytest.mark.parametrize("u_at_ground", [True, False])
def test_cross_of_vanishing_mass_is_the_universal_joint(u_at_ground, pair):
    ideal = chain(u_at_ground)
    ref = cl.simulate(ideal, 0.5, dt_out=1e-2, rtol=1e-10, atol=1e-12)
    assert ref.success, ref.message
    errs = []
    for scale in (1e-4, 1e-6):
        u = cl.UniversalClearance(
            **_journal(1e-4), pair=pair, cross_mass=scale, cross_inertia=(scale, scale, 2 * scale)
        )
        m = ideal.with_clearance("U", u)
        assert set(m.joints) == {"U.i", "U.j", "S"} and "U.cross" in m.bodies
        m = _ideal_pairs(m, f"U.{pair}")
        r = cl.simulate(m, 0.5, dt_out=1e-2, rtol=1e-10, atol=1e-12)
        assert r.success, r.message
        d = max(np.max(np.abs(r.position(b) - ref.position(b))) for b in ("rod1", "rod2"))
        errs.append(d)
    # the difference is the cross's inertia: it shrinks with it (not a geometry error)
    assert errs[1] < 1e-5 and errs[1] < 0.03 * errs[0], errs  # linear in the inertia


@pytest.mark.parametrize("pair", ["i", "j"])
def test_small_clearance_in_a_pair_approaches_the_universal_joint(pair):
    """c -> 0 with a stiff contact: the lower rod's joint point follows the motion with the
    pair ideal (the same cross; the test above shows that this is the universal joint as
    the cross's inertia vanishes) to the order of c (planar journal model: the pair's radial
    rows are the contact)."""
    ideal = chain(u_at_ground=False)
    cross = dict(pair=pair, cross_mass=0.02, cross_inertia=(2e-6, 2e-6, 3e-6))
    ref_mech = _ideal_pairs(
        ideal.with_clearance("U", cl.UniversalClearance(**_journal(1e-4), **cross)), f"U.{pair}"
    )
    ref = cl.simulate(ref_mech, 0.1, dt_out=1e-3, rtol=1e-9, atol=1e-12)
    errs = []
    for c in (1e-4, 1e-5):
        m = ideal.with_clearance("U", cl.UniversalClearance(**_journal(c), **cross))
        r = cl.simulate(m, 0.1, dt_out=1e-3, rtol=1e-8, atol=1e-12, max_steps=2_000_000)
        assert r.success, r.message
        assert len(r.impacts(f"U.{pair}")) > 0  # the journal does touch its bearing
        mk = ideal.markers["r2_top"]
        d = r.point_position("rod2", mk.position) - ref.point_position("rod2", mk.position)
        errs.append(float(np.max(np.linalg.norm(d, axis=1))) / c)
    assert errs[0] < 3.0 and errs[1] < 3.0, errs


def test_universal_clearance_checks():
    kw = _journal(1e-4)
    with pytest.raises(cl.ModelError, match="pair"):
        cl.UniversalClearance(**kw, cross_mass=0.02, cross_inertia=(1e-6, 1e-6, 1e-6))
    with pytest.raises(cl.ModelError, match="cross_mass"):
        cl.UniversalClearance(**kw, pair="i", cross_inertia=(1e-6, 1e-6, 1e-6))
    with pytest.raises(cl.ModelError) as err:
        cl.UniversalClearance(**kw, pair="i", cross_mass=0.02, cross_inertia=(1e-6, -1.0, 1e-6))
    assert err.value.field == "cross_inertia"
    u = cl.UniversalClearance(**kw, pair="i", cross_mass=0.02, cross_inertia=(1e-6, 1e-6, 1e-6))
    m = chain(True)
    with pytest.raises(cl.ModelError, match="UniversalClearance"):
        m.with_clearance("U", cl.RevoluteClearance(**kw))  # a universal joint needs its pair
    with pytest.raises(cl.ModelError, match="clearance"):
        cl.Revolute("R", "top", "r1_top", clearance=u)  # a revolute joint takes its own kind
    assert u.revolute() == cl.RevoluteClearance(**kw)
