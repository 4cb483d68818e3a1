"""A classification of a steady-state response (period-n, quasi-periodic, chaotic) with the
evidence behind it: the recurrence of the Poincare points, the 0-1 test, the largest
Lyapunov exponent and the spectrum's dominant lines relative to the drive frequency."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from clearance.nonlinear.chaos import LyapunovEstimate, zero_one_test
from clearance.nonlinear.poincare import (
    default_tolerance,
    distinct_points,
    recurrence_period,
)
from clearance.nonlinear.spectra import Peak

__all__ = ["Classification", "classify"]

K_CHAOTIC = 0.8  # 0-1 test: K above is chaotic (Gottwald & Melbourne 2009 use ~1 vs ~0)
K_REGULAR = 0.2


@dataclass(frozen=True)
class Classification:
    """kind: "period-<n>", "quasi-periodic", "chaotic" or "undetermined"; period: n or
    None; the evidence: points (Poincare points used), distinct (their number of distinct
    points at tolerance tol), zero_one (K or None), lyapunov (estimate or None), peaks
    (dominant spectral lines or ()), drive_frequency [Hz] or None; reasons: one line per
    piece of evidence, in words."""

    kind: str
    period: int | None
    points: int
    distinct: int
    tol: float
    zero_one: float | None = None
    lyapunov: LyapunovEstimate | None = None
    peaks: tuple = ()
    drive_frequency: float | None = None
    reasons: tuple = field(default=())

    def __str__(self) -> str:
        return f"{self.kind}: " + "; ".join(self.reasons)


def classify(
    points: object,
    *,
    tol: float | None = None,
    max_period: int = 32,
    lyapunov: LyapunovEstimate | None = None,
    peaks: list[Peak] | tuple = (),
    drive_frequency: float | None = None,
    zero_one: bool | float | None = True,
) -> Classification:
    """Classify a response from its Poincare points (one per drive period, after the
    transient; (n, d) array over the chosen channels) and optional evidence.

    Rules, in order:
    1. the points recur with period n <= max_period within tol (default 1e-4 of their
       largest magnitude) -> "period-n";
    2. a Lyapunov exponent positive by more than 3 standard errors -> "chaotic" (without
       an exponent: a 0-1 test K > 0.8);
    3. an exponent negative by more than 3 standard errors -> "undetermined": an attracting
       orbit not reached yet (discard more transient periods);
    4. K < 0.2, or an exponent within 3 standard errors of 0 with those below 5 % of the
       drive frequency -> "quasi-periodic", unless the points still converge (their last
       quarter spreads less than half as much as their first: "undetermined", a transient);
    5. else "undetermined" (run longer).
    zero_one: True to run the 0-1 test on >= 100 points, on the coordinate whose points
    spread most (scale the coordinates comparably), a number to use a K computed
    elsewhere, None / False to skip. Disagreements between the indicators are stated in
    the reasons."""
    P = np.asarray(points, dtype=float)
    if P.ndim == 1:
        P = P[:, None]
    tol = default_tolerance(P) if tol is None else float(tol)
    n = P.shape[0]
    period = recurrence_period(P, tol=tol, max_period=max_period)
    nd = distinct_points(P, tol=tol)
    reasons = [f"{nd} distinct Poincare point(s) among {n} (tolerance {tol:.3g})"]
    K = None
    if period is not None:
        pass  # (recurrence decides; the 0-1 test of a fixed point's noise says nothing)
    elif zero_one is True and n >= 100:
        # on the coordinate whose points spread most (the one that does not recur; one at
        # the level of the integration noise would look chaotic to the test)
        K = zero_one_test(P[:, int(np.argmax(np.ptp(P, axis=0)))]).K
    elif isinstance(zero_one, (int, float)) and not isinstance(zero_one, bool):
        K = float(zero_one)
    if K is not None:
        reasons.append(f"0-1 test K = {K:.3f}")
    lam_pos = lam_zero = lam_neg = False
    if lyapunov is not None:
        lam, se = lyapunov.exponent, lyapunov.standard_error
        lam_pos = lam > 3 * se and lam > 0
        lam_neg = lam < -3 * se and lam < 0
        # "zero" only when the estimate is sharp against the drive's rate: a wide one
        # straddles 0 without telling anything
        sharp = drive_frequency is not None and se < 0.05 * drive_frequency
        lam_zero = abs(lam) <= 3 * se and sharp
        reasons.append(f"largest Lyapunov exponent {lam:.4g} +- {se:.2g} 1/s")
    if peaks:
        lines = ", ".join(
            f"{p.frequency:.4g} Hz"
            + (f" ({p.frequency / drive_frequency:.3g} f_drive)" if drive_frequency else "")
            for p in peaks[:5]
        )
        reasons.append(f"dominant frequencies {lines}")
    if period is not None:
        kind = f"period-{period}"
        reasons[0] = f"the Poincare points repeat every {period} period(s): " + reasons[0]
        if lam_pos:
            reasons.append("but the Lyapunov exponent is positive: the orbit may be unstable")
    elif lam_pos or (lyapunov is None and K is not None and K > K_CHAOTIC):
        kind = "chaotic"
        if K is not None and K < K_REGULAR:
            reasons.append("but the 0-1 test says regular")
        if not lam_pos:
            reasons.append(
                "by the 0-1 test alone: a slowly drifting transient reads the same; confirm "
                "with the Lyapunov exponent"
            )
    elif lam_neg:
        kind = "undetermined"
        reasons.append(
            "the exponent is negative (an attracting orbit) but the points do not recur yet: "
            "discard more transient periods"
        )
    elif ((K is not None and K < K_REGULAR) or lam_zero) and _settling(P):
        kind = "undetermined"
        reasons.append(
            "regular but the points still converge (a transient): discard more transient periods"
        )
    elif (K is not None and K < K_REGULAR) or lam_zero:
        kind = "quasi-periodic"
    else:
        kind = "undetermined"
        reasons.append("too few points or conflicting indicators: run longer")
    return Classification(
        kind,
        period,
        n,
        nd,
        tol,
        K,
        lyapunov,
        tuple(peaks),
        drive_frequency,
        tuple(reasons),
    )


def _settling(P: np.ndarray) -> bool:
    """The points of the coordinate that spreads most converge: the spread of its last
    quarter is below half that of its first (a spiral into a fixed point, not a closed
    invariant curve, whose quarters spread alike)."""
    x = P[:, int(np.argmax(np.ptp(P, axis=0)))]
    q = max(2, x.size // 4)
    return bool(np.ptp(x[-q:]) < 0.5 * np.ptp(x[:q]))
