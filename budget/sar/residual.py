"""What PGA cannot remove: ONE definition, used by the Monte Carlo verdict and the analytic bounds.

PGA estimates the phase error from the dominant scatterers inside a window of W azimuth samples
around each of them (Wahl et al. 1994, step 3). A phase component of k cycles over the aperture
puts paired echoes k·n/n_ap samples from the target (n image samples, n_ap of them inside the
aperture band; a sinusoid of amplitude β gives paired echoes at 20·log10(β/2) dB). Once
PGA's window has settled to W samples, components of more than

    K = W · n_ap / (2 n)  cycles per aperture                                  (1)

put their energy outside the window: the settled PGA neither sees nor corrects them. Components
up to K land inside the window, where the image metrics (broadening, PSLR, ISLR, peak loss)
already judge what is left of them.

Definition. The phase over the aperture bins is fitted (least squares) with what PGA removes:
the Legendre polynomials up to the cubic (constant and linear only move the image; quadratic and
cubic are PGA's first job, seed 004) and the DCT-II cosines cos(π j (i + ½)/n) up to j = 2K
(index j is j/2 cycles per aperture, so these are the components up to K cycles). What is left
is what PGA cannot remove. (The polynomials are in the basis because a smooth trend is not
band-limited for the DCT: its even extension has kinks at the aperture ends, so a large
quadratic would otherwise leak into the "fast" part.)

* Monte Carlo: the residual r = (PGA estimate − true phase) high-passed above 2K, its rms
  weighted by the aperture's signal energy per bin (the weight with which a phase error moves
  main-lobe energy into sidelobes: a small phase error of rms σ moves σ² of it), the fit of the
  removable part weighted by the same energy (bins that carry little signal — a Taylor window's
  ends — do not decide what is called removable where the signal is);
  :func:`pga_residual_rms_rad`;
* analytic: the true phase high-passed above 2K (PGA is credited with nothing beyond its settled
  window, a worst case: on clean isolated points its early wide-window iterations also remove part
  of the fast phase), whose expected rms for random walks is exact from the covariance of the
  integrated white noise (no Monte Carlo), fitted and averaged with the same weight — the energy
  w² of the aperture's amplitude window, which the signal energy per bin follows (the verdict's
  Taylor window on radar; 'rect' = unweighted, the bounds' conservative default);
  :func:`random_walk_highpass_rms`.

Both share :func:`highpass_phase`; the bounds (:mod:`budget.bounds.fast_phase`,
:mod:`budget.bounds.lever_arm`) and the Monte Carlo (:mod:`budget.mc.chain`) call this module.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import scipy.fft as sfft

from .windows import Window

#: PGA's smallest window in resolution cells, the floor the Monte Carlo gives PGA
#: (:func:`budget.mc.chain.pga_min_window`, where the choice is measured): a window of W samples
#: spans W·n_ap/n cells of an image of n azimuth samples, n_ap of them in the aperture band.
PGA_MIN_WINDOW_CELLS = 4.0
#: K of (1) the analytic bounds use when no PGA run tells them the settled window: the K of a
#: settled window at the Monte Carlo's floor, W·n_ap/(2n) = 4 cells / 2 = 2 cycles per aperture,
#: whatever the image's sampling — one definition for both (measured K = 2.03–2.05 on the presets'
#: images). The bounds used 2.5 (PGA's former 8-sample floor) until the per-trial distribution
#: showed the difference: 77 GHz, ADIS16405, P(≤ 1°) 0.960 at 2.5, 0.918 at 2.0 against the
#: Monte Carlo's 0.922.
DEFAULT_PGA_BANDWIDTH_CYCLES = PGA_MIN_WINDOW_CELLS / 2.0

#: The share of apertures a verdict asks to pass: the Monte Carlo's decision target (P(pass after
#: PGA), :func:`budget.mc.sweep.cheapest_passing`) and the share of apertures the analytic
#: fast-phase limits keep within their limit (:func:`random_walk_rms_quantile`), one number so
#: that the two verdicts ask the same of a part.
DEFAULT_PASS_SHARE = 0.9


def pga_bandwidth_cycles(final_window_samples: float, n_bins: int, n_aperture_bins: int) -> float:
    """K of (1): cycles per aperture inside PGA's settled window of ``final_window_samples``."""
    if not (final_window_samples > 0 and n_bins > 0 and n_aperture_bins > 0):
        raise ValueError("window, bins and aperture bins must be > 0")
    return float(final_window_samples) * n_aperture_bins / (2.0 * n_bins)


@lru_cache(maxsize=256)
def _legendre_columns(n: int) -> tuple[np.ndarray, ...]:
    """P0…P3 (Legendre) on n points of [−1, 1] (fewer for n < 4)."""
    u = np.linspace(-1.0, 1.0, n)
    return tuple(np.polynomial.legendre.legval(u, np.eye(4)[k]) for k in range(min(4, n)))


# PGA's fast-phase stage asks for a basis per span and window (tens of sizes in a Monte Carlo run)
@lru_cache(maxsize=256)
def _removable_basis(n: int, n_cos: int) -> np.ndarray:
    """B = [P0…P3 (Legendre), DCT-II cosines 1…n_cos] on n points (n × columns; read-only)."""
    cols = list(_legendre_columns(n))
    i = np.arange(n) + 0.5
    cols += [np.cos(np.pi * j * i / n) for j in range(1, min(n_cos, n - 1) + 1)]
    b = np.stack(cols, axis=1)
    b.setflags(write=False)
    return b


@lru_cache(maxsize=32)
def _removable_projector(n: int, n_cos: int) -> np.ndarray:
    """I − B B⁺ for B of :func:`_removable_basis`."""
    b = _removable_basis(n, n_cos)
    return np.eye(n) - b @ np.linalg.pinv(b)


def highpass_phase(phase_rad, cutoff_cycles: float, weight=None) -> np.ndarray:
    """The part of ``phase_rad`` (rad, over the aperture bins) beyond PGA's bandwidth of
    ``cutoff_cycles`` cycles per aperture: least-squares residual after the Legendre terms up to
    the cubic and the DCT-II cosines up to index ⌊2·cutoff⌋ (module docstring). ``weight``
    (≥ 0 per bin, e.g. the signal energy) makes the fit weighted least squares: bins that carry
    no signal then do not steer what is called removable where the signal is. A 2-D
    ``phase_rad`` (bins × columns) is high-passed column by column."""
    x = np.asarray(phase_rad, dtype=float)
    n = x.shape[0]
    if n < 6:
        return np.zeros_like(x)
    n_cos = int(math.floor(2.0 * cutoff_cycles))
    if weight is None:
        return _removable_projector(n, n_cos) @ x
    w = np.asarray(weight, dtype=float)
    if w.shape != (n,) or not np.all(np.isfinite(w)) or np.any(w < 0) or not np.any(w > 0):
        raise ValueError("weight must be finite, ≥ 0, not all zero, one per bin")
    b = _removable_basis(n, n_cos)
    sw = np.sqrt(w / w.max()).reshape((n,) + (1,) * (x.ndim - 1))
    coef, *_ = np.linalg.lstsq(b * sw.reshape(n, 1), x * sw, rcond=None)
    return x - b @ coef


def pga_residual_rms_rad(estimate_rad, truth_rad, mask, weight, cutoff_cycles: float) -> float:
    """Energy-weighted rms (rad) of (estimate − truth) over the aperture bins ``mask`` beyond
    ``cutoff_cycles`` (the definition in the module docstring); nan when < 8 bins."""
    m = np.asarray(mask, bool) & np.isfinite(truth_rad) & np.isfinite(estimate_rad)
    if m.sum() < 8:
        return math.nan
    w = np.asarray(weight, float)[m]
    if not np.any(w > 0):
        w = np.ones_like(w)
    r = highpass_phase(np.asarray(estimate_rad, float)[m] - np.asarray(truth_rad, float)[m], cutoff_cycles, w)
    return float(math.sqrt(np.sum(w * r * r) / np.sum(w)))


def phase_history_energy(image_data) -> np.ndarray:
    """Signal energy per azimuth-frequency bin (centred order, as PGA's estimate): Σ_r |G(k, r)|²."""
    g = sfft.ifft(np.asarray(image_data), axis=0)
    return np.fft.fftshift((np.abs(g) ** 2).sum(axis=1))


#: Random processes the analytic residual knows: power p of e(t) = ∫₀ᵗ (t − s)^p/p! dW(s).
#: ``vrw``: accelerometer white noise → position (p = 1); ``arw``: gyro white noise → tilt →
#: gravity → position (p = 2, × g); ``rw``: a random walk itself, e.g. ARW attitude noise seen
#: through a lever arm d (p = 0, × |d|).
KIND_POWER = {"rw": 0, "vrw": 1, "arw": 2}


def random_walk_highpass_rms(kind: str, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                             n: int = 800, window: Window | str = "rect") -> float:
    """√E[r²] of :func:`highpass_phase` applied to the ``kind`` random walk over t ∈ [0, 1] s
    with unit noise density (exact: covariance of e on an n-point grid, no sampling).

    ``window``: the aperture's amplitude weighting w(t) ('rect', 'taylor' or a
    :class:`~budget.sar.windows.Window`). Its energy w² weights the fit of the removable part and
    the mean of r² — the weight the Monte Carlo uses (the signal energy per azimuth bin, which
    for a weighted aperture follows w²): E[Σ w² r²]/Σ w². 'rect' is the unweighted mean, the
    larger value for a random walk (its residual is largest at the aperture's ends, where a
    Taylor window puts little energy).

    Scale: ``rw`` × N·√Tc, ``vrw`` × N·Tc^1.5, ``arw`` × g·N·Tc^2.5 (N per √s: rad/√s or
    m/s²/√Hz) — a position (m) to turn into phase with 4π/λ.
    """
    return _random_walk_highpass_rms(kind, float(cutoff_cycles), int(n), Window.parse(window))


def random_walk_highpass_eigenvalues(kind: str, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                                     n: int = 400, window: Window | str = "rect") -> np.ndarray:
    """The weights λ_i (descending, Σλ_i = 1) of the mean square beyond PGA's bandwidth of the
    ``kind`` random walk, r̄² = E[r̄²]·Σ λ_i z_i² with z_i independent standard normal — its
    distribution from aperture to aperture, not only its mean (:func:`random_walk_highpass_rms`
    gives E[r̄²]). Exact on an n-point grid: r̄² = ‖B dW‖² with B = diag(√(q/Σq)) H K (H the
    highpass, K the walk's kernel, q the energy weight), so the λ_i are B's squared singular
    values. A random walk's residual is dominated by its first few modes (on the Taylor window
    beyond 2 cycles the largest λ is 0.44 for ARW, 0.34 for VRW), so its rms scatters widely
    about √E[r̄²]: a per-trial limit is met less often than the rms suggests
    (:func:`random_walk_rms_quantile`)."""
    return _random_walk_highpass_eigenvalues(kind, float(cutoff_cycles), int(n), Window.parse(window)).copy()


def random_walk_rms_quantile(kind: str, share: float, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                             window: Window | str = "rect") -> float:
    """The ``share``-quantile of one aperture's rms beyond PGA's bandwidth of the ``kind`` random
    walk, in units of its rms over apertures √E[r̄²] (:func:`random_walk_highpass_rms`): the rms
    over apertures must be this many times below a limit for a ``share`` of apertures to meet it.
    Exact: √ of the quantile of Σ λ_i z_i² (:func:`random_walk_highpass_eigenvalues`, Σλ = 1)
    by Imhof's inversion (:func:`budget.quadform.quadratic_form_quantile_imhof`). At 2 cycles,
    share 0.9: 1.36 for VRW, 1.43 for ARW, 1.22 for a walk seen directly (Taylor window; the
    rms itself is met by only 0.58–0.63 of apertures)."""
    if not (0.0 < share < 1.0):
        raise ValueError("share must lie strictly between 0 and 1")
    return _random_walk_rms_quantile(kind, float(share), float(cutoff_cycles), Window.parse(window))


def random_walk_highpass_cross(kind_a: str, kind_b: str, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                               n: int = 800, window: Window | str = "rect") -> float:
    """E[Σ w² r_a r_b]/Σ w² for the ``kind_a`` and ``kind_b`` walks driven by *the same* unit white
    noise, each high-passed as in :func:`random_walk_highpass_rms` (which this is for
    ``kind_a == kind_b``, squared): the cross term of two effects of one sensor noise, e.g. a
    gyro's ARW seen through gravity (``arw``) and through a lever arm (``rw``) — correlation
    ≈ −0.70 beyond 2 cycles, far from the independence a root sum of squares assumes."""
    return _random_walk_highpass_cross(*sorted((kind_a, kind_b)), float(cutoff_cycles), int(n), Window.parse(window))


@lru_cache(maxsize=64)
def _random_walk_highpass_cross(kind_a: str, kind_b: str, cutoff_cycles: float, n: int, window: Window) -> float:
    ra, q = _highpassed_kernel(kind_a, cutoff_cycles, n, window)
    rb, _ = _highpassed_kernel(kind_b, cutoff_cycles, n, window)
    return float(np.sum(q[:, None] * ra * rb) * (1.0 / n) / q.sum())


def random_walk_mixture_eigenvalues(coefficients: dict, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                                    n: int = 400, window: Window | str = "rect") -> np.ndarray:
    """The weights λ_i (descending; Σλ_i = E[r̄²]) of the mean square beyond PGA's bandwidth of
    Σ_k c_k e_k, the walks of :data:`KIND_POWER` weighted by ``coefficients`` ({kind: c_k}) and
    all driven by one unit white noise (:func:`random_walk_highpass_eigenvalues` for one kind,
    there normalised to Σλ = 1): the exact distribution of one noise seen through several paths,
    the one-source case of :func:`random_walk_sources_eigenvalues`."""
    return random_walk_sources_eigenvalues([coefficients], cutoff_cycles, n=n, window=window)


def random_walk_sources_eigenvalues(sources, cutoff_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES,
                                    n: int = 400, window: Window | str = "rect") -> np.ndarray:
    """The weights λ_i (descending; Σλ_i = E[r̄²]) of the mean square beyond PGA's bandwidth of a
    phase made of *independent* sources, each Σ_k c_k e_k over the walks of :data:`KIND_POWER`
    driven by its own unit white noise (``sources``: a sequence of {kind: c_k}; one source:
    :func:`random_walk_mixture_eigenvalues`).

    The sources add before the mean square is taken: r̄² = ‖Σ_s B_s dW_s‖² (B_s as in
    :func:`random_walk_highpass_eigenvalues`), so the λ_i are the eigenvalues of Σ_s B_s B_sᵀ, the
    covariance of the summed residual. Pooling each source's own λ instead describes
    Σ_s ‖B_s dW_s‖², which has the same mean but leaves out the cross terms: two independent
    walks of one kind (e.g. the roll and pitch gyros' tilt seen on a squinted line of sight) sum
    to one walk of that kind, whose r̄² scatters as either does, where the pooled weights would
    halve its spread. Σ_s B_s B_sᵀ = Σ_{k,l} (Σ_s c_sk c_sl) B_k B_lᵀ, so the n × n products of the
    three kinds are formed once per bandwidth and window."""
    kinds = tuple(sorted(KIND_POWER))
    a = np.zeros((len(kinds), len(kinds)))
    for src in sources:
        unknown = set(src) - set(kinds)
        if unknown:
            raise ValueError(f"unknown kind(s) {sorted(unknown)}: expected 'rw', 'vrw' or 'arw'")
        c = np.array([float(src.get(k, 0.0)) for k in kinds])
        a += np.outer(c, c)
    scale = float(np.trace(a))
    if not scale > 0.0:
        return np.zeros(0)
    # one geometry, many parts: the shape of A is cached, its size scales λ
    unit = tuple(round(float(v), 12) for v in (a / scale).ravel())
    return scale * _sources_eigenvalues(unit, float(cutoff_cycles), int(n), Window.parse(window))


@lru_cache(maxsize=256)
def _sources_eigenvalues(unit: tuple, cutoff_cycles: float, n: int, window: Window) -> np.ndarray:
    k = len(KIND_POWER)
    a = np.asarray(unit).reshape(k, k)
    gram = _kind_products(cutoff_cycles, n, window)
    m = sum(a[i, j] * gram[i][j] for i in range(k) for j in range(k) if a[i, j] != 0.0)
    lam = np.linalg.eigvalsh(0.5 * (m + m.T))[::-1]
    lam = np.clip(lam, 0.0, None)
    lam.setflags(write=False)
    return lam


@lru_cache(maxsize=8)
def _kind_products(cutoff_cycles: float, n: int, window: Window) -> tuple:
    """B_k B_lᵀ (n × n) for the kinds of :data:`KIND_POWER` in sorted order."""
    bs = []
    for kind in sorted(KIND_POWER):
        r, q = _highpassed_kernel(kind, cutoff_cycles, n, window)
        bs.append(np.sqrt(q / q.sum())[:, None] * r * math.sqrt(1.0 / n))
    return tuple(tuple(bk @ bl.T for bl in bs) for bk in bs)


@lru_cache(maxsize=64)
def _random_walk_rms_quantile(kind: str, share: float, cutoff_cycles: float, window: Window) -> float:
    from ..quadform import quadratic_form_quantile_imhof

    lam = _random_walk_highpass_eigenvalues(kind, cutoff_cycles, 400, window)
    return float(math.sqrt(quadratic_form_quantile_imhof(lam, share)))


@lru_cache(maxsize=64)
def _random_walk_highpass_eigenvalues(kind: str, cutoff_cycles: float, n: int, window: Window) -> np.ndarray:
    ds = 1.0 / n
    r, q = _highpassed_kernel(kind, cutoff_cycles, n, window)
    b = np.sqrt(q / q.sum())[:, None] * r * math.sqrt(ds)
    lam = np.linalg.svd(b, compute_uv=False) ** 2
    return lam / lam.sum()


def _highpassed_kernel(kind: str, cutoff_cycles: float, n: int, window: Window) -> tuple[np.ndarray, np.ndarray]:
    """(H K, q): the highpass of the ``kind`` walk's kernel on an n-point grid of [0, 1] s, and
    the energy weight q (1 for rect)."""
    p = KIND_POWER.get(kind)
    if p is None:
        raise ValueError("kind must be 'rw', 'vrw' or 'arw'")
    ds = 1.0 / n
    t = (np.arange(n) + 0.5) * ds
    s = np.arange(n) * ds
    lag = np.clip(t[:, None] - s[None, :], 0.0, None)
    kernel = (lag > 0) * lag ** p / math.factorial(p) if p else (lag > 0).astype(float)
    rect = window.kind == "rect"
    q = np.ones(n) if rect else window.samples(n) ** 2
    return highpass_phase(kernel, cutoff_cycles, None if rect else q), q


@lru_cache(maxsize=64)
def _random_walk_highpass_rms(kind: str, cutoff_cycles: float, n: int, window: Window) -> float:
    # highpass_phase (a linear operator H) applied to every column of the kernel: r = H e with
    # e = kernel @ dW, var(dW) = ds → E[Σ_i q_i r_i²] = Σ_i q_i ‖(H kernel)_i‖² · ds, q = w² the
    # energy weight (1 for rect)
    r, q = _highpassed_kernel(kind, cutoff_cycles, n, window)
    return float(math.sqrt(np.sum(q[:, None] * r * r) * (1.0 / n) / q.sum()))
