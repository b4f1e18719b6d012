"""Euler's equations evaluated at given states: how fast a free body's angular velocity changes and turns.

The exact solutions (:mod:`wobble.models.free`) give omega(t); a caller holding samples of omega (a
file, a figure) asks instead how fast omega moves *at* those samples, whatever their spacing:

* :func:`omega_dot`: ``d omega/dt`` of the torque-free body, from Euler's equations with one point
  fixed, ``I d omega/dt = (I omega) x omega`` (course notes 5.5, p. 68, with tau = 0), for a body
  whose principal axes lie in any orientation in the frame of omega;
* :func:`polhode_turn_rate`: the angular speed at which omega runs round its polhode, about the
  principal axis of largest moment when ``L^2 > 2 T I_mid`` and of smallest otherwise (Landau &
  Lifshitz, Mechanics, sec. 37): ``|a . (w_perp x w_perp_dot)| / |w_perp|^2``, with ``w_perp`` the
  part of omega across that axis ``a``. For a symmetric body it is the Euler frequency
  ``|(C - A)/A omega_3|`` (notes 5.6, p. 69) at every sample; over one period of an asymmetric
  body's omega it averages to ``2 pi / period``.

SI floats throughout (kg m^2, rad/s); every function broadcasts over leading dimensions.
"""

from __future__ import annotations

import numpy as np

__all__ = ["omega_dot", "polhode_turn_rate", "wobble_angle_rate"]

# Below this share of |omega| the part of omega across the polhode's axis is rounding (omega's components
# carry about 1e-16 of |omega|; 1e-13 leaves a margin of a thousand): its turn rate, a ratio of two
# rounding errors, is reported as 0 (a spin about a principal axis does not turn). A real wobble of
# 1e-12 |omega| still turns at the Euler frequency.
_ROUNDING = 1e-13


def _principal(moments, axes, omega):
    """(moments, axes, omega's principal-frame components) broadcast together."""
    moments = np.asarray(moments, dtype=float)
    axes = np.asarray(axes, dtype=float)
    omega = np.asarray(omega, dtype=float)
    # Row k of ``axes`` is principal axis k in the frame of omega, so axes @ omega are omega's principal components.
    return moments, axes, np.einsum("...ij,...j->...i", axes, omega)


def _principal_rates(moments, wp):
    """Euler's torque-free equations in the principal frame: ``I_i dw_i/dt = ((I w) x w)_i`` (notes 5.5)."""
    return np.cross(moments * wp, wp) / moments


def omega_dot(moments, axes, omega) -> np.ndarray:
    """``d omega/dt`` (rad/s^2) of a torque-free rigid body at angular velocity ``omega``.

    Euler's equations with one point fixed and no torque, ``I d omega/dt = (I omega) x omega``
    (course notes 5.5, p. 68), in the frame ``omega`` is given in.

    Parameters
    ----------
    moments : array_like, (..., 3)
        Principal moments (kg m^2), all positive.
    axes : array_like, (..., 3, 3)
        Row ``k``: the unit principal axis of ``moments[k]`` in the frame of ``omega`` (an orthogonal
        matrix; the identity when omega is given in the principal frame).
    omega : array_like, (..., 3)
        Angular velocity (rad/s) in that frame.

    Returns
    -------
    ndarray, (..., 3)
        ``d omega/dt`` in the same frame.
    """
    moments, axes, wp = _principal(moments, axes, omega)
    return np.einsum("...ji,...j->...i", axes, _principal_rates(moments, wp))


def polhode_turn_rate(moments, axes, omega) -> np.ndarray:
    """The angular speed (rad/s) at which a free body's omega runs round its polhode, at each ``omega``.

    omega circles the principal axis of largest moment when ``L^2 > 2 T I_mid`` and of smallest
    otherwise (Landau & Lifshitz, Mechanics, sec. 37); its speed about that axis ``a`` is
    ``|a . (w_perp x w_perp_dot)| / |w_perp|^2``, ``w_perp`` the part of omega across ``a`` and its
    derivative from Euler's equations (:func:`omega_dot`). For a symmetric body, the Euler frequency
    ``|(C - A)/A omega_3|`` (notes 5.6, p. 69).

    Parameters
    ----------
    moments, axes, omega : array_like
        As in :func:`omega_dot`: principal moments (..., 3), all positive; their axes (..., 3, 3) in
        the frame of ``omega``; angular velocities (..., 3), rad/s.

    Returns
    -------
    ndarray
        The rate (rad/s), omega's leading shape: 0 for a spin about a principal axis (omega across
        ``a`` below 1e-13 of ``|omega|``) and for a body at rest; NaN where omega is not finite. On the
        separatrix (``L^2 = 2 T I_mid`` exactly) omega turns about no axis; the rate about the axis the
        comparison picks is returned, and a change of omega in its last bit can pick the other.
    """
    moments, axes, wp = _principal(moments, axes, omega)
    moments = np.broadcast_to(moments, wp.shape)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        wdot = _principal_rates(moments, wp)
        twice_t, l_squared = np.sum(moments * wp**2, axis=-1), np.sum((moments * wp) ** 2, axis=-1)
        about_largest = l_squared > twice_t * np.median(moments, axis=-1)
        a = np.eye(3)[np.where(about_largest, np.argmax(moments, axis=-1), np.argmin(moments, axis=-1))]
        perp = wp - np.sum(wp * a, axis=-1, keepdims=True) * a
        perp_dot = wdot - np.sum(wdot * a, axis=-1, keepdims=True) * a
        turn = np.abs(np.sum(a * np.cross(perp, perp_dot), axis=-1))
        size = np.sum(perp**2, axis=-1)
        # |w_perp|^2 against (rounding x |w|)^2, both in rad^2/s^2: a small wobble of a fast spin is a wobble.
        rates = np.where(size > _ROUNDING**2 * np.sum(wp**2, axis=-1), turn / size, 0.0)
    return np.where(np.all(np.isfinite(wp), axis=-1), rates, np.nan)


def wobble_angle_rate(moments, axes, omega) -> np.ndarray:
    """d/dt of the wobble angle, ``atan2(|(omega_1, omega_2)|, omega_3)``, the angle between omega and body
    axis 3 (rad/s), of a torque-free body, from Euler's equations (:func:`omega_dot`).

    Parameters are those of :func:`omega_dot` (``omega`` in the body frame whose axis 3 the angle is
    measured from); the result has omega's leading shape. Where omega lies on axis 3 (the angle's
    derivative there is that of ``|omega_perp|``), the rate of ``|(omega_1, omega_2)|`` over ``|omega|``;
    0 for a body at rest.
    """
    w = np.asarray(omega, dtype=float)
    wd = omega_dot(moments, axes, w)
    across = np.hypot(w[..., 0], w[..., 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        across_dot = np.where(
            across > 0, (w[..., 0] * wd[..., 0] + w[..., 1] * wd[..., 1]) / across, np.hypot(wd[..., 0], wd[..., 1])
        )
        # d/dt atan2(a, w3) = (w3 a' - a w3') / (a^2 + w3^2); 0/0 for a body at rest.
        return np.nan_to_num((w[..., 2] * across_dot - across * wd[..., 2]) / np.sum(w * w, axis=-1))
