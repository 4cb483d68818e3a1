"""Describe/compile layer: validation messages name the element, field and value; compile
never mutates the description; describe() shows the layout."""

import numpy as np
import pytest

import clearance as cl
from clearance.layout import NWORK


def _pendulum():
    m = cl.Mechanism("p")
    m.add(
        cl.Body("rod", 2.0, (0.1, 0.1, 0.01), position=(0.5, 0, 0)),
        cl.Marker("g", "ground"),
        cl.Marker("a", "rod", (-0.5, 0, 0)),
        cl.Spherical("s", "g", "a"),
    )
    return m


@pytest.mark.parametrize(
    "make, field, value",
    [
        (lambda: cl.Body("b", -1.0), "mass", "-1.0"),
        (lambda: cl.Body("b", 0.0), "mass", "0.0"),
        (lambda: cl.Body("b", 1.0, (1.0, -1.0, 1.0)), "inertia", "-1.0"),
        (lambda: cl.Body("b", 1.0, (1.0, 1.0, 3.0)), "inertia", "triangle"),
        (lambda: cl.Body("b", 1.0, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "inertia", "symmetric"),
        (lambda: cl.Body("b", 1.0, orientation=(1, 1, 0, 0)), "orientation", "unit"),
        (lambda: cl.Body("ground", 1.0), "name", "reserved"),
        (lambda: cl.Marker("m", "b", orientation=np.diag([1, 1, 2])), "orientation", "orthonormal"),
        (
            lambda: cl.Marker("m", "b", orientation=np.diag([1, 1, -1])),
            "orientation",
            "right-handed",
        ),
        (lambda: cl.Marker("m", "b", position=(0, 0)), "position", "3"),
        (lambda: cl.OrientationDriver("o", "m", (0, 0, 0), sequence="xyw"), "sequence", "xyw"),
        (lambda: cl.OrientationDriver("o", "m", (0, 0, 0), mode="half"), "mode", "half"),
        (lambda: cl.SpringDamper("k", "a", "b", stiffness=-1), "stiffness", "-1"),
    ],
)
def test_invalid_elements_are_named(make, field, value):
    with pytest.raises(cl.ModelError) as e:
        make()
    msg = str(e.value)
    assert f"'{field}'" in msg and value in msg


def test_references_and_duplicates():
    m = _pendulum()
    with pytest.raises(cl.ModelError, match="'name' = 'rod'.*already used by a body"):
        m.add(cl.Marker("rod", "rod"))
    with pytest.raises(cl.ModelError, match="'body' = 'nope'.*unknown body"):
        m.add(cl.Marker("x", "nope"))
    with pytest.raises(cl.ModelError, match="'marker_j' = 'zz'.*unknown marker"):
        m.add(cl.Revolute("r", "g", "zz"))
    m.add(cl.Marker("a2", "rod"))
    with pytest.raises(cl.ModelError, match="both markers are on body 'rod'"):
        m.add(cl.Revolute("r", "a", "a2"))
    with pytest.raises(cl.ModelError, match="'joint' = 's'.*Prismatic or Cylindrical"):
        m.add(cl.PrismaticDriver("d", "s", 0.1))
    with pytest.raises(cl.ModelError, match="'function'"):
        cl.PrismaticDriver("d", "s", "sin(t)")  # strings are never evaluated


def test_compile_does_not_mutate_and_describes_layout():
    m = _pendulum()
    before = (dict(m.bodies), dict(m.markers), dict(m.joints))
    c = cl.compile_mechanism(m)
    assert (dict(m.bodies), dict(m.markers), dict(m.joints)) == before
    assert c.nrow == 3 and c.nv == 6 and c.ny == 13 + NWORK
    text = c.describe()
    assert "lam[0:3] Spherical" in text and "rod" in text
    assert c.rows("s") == slice(0, 3)
    with pytest.raises(ValueError):
        c.model.body_mass[0] = 3.0  # frozen arrays


def test_full_inertia_is_kept():
    J = np.array([[2.0, 0.1, 0.0], [0.1, 3.0, 0.2], [0.0, 0.2, 4.0]])
    b = cl.Body("b", 1.0, J)
    assert np.allclose(b.inertia_matrix, J)


def test_body_orientation_from_matrix_roundtrip():
    rng = np.random.default_rng(1)
    for _ in range(20):
        p = rng.normal(size=4)
        p /= np.linalg.norm(p)
        b = cl.Body("b", 1.0, orientation=cl.model.bodies.quaternion_to_rotation(p))
        assert np.allclose(b.rotation, cl.model.bodies.quaternion_to_rotation(p), atol=1e-12)
