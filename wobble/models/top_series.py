"""The heavy top's series accelerator: its periodic parts as Fourier series (SI, float64; notes 5.7).

The nutating top's theta(r), the periodic parts of its half angles and dtheta/dr are
analytic and 2K-periodic in the reduced nutation phase r while the axis stays off the
poles (:meth:`wobble.models.top_closed_form.Elliptic.periodic_of_r`). Their Fourier
coefficients decay geometrically; :func:`build` computes them once per top by an FFT
of exact values and tabulates the series with their derivatives as Taylor expansions
at equispaced nodes, so that each output costs a degree-5 polynomial instead of
Jacobi functions and Carlson integrals (~3 us). The table is used only after it
reproduces the direct evaluation between the nodes within the solution's error
estimate; otherwise the model keeps the direct path.

The table of a top is built on first use and kept in :func:`series_of`'s cache, keyed
by the model and released with it: the frozen model itself holds no mutable state.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, replace

import numpy as np

from wobble.numerics import compiled

__all__ = ["MIN_SAMPLES", "Fourier", "build", "series_of"]

_EPS = float(np.finfo(float).eps)


_TAYLOR_ORDER = 5


@dataclass(frozen=True)
class Fourier:
    """The periodic parts as Fourier series in the nutation phase (fast evaluation).

    theta(r) (even), k_- P_-(r), k_+ P_+(r) and dtheta/dr (odd) are analytic and
    2K-periodic in the reduced phase r while the axis stays off the poles; their
    Fourier coefficients in vartheta = pi r / K decay geometrically and are computed
    once by an FFT of exact values (:meth:`~wobble.models.top_closed_form.Elliptic.periodic_of_r`). For evaluation
    the series are tabulated with their derivatives up to order 5 at S equispaced
    phases (one batched inverse FFT), and each output takes a degree-5 Taylor
    polynomial from the nearest node: one gather per order and 5 Horner steps per series,
    whatever the series' length. The table is accepted only after it agrees with the
    direct evaluation between the nodes to within the solution's error estimate
    (:func:`build`); otherwise the direct path is used.
    """

    base: object  # the Elliptic evaluator (wobble.models.top_closed_form)
    coef: np.ndarray  # (4, L + 1): theta (cos), sigma_p (sin), delta_p (sin), dtheta/dr (sin)
    kinds: tuple  # "cos" or "sin" per row
    scale: float  # pi / K
    table: np.ndarray  # (4, order + 1, S): f^(j)(node) / j! in units of r
    h: float  # node spacing in r
    error_theta: float
    error_phase: float

    def clenshaw(self, r, rows):
        """The series summed directly (Clenshaw), for building and checking the table."""
        vt = r * self.scale
        c, s_ = np.cos(vt), np.sin(vt)
        alpha = 2.0 * c
        coef = self.coef[list(rows)]
        nrow, ncoef = coef.shape
        b1 = np.zeros((nrow,) + r.shape)
        b2 = np.zeros_like(b1)
        tmp = np.empty_like(b1)
        for k in range(ncoef - 1, 0, -1):
            np.multiply(alpha, b1, out=tmp)
            tmp -= b2
            tmp += coef[:, k, None]
            b1, b2, tmp = tmp, b1, b2
        out = []
        for i, row in enumerate(rows):
            out.append(coef[i, 0] + b1[i] * c - b2[i] if self.kinds[row] == "cos" else b1[i] * s_)
        return out

    def series(self, r, rows):
        """The series at reduced phases r from the Taylor table (nearest node, Horner).

        One contiguous 1-D table per series and order, gathered with np.take (the
        tables stay in cache; fancy indexing of a 3-D table was three times slower);
        long arrays in one compiled pass instead (:mod:`wobble.numerics.taylor_table`).
        """
        if r.size >= compiled.LONG_ARRAY and compiled.available():  # one pass, bit for bit the sum below
            from wobble.numerics import taylor_table

            return taylor_table.series(r, self.base.K[0], self.h, self.table, rows)
        u = (r + self.base.K[0]) * (1.0 / self.h)
        idx = np.rint(u)
        d = (u - idx) * self.h
        ii = idx.astype(np.intp)
        nodes = self.table.shape[2]
        ii[ii >= nodes] -= nodes  # r = +K is the node of r = -K
        out = []
        for row in rows:
            tab = self.table[row]
            acc = np.take(tab[_TAYLOR_ORDER], ii)
            for j in range(_TAYLOR_ORDER - 1, -1, -1):
                acc *= d
                acc += np.take(tab[j], ii)
            out.append(acc)
        return out

    def angles_core(self, t):
        e = self.base
        r, j = e.phase(t)
        theta, sp, dp = self.series(r, (0, 1, 2))
        sig = e.sigma_sec(j, r, e.w0)
        dlt = e.delta_sec(j, r, e.w0)
        return theta, sig + (sp - e.k_minus * e.p_minus0), dlt + (dp - e.k_plus * e.p_plus0)

    def core(self, t):
        e = self.base
        r, j = e.phase(t)
        theta, sp, dp, dth = self.series(r, (0, 1, 2, 3))
        half = 0.5 * theta
        sh, ch = np.sin(half), np.cos(half)
        x, y = 2.0 * sh * sh, 2.0 * ch * ch
        bx, cy = e.B / x, e.C / y
        sig = e.sigma_sec(j, r, e.w0)
        dlt = e.delta_sec(j, r, e.w0)
        return dict(
            sh=sh, ch=ch, sigma=sig + (sp - e.k_minus * e.p_minus0), delta=dlt + (dp - e.k_plus * e.p_plus0),
            thetadot=e.lam[0] * dth, phidot=0.5 * (bx + cy), psidot=(e.omega3 - e.a) - 0.5 * (bx - cy),
            u=np.where(x <= 1.0, 1.0 - x, y - 1.0), phidot_sin=0.5 * (e.B * ch / sh + e.C * sh / ch),
        )


#: From this many samples on, the model evaluates through the series (where verified).
MIN_SAMPLES = 1024
_FOURIER_MAX_N = 512
_FOURIER_MAX_TERMS = 96
_TAYLOR_MAX_NODES = 1 << 15


def build(e, est: dict) -> Fourier | None:
    """Fourier series of the periodic parts of ``e``, verified; None where not worth it.

    Four 2K-periodic functions of the reduced phase are sampled exactly at N
    equispaced phases: theta (even), k_- P_- and k_+ P_+ (odd) and dtheta/dr (odd,
    sampled from its closed form rather than by differentiating the theta series,
    which would amplify the rounding of theta's samples). N doubles until the upper
    half of every spectrum is at rounding level; the series must then reproduce the
    direct evaluation between the nodes within the solution's error estimate.
    Used only off the poles (x, y > 0 on the orbit).
    """
    if e.through_top or e.through_bottom:
        return None
    k = e.K[0]
    noise = 8 * _EPS  # the FFT of exact values has a noise floor of a few eps
    sample = e.periodic_of_r
    # Check points between the nodes (phases offset by an irrational fraction of the spacing).
    m = 41
    vt = -np.pi + 2 * np.pi * (np.arange(m) + 0.6180339887498949) / m
    r_check = vt * (k / np.pi)
    want = None
    for n in (64, 128, 256, _FOURIER_MAX_N):
        vt = 2 * np.pi * np.arange(n) / n
        vt = np.where(vt > np.pi, vt - 2 * np.pi, vt)
        if want is None:  # nodes and check points in one pass of the direct path
            both = sample(np.concatenate([vt * (k / np.pi), r_check]))
            vals = [v[:n] for v in both]
            want = [v[n:] for v in both]
        else:
            vals = sample(vt * (k / np.pi))
        spectra = [np.fft.rfft(v) / n for v in vals]
        scales = [max(float(np.max(np.abs(v))), 1e-300) for v in vals]
        scales[1] = scales[2] = max(1.0, scales[1], scales[2])  # phases: absolute (rad)
        # Aliasing folds c_{n-k} onto c_k: only the top of the band must be at rounding
        # level; the check against the direct evaluation below decides.
        if not all(np.max(np.abs(sp[7 * n // 16 :])) <= noise * sc for sp, sc in zip(spectra, scales)):
            continue
        fo = _fourier_from_spectra(e, spectra, scales, k)
        if fo is None:
            return None  # too long a series: the direct path is about as fast
        checked = _check_fourier(fo, r_check, want, scales[3], est, k)
        if checked is not None:
            return checked
    return None


def _fourier_from_spectra(e, spectra, scales, k):
    kinds = ("cos", "sin", "sin", "sin")
    rows = []
    for sp, kind in zip(spectra, kinds):
        if kind == "cos":
            c = 2 * sp.real
            c[0] = sp[0].real
        else:
            c = -2 * sp.imag
            c[0] = 0.0
        rows.append(c)
    big = np.maximum.reduce([np.abs(c) / sc for c, sc in zip(rows, scales)])
    keep = np.nonzero(big > 0.25 * _EPS)[0]
    last = int(keep.max()) if keep.size else 1
    if last > _FOURIER_MAX_TERMS:
        return None
    coef = np.stack([c[: last + 1] for c in rows])
    scale = np.pi / k
    nodes = 1 << max(8, int(np.ceil(np.log2(32 * (last + 1)))))
    return Fourier(base=e, coef=coef, kinds=kinds, scale=scale, table=_taylor_table(coef, kinds, nodes, scale),
                    h=2 * k / nodes, error_theta=0.0, error_phase=0.0)


def _check_fourier(fo, r, want, dscale, est, k):
    """The table if it reproduces the direct values within the error estimate (finer tables
    are tried first); None otherwise."""
    while fo.table.shape[2] <= _TAYLOR_MAX_NODES:
        got = fo.series(r, (0, 1, 2, 3))
        err_t = float(np.max(np.abs(got[0] - want[0])))
        err_p = max(float(np.max(np.abs(got[1] - want[1]))), float(np.max(np.abs(got[2] - want[2]))))
        err_d = float(np.max(np.abs(got[3] - want[3]))) / dscale
        if err_t <= est["theta_rad"] and err_p <= est["attitude_rad"] and err_d <= 64 * _EPS * (1 + k):
            return replace(fo, error_theta=err_t, error_phase=err_p)
        nodes = 2 * fo.table.shape[2]
        if nodes > _TAYLOR_MAX_NODES:
            break
        fo = replace(fo, table=_taylor_table(fo.coef, fo.kinds, nodes, fo.scale), h=fo.h / 2)
    return None


def _taylor_table(coef, kinds, nodes, scale):
    """f^(j)(r_i)/j! (j = 0.._TAYLOR_ORDER, r-units) of every series at the nodes r_i = -K + i h.

    With vartheta_i = -pi + 2 pi i / S, e^{i k vartheta_i} = (-1)^k e^{2 pi i k i / S}, so
    Re sum_k c_k (i k scale)^j e^{i k vartheta_i} for all rows and orders is one batched
    real inverse FFT (cos series: c_k = a_k; sin series: c_k = -i b_k).
    """
    nrow, ncoef = coef.shape
    kk = np.arange(ncoef)
    sign = np.where(kk % 2 == 0, 1.0, -1.0)
    orders = np.arange(_TAYLOR_ORDER + 1)
    fact = np.cumprod(np.concatenate([[1.0], np.arange(1, _TAYLOR_ORDER + 1)]))
    rot = np.array([1.0 if k == "cos" else -1j for k in kinds])[:, None, None]
    power = (1j * kk[None, :] * scale) ** orders[:, None]  # (order + 1, ncoef)
    c = coef[:, None, :] * sign * power[None] * rot / fact[None, :, None]  # (rows, order + 1, ncoef)
    spec = np.zeros((nrow, _TAYLOR_ORDER + 1, nodes // 2 + 1), dtype=complex)
    spec[..., :ncoef] = c
    spec[..., 1:] *= 0.5  # irfft counts each k >= 1 twice (Hermitian extension)
    return np.fft.irfft(spec, n=nodes, axis=-1) * nodes


# The table of each model, built on first use: keyed by id(model), dropped when the model is
# collected (weakref.finalize), so a frozen model stays immutable and the cache never grows
# with models that are gone.
_TABLES: dict[int, Fourier | None] = {}


def series_of(owner, e, est: dict) -> Fourier | None:
    """The verified series of the evaluator ``e`` of model ``owner`` (built once), or None.

    ``owner`` is the object the table belongs to (the frozen model): the table lives
    here, not in it, for as long as ``owner`` does.
    """
    key = id(owner)
    try:
        return _TABLES[key]
    except KeyError:
        pass
    table = build(e, est)
    _TABLES[key] = table
    weakref.finalize(owner, _TABLES.pop, key, None)
    return table
