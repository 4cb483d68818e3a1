"""Wear maps on a sphere (issue 16, first step): exact cell areas, the worn volume against
closed forms (a uniform cap, the imprint of a ball pressed into its socket), Archard's law
with a Hertz patch: volume k_w F s whatever the grid, depth profile converging to
k_w p0 s; Hertz's pressure integrating to the load (quadrature written here)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from clearance.wear import SphereWearMap, archard_hertz, hertz_conformal

R = 0.0153  # the default socket radius [m]


@pytest.mark.parametrize("n", [1, 3, 16, 64])
def test_cells_tile_the_sphere(n):
    s = SphereWearMap(R, n)
    assert s.areas.sum() == pytest.approx(4 * math.pi * R**2, rel=1e-12)
    assert s.areas.max() / s.areas.min() < 1.5
    f, i, j = s.cell_of(s.centres.reshape(-1, 3))  # each centre lies in its own cell
    idx = np.indices((6, n, n)).reshape(3, -1)
    assert np.array_equal(np.stack([f, i, j]), idx)


def _cap_volume(h0, alpha, outer=True):
    shell = (R + h0) ** 3 - R**3 if outer else R**3 - (R - h0) ** 3
    return 2 * math.pi * (1 - math.cos(alpha)) * shell / 3


@pytest.mark.parametrize("outer", [True, False])
def test_uniform_cap_volume_converges(outer):
    """A cap of half-angle 20 deg worn to 0.1 mm, about a direction off every axis."""
    u = np.array([0.3, -0.5, 0.81])
    u /= np.linalg.norm(u)
    alpha, h0 = math.radians(20), 1e-4
    errs = []
    for n in (16, 32, 64, 128):
        s = SphereWearMap(R, n, outer=outer)
        s.depth[np.arccos(np.clip(s.centres @ u, -1, 1)) < alpha] = h0
        errs.append(abs(s.volume() / _cap_volume(h0, alpha, outer) - 1))
    # (the staircase at the cap's rim: first order in the cell size, not monotone)
    assert errs[-1] < 0.005 and max(errs[2:]) < errs[0]


def test_imprint_volume():
    """The socket worn to the imprint of the ball pushed d0 beyond contact (clearance c):
    h = max(0, d0 cos psi - c (1 - cos psi)), V = pi R^2 d0^2 / (d0 + c) to first order
    in h / R (docs/notes/wear-literature.md section 6, derived there and here)."""
    d0, c = 2e-5, 3e-4
    u = np.array([0.0, 0.6, 0.8])
    s = SphereWearMap(R, 96)
    cos = s.centres @ u
    s.depth = np.maximum(0.0, d0 * cos - c * (1 - cos))
    exact = math.pi * R**2 * d0**2 / (d0 + c)
    assert s.volume() == pytest.approx(exact, rel=0.01)
    # the derivation, by quadrature: 2 pi R^2 int h(psi) sin(psi) dpsi
    val, _ = quad(lambda p: max(0.0, d0 * math.cos(p) - c * (1 - math.cos(p))) * math.sin(p), 0, 1)
    assert 2 * math.pi * R**2 * val == pytest.approx(exact, rel=1e-9)


def test_hertz_pressure_integrates_to_the_load():
    E = 207e9 / (2 * (1 - 0.3**2))  # steel on steel
    a, p0 = hertz_conformal(1000.0, 0.015, R, E)
    f, _ = quad(lambda r: p0 * math.sqrt(1 - (r / a) ** 2) * 2 * math.pi * r, 0, a)
    assert f == pytest.approx(1000.0, rel=1e-9)
    r_star = 0.015 * R / (R - 0.015)
    delta = a * a / r_star  # the approach: F = 4/3 E* sqrt(R*) delta^1.5 (Hertz)
    assert 4 / 3 * E * math.sqrt(r_star) * delta**1.5 == pytest.approx(1000.0, rel=1e-12)
    assert hertz_conformal(0.0, 0.015, R, E) == (0.0, 0.0)
    with pytest.raises(ValueError):
        hertz_conformal(1.0, R, 0.015, E)


def test_archard_volume_is_k_f_s_and_the_depth_converges():
    """1000 N over 1 m of sliding at k_w = 1e-14 m^2/N, at a contact direction off the
    axes: the volume (first order) is k_w F s on every grid; every cell's depth is
    k_w s p(r) of Hertz's pressure at its centre, up to the grid's quadrature of the load,
    whose error falls as the grid resolves the patch (a = 1.7 mm, 6.4 deg)."""
    E = 207e9 / (2 * (1 - 0.3**2))
    F, s_slide, k_w = 1000.0, 1.0, 1e-14
    a, p0 = hertz_conformal(F, 0.015, R, E)
    n_dir = np.array([0.2, 0.3, -0.93])
    n_dir /= np.linalg.norm(n_dir)
    errs = []
    for n in (16, 32, 128):
        s = SphereWearMap(R, n)
        dh = archard_hertz(s, n_dir, F, a, s_slide, k_w)
        assert np.sum(dh * s.areas) == pytest.approx(k_w * F * s_slide, rel=1e-12)
        assert s.volume() == pytest.approx(k_w * F * s_slide, rel=1e-6)  # h / R ~ 1e-7
        r = R * np.arccos(np.clip(s.centres @ n_dir, -1, 1))
        hertz = k_w * s_slide * p0 * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None))
        inside = hertz > 0
        ratio = dh[inside] / hertz[inside]
        assert np.ptp(ratio) < 1e-12 and not dh[~inside].any()  # Hertz's profile, scaled
        errs.append(abs(ratio[0] - 1))
    assert errs[-1] < 0.002 and errs[-1] < errs[0] / 5


def test_a_patch_smaller_than_the_cells_goes_into_one_cell():
    s = SphereWearMap(R, 4)
    dh = archard_hertz(s, [1.0, 0.1, 0.05], 10.0, 1e-5, 0.5, 1e-13)
    assert np.count_nonzero(dh) == 1
    assert np.sum(dh * s.areas) == pytest.approx(1e-13 * 10.0 * 0.5, rel=1e-12)
    assert not archard_hertz(s, [1, 0, 0], 0.0, 1e-5, 0.5, 1e-13).any()


def test_vectorised_samples_cover_a_hertz_patch_beside_a_pocket():
    """A contact that overlaps no cell (0.3 um beyond c over a 3 um pocket 0.08 rad wide,
    n = 64): the deposit on the cells the ball is pushed into, away from e / |e| on the
    pocket's rim; the vectorised deposit reaches every cell the single one does (review
    finding: a window that once missed 3 of 88 cells, 33 % off)."""
    from clearance.wear.surface import archard_samples, overlap_patch

    c, n = 3e-4, 64
    worn = SphereWearMap(R, n)
    u0 = np.array([0.0, 0.0, -1.0])
    th = np.arccos(np.clip(worn.centres @ u0, -1, 1))
    worn.depth = np.where(th < 0.08, 3e-6 * (1 - (th / 0.08) ** 2) ** 2, 0.0)
    e = (c + 0.3e-6) * u0
    ref = SphereWearMap(R, n)
    cells, dh = overlap_patch(worn, e, c, 1000.0, 1e-4, 1e-14)
    assert cells.size >= 8
    ref.depth.reshape(-1)[cells] += dh
    got = SphereWearMap(R, n)
    archard_samples(got, e[None], [1000.0], [1e-4], [1.9e-3], 1e-14, worn=worn, clearance=c)
    np.testing.assert_allclose(got.depth, ref.depth, rtol=1e-10, atol=1e-12 * ref.depth.max())


@pytest.mark.parametrize("worn", [False, True], ids=["unworn", "worn"])
def test_vectorised_samples_deposit_what_the_single_patches_do(worn):
    """archard_samples (chunks of samples over the cells near them) adds exactly what
    hertz_patch / overlap_patch add one sample at a time (over every cell): random contacts
    around two directions, a socket with and without a pocket; small penetrations (the Hertz
    fallback) and deep ones (the overlap's pressure)."""
    from clearance.wear.surface import archard_samples, hertz_patch, overlap_patch

    rng = np.random.default_rng(4)
    c, n = 3e-4, 24
    base = SphereWearMap(R, n)
    if worn:
        u0 = np.array([0.0, -0.6, -0.8])
        cos = base.centres @ u0
        base.depth = np.maximum(0.0, 30e-6 * (cos - 0.985) / 0.015)
    k = 300
    dirs = np.array([0.0, -0.6, -0.8]) + 0.15 * rng.normal(size=(k, 3))
    dirs[: k // 2] += np.array([0.0, 1.2, 0.0])
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    e = dirs * (c + rng.uniform(-1e-6, 25e-6, size=k))[:, None]
    F = rng.uniform(0.0, 500.0, size=k)
    F[::7] = 0.0
    s = rng.uniform(0.0, 1e-4, size=k)
    a = rng.uniform(2e-4, 2e-3, size=k)
    ref = SphereWearMap(R, n)
    flat = ref.depth.reshape(-1)
    for i in range(k):
        if worn:
            cells, dh = overlap_patch(base, e[i], c, F[i], s[i], 1e-14)
        else:
            cells, dh = hertz_patch(base, e[i], F[i], a[i], s[i], 1e-14)
        flat[cells] += dh
    got = SphereWearMap(R, n)
    archard_samples(got, e, F, s, a, 1e-14, worn=base if worn else None, clearance=c, chunk=37)
    assert ref.depth.max() > 0
    np.testing.assert_allclose(got.depth, ref.depth, rtol=1e-10, atol=1e-12 * ref.depth.max())


def test_reachable_depth_is_the_brute_force_minimum():
    """c + H(u) = min over every cell v with u . v > 0 of (c + h(v)) / (u . v), written here
    over all cell pairs (the package searches the worn cells and the nearest unworn one):
    a random rough wear patch and a narrow deep pit, H <= h, H = 0 away from the wear."""
    rng = np.random.default_rng(8)
    c = 3e-4
    m = SphereWearMap(R, 12)
    u0 = np.array([0.3, -0.2, -0.93]) / np.linalg.norm([0.3, -0.2, -0.93])
    th = np.arccos(np.clip(m.centres @ u0, -1, 1))
    m.depth = np.where(th < 0.6, 20e-6 * rng.uniform(0, 1, size=th.shape), 0.0)
    m.depth[np.unravel_index(np.argmin(th), th.shape)] = 80e-6  # a one-cell pit
    cells = m.centres.reshape(-1, 3)
    h = m.depth.reshape(-1)
    cos = cells @ cells.T
    ratio = np.where(cos > 0, (c + h[None, :]) / np.where(cos > 0, cos, 1.0), np.inf)
    brute = np.clip(ratio.min(axis=1) - c, 0.0, h)
    H = m.reachable_depth(c).reshape(-1)
    np.testing.assert_allclose(H, brute, rtol=0, atol=1e-18)
    assert np.all(H <= h) and H[np.argmax(h)] < 0.5 * h.max()  # the pit is out of reach
    assert not H[th.reshape(-1) > 0.9].any()
