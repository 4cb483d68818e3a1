"""Line-contact laws of a journal in its bearing (Johnson, Pereira, Liu): each formula
against an independent form (Johnson's implicit relation and scipy's Lambert W, Pereira in
its own mm-N-MPa units, quadrature for the energies), and in the joint: a uniformly loaded
aligned journal carries L q(delta), and the apparent restitution of a single impact is that
of the hysteresis factor whatever the elastic law (0.9132 for Lankarani-Nikravesh, 0.9)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import lambertw

import clearance as cl
from clearance.compile.laws import ContactGeometry, encode_normal
from clearance.contact.laws import elastic_energy, johnson_line, liu_line, normal_force
from clearance.kinds import NormalLaw

E_STAR = 1.0 / (2 * (1 - 0.3**2) / 207e9)  # steel on steel [Pa]
DR = 0.5e-3  # radial clearance [m]
L = 0.02  # bearing length [m]


@pytest.mark.parametrize("r", [1e-9, 1e-6, 1e-4, 1e-2, 0.1, 0.13])
def test_johnson_solves_the_implicit_relation(r):
    """delta = (q/(pi E*)) [ln(4 pi E* dR / q) - 1] holds for the computed q, which is also
    scipy's Lambert-W form q = pi E* delta / (x - 1), x = 1 - W_-1(-e delta / (4 dR))."""
    delta = r * DR
    q, _ = johnson_line(E_STAR, DR, delta)
    implicit = q / (math.pi * E_STAR) * (math.log(4 * math.pi * E_STAR * DR / q) - 1.0)
    assert implicit == pytest.approx(delta, rel=1e-12)
    x = 1.0 - lambertw(-math.e * delta / (4 * DR), -1).real
    assert q == pytest.approx(math.pi * E_STAR * delta / (x - 1.0), rel=1e-12)


@pytest.mark.parametrize("line", [johnson_line, liu_line])
@pytest.mark.parametrize("r", [1e-7, 5e-4, 2e-3, 0.05, 0.2, 0.3])
def test_line_energy_is_the_integral_of_the_load(line, r):
    """u(delta) = int_0^delta q (quadrature), across the series / closed-form switch of Liu
    and the linear continuation of Johnson (beyond delta = 0.27 dR)."""
    delta = r * DR
    u = line(E_STAR, DR, delta)[1]
    ref = quad(lambda d: line(E_STAR, DR, d)[0], 0.0, delta, epsabs=0, epsrel=1e-13, limit=200)
    assert u == pytest.approx(ref[0], rel=1e-9)
    # continuity of the load: no jump where the formulas switch
    q0, q1 = line(E_STAR, DR, delta * (1 - 1e-9))[0], line(E_STAR, DR, delta * (1 + 1e-9))[0]
    assert abs(q1 - q0) < 1e-6 * abs(q0)


def test_liu_formula():
    delta = 3e-6
    q, _ = liu_line(E_STAR, DR, delta)
    assert q == pytest.approx(
        0.5 * math.pi * E_STAR * delta * math.sqrt(delta / (2 * (DR + delta)))
    )


def _pereira_mm(dR_mm, delta_mm, L_mm, E_mpa):
    """Pereira et al. (2011), internal contact, in the fit's own units (mm, N, MPa)."""
    Y = 1.51 * math.log(1000 * dR_mm) ** -0.151 if dR_mm < 0.34954 else 0.0151 * dR_mm + 1.151
    n = Y * dR_mm**-0.005
    return (0.965 * dR_mm + 0.0965) / dR_mm * L_mm * E_mpa * delta_mm**n


@pytest.mark.parametrize("dR", [0.01e-3, 0.2e-3, 0.5e-3, 2e-3])
def test_pereira_in_si_equals_the_fit_in_its_units(dR):
    code, par = encode_normal(
        cl.Pereira(damping="none"), ContactGeometry(0.01, 0.01 + dR, length=L)
    )
    assert code == int(NormalLaw.POWER)
    for delta in (1e-7, 1e-6, 1e-5):
        f, _ = normal_force(code, par, delta, 0.0, 1.0, dR)
        ref = _pereira_mm(1000 * dR, 1000 * delta, 1000 * L, 1e-6 * E_STAR)
        assert f == pytest.approx(ref, rel=1e-12)


def test_pereira_is_close_to_johnson_where_it_was_fitted():
    """Pereira's fit reproduces Johnson's law within about 10 % for delta/dR in
    [0.001, 0.05] at dR = 0.5 mm (their reference; the mm unit convention is the one that
    does this, docs/clearance-joints.md)."""
    code, par = encode_normal(
        cl.Pereira(damping="none"), ContactGeometry(0.01, 0.01 + DR, length=L)
    )
    for r in (1e-3, 1e-2, 5e-2):
        f, _ = normal_force(code, par, r * DR, 0.0, 1.0, DR)
        assert 0.9 < f / (L * johnson_line(E_STAR, DR, r * DR)[0]) < 1.12


def test_line_laws_need_a_journal_with_a_length():
    with pytest.raises(cl.ModelError, match="needs it"):
        cl.RevoluteClearance(0.01, radial_clearance=DR, normal=cl.Johnson())
    with pytest.raises(cl.ModelError, match="line-contact law"):
        cl.Clearance(ball_radius=0.01, radial_clearance=DR, normal=cl.Liu())
    with pytest.raises(cl.ModelError, match="0.005 mm"):
        encode_normal(cl.Pereira(), ContactGeometry(0.01, 0.01 + 1e-6, length=L))


@pytest.mark.parametrize("law", [cl.Johnson, cl.Pereira, cl.Liu])
def test_energy_consistency_in_the_kernel(law):
    """elastic_energy is the integral of the elastic force (central differences)."""
    code, par = encode_normal(law(), ContactGeometry(0.0095, 0.0095 + DR, length=L))
    for delta in (2e-7, 4e-6, 3e-5):
        h = 1e-4 * delta
        dU = elastic_energy(code, par, delta + h, DR) - elastic_energy(code, par, delta - h, DR)
        f_el = normal_force(code, par, delta, 0.0, 1.0, DR)[1]
        assert dU / (2 * h) == pytest.approx(f_el, rel=1e-7)


def journal_pair(normal, model="spatial", v0=0.05):
    m = cl.Mechanism("impact", gravity=(0.0, 0.0, 0.0))
    clr = cl.RevoluteClearance(
        0.0095, radial_clearance=DR, model=model, length=L, stations=4, normal=normal
    )
    m.add(
        cl.Body("b", 0.5, (2e-4, 3e-4, 4e-4), velocity=(v0, 0.0, 0.0)),
        cl.Marker("outer", "ground"),
        cl.Marker("inner", "b"),
        cl.Revolute("J", "outer", "inner", clearance=clr),
    )
    return m


@pytest.mark.parametrize("law", [cl.Johnson, cl.Pereira, cl.Liu])
def test_uniform_line_load_and_restitution_in_the_joint(law):
    """An aligned journal pressed by delta carries L q(delta) in total (its stations share
    it); a single radial impact with Lankarani-Nikravesh damping (c_r = 0.9) rebounds with
    the g.2 table's 0.9132, as for point laws."""
    from clearance.contact.element import clearance_forces, make_contact_state
    from clearance.dynamics.rhs import body_states, make_work

    m = journal_pair(law(restitution=0.9))
    c = cl.compile_mechanism(m)
    delta = 4e-6
    y = cl.initial_state(c, assemble_positions=False)
    y[0] = DR + delta  # the journal centre offset along x
    y[c.nq : c.nq + c.nv] = 0.0
    wk, cs = make_work(c.model), make_contact_state(c.model)
    body_states(c.model, y, wk)
    clearance_forces(c.model, y, wk, cs, np.zeros(c.ny))
    code, par = encode_normal(law(restitution=0.9), ContactGeometry(0.0095, 0.0095 + DR, length=L))
    assert -wk.Q[0, 0] == pytest.approx(normal_force(code, par, delta, 0.0, 1.0, DR)[1], rel=1e-9)
    if law is cl.Johnson:
        assert -wk.Q[0, 0] == pytest.approx(L * johnson_line(E_STAR, DR, delta)[0], rel=1e-9)
    r = cl.simulate(m, 2.5 * DR / 0.05 + 2e-3, dt_out=1e-5, rtol=1e-10, atol=1e-14)
    assert r.success, r.message
    v = r.velocity("b")[:, 0]
    assert len(r.impacts("J")) >= 1 and np.all(r.penetration("J")[-10:] < 0)
    assert -v[-1] / v[0] == pytest.approx(0.9132, abs=2e-3)
