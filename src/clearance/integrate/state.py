"""The integrator contract: what every integration loop receives, keeps and returns.

A loop (`erk.erk54`, `rk4.rk4`, or a new one) is a compiled function

    loop(model, wk, cs, opts, out, *method_data, t0, y0) -> (status, n_out, t_reached, n_events)

* model: the compiled mechanism (`clearance.compile.compiled.Model`); wk: scratch arrays of
  one right-hand side evaluation (`clearance.dynamics.rhs.Work`); the right-hand side is
  `rhs(t, y, model, wk, cs, opts.alpha, opts.beta, opts.solver, ydot)`.
* cs: the explicit discrete state (`clearance.contact.element.ContactState`): the contact
  flag and latched impact velocity of every contact point. The right-hand side only reads
  it; the loop changes it only through the shared on-accept hook.
* opts: `Options` (below), the settings bundled. out: `Outputs` (below), the arrays the
  loop fills: states at the requested times, the contact state with them, the event log,
  statistics and peaks.
* status: a `clearance.kinds.Status` value (0: reached the final time).

What every loop must do (clearance.integrate.accept has the shared hooks):

1. start: `accept.start(...)` (projection of the initial state if asked, the contact state
   of the initial state, samples at t0);
2. per accepted step: locate contact events on the step's dense output
   (`events.locate_event`, which takes the dense output as data: y, the stages K and the
   weight polynomials P, step h) and cut the step at the earliest one; write the samples
   inside the step from the dense output with `accept.sample` (which notes the step in
   out.piece: the post-processing interpolates between samples of one step only); then
   `accept.after_step(...)` (discrete contact update and event log, quaternion
   normalisation, projection), which says whether y or the discrete state changed (a
   first-same-as-last stage must then be recomputed); then `accept.track_peaks` with the
   diagnostics of f(t, y); with a Poincare section (out.sec_w not empty), `accept.section`
   on each accepted step's dense output, before its samples;
3. count in out.stats (kinds.ST_*): rhs evaluations, accepted and rejected steps,
   projections, steps cut at events, smallest / largest / last step;
4. hand control back: after out.ctl[CT_BUDGET] attempted steps in one call (0: no limit),
   keep the scalars of the loop's state in out.ctl (kinds.CT_*), its arrays in out.ys/ks,
   and return Status.PAUSED; called again with the same arguments, continue exactly where
   it stopped (out.ctl[CT_STARTED] != 0: skip the start, ignore y0). The step sequence
   does not depend on the budgets: a run in slices is the same run to the last bit; on
   every return, keep (status, outputs, t, events) in out.ctl too (`accept.returned`)
   (`simulate` calls the loop in slices of ~0.1 s of wall time, so that Ctrl-C, a stop
   request, max_wall_time and the progress callback act within the run).

A new explicit method is its loop module plus one line in `methods.METHODS`; a 7-stage FSAL
5(4) pair is only its tableau (`tableau.py`) and the registry line.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Options(NamedTuple):
    """Settings of one integration (see `clearance.integrate.simulate.simulate`)."""

    alpha: float  # Baumgarte alpha [1/s]
    beta: float  # Baumgarte beta [1/s]
    solver: int  # kinds.Solver
    rtol: float
    atol: float
    h0: float  # first step [s] (0: automatic)
    hmax: float  # largest step [s]
    hmin: float  # smallest step [s] before failure
    max_steps: int
    proj_tol: float  # > 0: coordinate projection after each accepted step (physics.md d.4)
    step: float  # fixed step of fixed-step methods [s]


class Outputs(NamedTuple):
    """Arrays a loop fills."""

    t_out: np.ndarray  # (n_out,) requested output times
    Y: np.ndarray  # (n_out, ny) states at t_out
    CS: np.ndarray  # (n_out, ncp, 2) contact flag and impact velocity valid at t_out
    piece: np.ndarray  # (n_out,) int64: the accepted step whose dense output gave the sample
    # (its count, from 1), -1 for a sample on the solution itself (the start, fixed steps)
    log: np.ndarray  # (max_events, layout.NLOG) contact event log
    stats: np.ndarray  # (kinds.NSTATS,)
    PK: np.ndarray  # (nclr, 4) largest F_N, its time, largest delta, its time
    ctl: np.ndarray  # (kinds.NCTL,) the step budget of a call, the loop's scalars between calls
    ys: np.ndarray  # (ny,) the loop's current state, kept between calls
    ks: np.ndarray  # (stages, ny) the method's stages, kept between calls (FSAL: ks[0] = f(t, ys))
    # a Poincare section g(y) = sec_w . y - sec[0] = 0 crossed in direction sec[1] (+1
    # upward, -1 downward, 0 both), located on the dense output of the accepted steps
    # (`accept.section`); sec[2]: crossings found (also those beyond the buffer)
    sec: np.ndarray  # (3,)
    sec_w: np.ndarray  # (ny,) weights of g, or (0,): no section
    sec_t: np.ndarray  # (max_crossings,) crossing times
    sec_Y: np.ndarray  # (max_crossings, ny) states at the crossings
