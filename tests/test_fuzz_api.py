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
    # or stopped with a reason, in few steps
    assert r.stats["naccept"] < 10_000, kw
    assert r.success or r.message


@pytest.mark.parametrize(
    "kw",
    [
        {"first_step": math.nan},
        {"baumgarte": (math.nan, 5.0)},
        {"max_steps": 1e30},
        {"max_step": -1.0},
        {"min_step": math.nan},
        {"max_events": -1},
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
