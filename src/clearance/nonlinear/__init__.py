"""Nonlinear dynamics of mechanisms with clearance: steady-state runs, Poincare maps,
spectra, Lyapunov exponents, the 0-1 test and a classification of the response.

Tools on time series (spectra, rosenstein, zero_one_test, section_crossings) take arrays;
`steady_state` and `mechanism_lyapunov` run mechanisms through the compiled integrator;
`largest_lyapunov` runs any pair of `Trajectory` objects (`OdeTrajectory` for an ODE).
"""

from clearance.nonlinear.chaos import (
    Divergence,
    LyapunovEstimate,
    OdeTrajectory,
    Trajectory,
    ZeroOne,
    largest_lyapunov,
    rosenstein,
    zero_one_test,
)
from clearance.nonlinear.classify import Classification, classify
from clearance.nonlinear.mechanism import (
    MechanismTrajectory,
    SteadyState,
    mechanism_lyapunov,
    steady_state,
)
from clearance.nonlinear.poincare import (
    distinct_points,
    ode_stroboscopic,
    periodic_grid,
    recurrence_period,
    section_crossings,
    spline_rate,
    strobe_indices,
)
from clearance.nonlinear.spectra import (
    Peak,
    amplitude_spectrum,
    dominant_frequencies,
    harmonics,
    power_spectral_density,
    spectrogram,
)

__all__ = [
    "Classification",
    "Divergence",
    "LyapunovEstimate",
    "MechanismTrajectory",
    "OdeTrajectory",
    "Peak",
    "SteadyState",
    "Trajectory",
    "ZeroOne",
    "amplitude_spectrum",
    "classify",
    "distinct_points",
    "dominant_frequencies",
    "harmonics",
    "largest_lyapunov",
    "mechanism_lyapunov",
    "ode_stroboscopic",
    "periodic_grid",
    "power_spectral_density",
    "recurrence_period",
    "rosenstein",
    "section_crossings",
    "spectrogram",
    "spline_rate",
    "steady_state",
    "strobe_indices",
    "zero_one_test",
]
