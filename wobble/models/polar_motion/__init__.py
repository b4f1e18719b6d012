"""The Chandler wobble measured in a polar-motion record (SI floats): one module per idea.

Units: time in seconds (any origin; the caller's), angles in radians,
angular frequencies in rad/s. Nothing here knows about files or units.

* :mod:`.record`: the complex pole, the constants and the checks of a series;
* :mod:`.fit`: the fitted model (equation 2) and its terms;
* :mod:`.least_squares` and :mod:`.spectrum`: the two estimators of the
  Chandler term, sharing the frequency search of :mod:`.search`;
* :mod:`.uncertainty`: the pieces of their uncertainty;
* :mod:`.windows`: sliding-window fits;
* :mod:`.quality`: Q from the line shape (:func:`quality_factor`).

**Sign convention.** The pole is the complex number

    p = x_p - i y_p,                                                        (1)

with x_p toward the Greenwich meridian and y_p toward 90 deg W (IERS). With
this sign a term ``a exp(+i sigma t)``, sigma > 0, turns counter-clockwise seen
from above the north pole: *prograde*, in the sense of the Earth's rotation
(Munk & MacDonald 1960, sec. 6; Gross 2007, Treatise on Geophysics 3, eq. 11).
The Chandler wobble is prograde: its spectral peak is at +0.843 cycles per
year, which the test-suite checks on the IERS record.

**The model** of a record is

    p(t) = sum_j c_j tau^j + A_c e^{i sigma_c s} + A_+ e^{i Omega_a s}
           + A_- e^{-i Omega_a s},   s = t - t_e,  tau = s / h,              (2)

a slow drift of the mean pole (a polynomial of degree ``drift_degree`` in the
scaled time tau, h = half the span, t_e the mid epoch), the Chandler term and
the prograde and retrograde annual terms at the tropical year. The complex
amplitudes carry the phase at the epoch t_e.

**Two independent estimators** of sigma_c:

* :func:`fit_least_squares` - nonlinear least squares of (2) on the complex
  series: the frequency from the maximum of the profile (variable-projection)
  gain, then polished by :func:`scipy.optimize.least_squares` on every
  parameter;
* :func:`fit_spectrum` - the peak of the two-sided (complex) amplitude
  spectrum of the detrended series with a Hann taper (no annual terms are
  fitted: the taper's low side lobes keep the annual peak out).

**Uncertainties.** The residuals of (2) are not white: they hold the changes of
the Chandler amplitude and phase over the decades, interannual motion and the
annual wobble's variations, all strongly autocorrelated. A white-noise
("formal") error is 20-300 times too small. Each estimator reports

* ``autocorrelation``: for least squares, the sandwich (HAC) covariance
  B^-1 M B^-1 whose middle term sums the autocovariances of the score series
  with Bartlett weights up to one beat period or a tenth of the span,
  whichever is shorter (Newey & West 1987), divided by the fixed-b bias
  factor 1 - b + b^2/3 of that estimator (Kiefer & Vogelsang 2005); for the
  spectrum, the local level of the residual spectrum in a ring outside the
  peak's main lobe, in the peak-location variance (Whittle 1952; Hannan 1973:
  coloured noise enters through its spectral density at the line's frequency).
  On synthetic records with AR(1) noise of 200-day correlation time these
  match the actual scatter to 5-30 %;
* ``subspans``: the scatter of the same estimator over n >= 3 disjoint
  sub-spans of at least two beat periods, sd/sqrt(n) times the Student-t
  factor for 68 %. If the wobble's phase wanders this is the error of the
  record's mean frequency; for a pure sinusoid in noise it is conservative
  by about n;
* ``excitation``: the Chandler wobble is a free mode kept up by random
  excitation, so a record's mean period scatters about the mode's period by
  far more than the residual noise says (several days for 30-65 years at
  Q = 100). A parametric Monte Carlo (:func:`_excitation_scatter`) measures
  that scatter for an assumed Q (default 100; ``excitation_q=None`` leaves it
  out);
* ``model``: the largest change when the drift polynomial has one degree
  more or less.

The adopted uncertainty is ``sqrt(max(autocorrelation, subspans,
excitation)^2 + model^2)``: the first three are alternative measures of the
same random error under different hypotheses, the last a systematic one.
Spans shorter than one beat period between the Chandler and the annual term
(about 6.4 years) cannot separate the two well: the result says so in
``caveats``, and the model and excitation terms, which grow quickly there,
widen the error.
"""

from __future__ import annotations

from wobble.models.polar_motion.fit import ChandlerFit, Harmonic, Uncertainty
from wobble.models.polar_motion.least_squares import MAX_VARIANCE_INFLATION, fit_least_squares
from wobble.models.polar_motion.quality import MIN_Q_SPAN, QualityFactor, quality_factor
from wobble.models.polar_motion.record import (
    ANNUAL_RATE,
    CHANDLER_BAND,
    DAY,
    JULIAN_YEAR,
    MIN_SPAN,
    TROPICAL_YEAR,
    beat_period,
    complex_pole,
    pole_xy,
)
from wobble.models.polar_motion.spectrum import Spectrum, fit_spectrum, two_sided_spectrum
from wobble.models.polar_motion.windows import WindowedFits, shortest_window, sliding_windows, window_allowed

__all__ = [
    "DAY",
    "JULIAN_YEAR",
    "TROPICAL_YEAR",
    "ANNUAL_RATE",
    "beat_period",
    "CHANDLER_BAND",
    "MIN_SPAN",
    "complex_pole",
    "pole_xy",
    "Harmonic",
    "Uncertainty",
    "ChandlerFit",
    "Spectrum",
    "WindowedFits",
    "QualityFactor",
    "fit_least_squares",
    "MAX_VARIANCE_INFLATION",
    "fit_spectrum",
    "two_sided_spectrum",
    "sliding_windows",
    "shortest_window",
    "window_allowed",
    "quality_factor",
    "MIN_Q_SPAN",
]
