"""Bad arguments of `simulate` (issue 11): a clear ModelError naming the argument, never a
traceback from deeper down, and never millions of steps on a NaN setting."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import clearance as cl
from clearance.mechanisms.examples import spatial_pendulum

BAD = [math.nan, math.inf, -math.inf, -1.0, 0.0, 1e30, "x", None, True, (math.nan, 5.0), [1, 2, 3]]
ARGS = [
    "rtol",
    "atol",
    "first_step",
    "max_step",
    "min_step",
    "max_steps",
    "step",
    "baumgarte",
    "projection_tol",
    "max_events",
    "dt_out",
    "method",
    "solver",
]


@pytest.fixture(scope="module")
def compiled():
    return cl.compile_mechanism(spatial_pendulum())


@settings(max_examples=150, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.sampled_from(ARGS), st.sampled_from(BAD)), min_size=1, max_size=2))
def test_bad_simulate_arguments_are_named(compiled, changes):
    kw = dict(changes)
    try:
        r = cl.simulate(compiled, 0.01, **kw)
    except cl.ModelError as e:
        assert e.field in kw, (e.field, kw)  # names one of the arguments it was given
        return
    # accepted: a legal combination (inf max_step, 0 first_step, ...) that ran to the end
    # or stopped with a reason, in few steps (a NaN setting used to take 10 million)
    assert r.stats["naccept"] < 10_000, kw


@pytest.mark.parametrize(
    "kw",
    [
        {"first_step": math.nan},
        {"baumgarte": (math.nan, 5.0)},
        {"max_steps": 1e30},
        {"max_step": -1.0},
        {"min_step": math.nan},
        {"max_events": -1},
        {"method": ["dopri5"]},
        {"solver": ["schur"]},
        {"t_start": "0"},
        {"t_start": math.nan},
        {"dt_out": 1e-310},
        {"rtol": 10**400},
        {"max_steps": 1.5},
    ],
)
def test_the_issues_cases(compiled, kw):
    (name,) = kw
    with pytest.raises(cl.ModelError) as err:
        cl.simulate(compiled, 0.01, **kw)
    assert err.value.field == name


def test_t_out_with_nan_is_refused(compiled):
    with pytest.raises(cl.ModelError, match="t_out"):
        cl.simulate(compiled, 0.01, t_out=np.array([0.0, math.nan, 0.01]))


def test_integral_floats_and_numpy_types_stay_accepted(compiled):
    """What scripts passed before keeps working: max_steps = 1e7, numpy scalars and
    arrays, t_out as a list."""
    r = cl.simulate(
        compiled,
        0.01,
        max_steps=1e7,
        max_events=np.int64(10),
        baumgarte=np.array([5.0, 5.0]),
        rtol=np.float64(1e-6),
        t_out=[0.0, 0.005, 0.01],
    )
    assert r.success and r.t.size == 3
