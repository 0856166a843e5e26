"""PGA speed and accuracy: budget.sar.pga against fastsar's PGA on one 512×512 image.

Run from the repository root:  python3 benchmarks/bench_pga.py [--fastsar-python PATH] [--repeat N]

The image: 512 × 512 complex, azimuth along axis 0, 12 point targets (unit-ish amplitudes,
random positions), receiver noise 50 dB below a unit target's peak, an unweighted aperture
filling 80 % of the azimuth band, and a smooth phase error injected on the phase history
(6 u² + 3 u³ + 2 sin(1.5πu) rad, u ∈ [−1, 1] over the aperture).

Residual (method-agnostic): the phase of Σ_r G_out(k, r) G_ideal*(k, r) over the aperture bins,
constant and linear terms removed (a shift), rms in rad — the phase error each corrected image
still carries, whatever convention the autofocus uses internally.

fastsar is NEVER a dependency of this project: install it only in a separate environment, e.g.
    python3 -m venv /tmp/fastsar-venv && /tmp/fastsar-venv/bin/pip install fastsar
and pass that interpreter with --fastsar-python (default /tmp/fastsar-venv/bin/python). Without
it, only this project's figures are printed.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from budget.sar import pga  # noqa: E402
from budget.sar.phase import smooth_phase_error  # noqa: E402

N = 512


def make_image(seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(defocused image, ideal image, aperture mask on centred bins)."""
    rng = np.random.default_rng(seed)
    k = np.arange(N) - N // 2  # centred azimuth-frequency bins
    support = np.abs(k) < 0.4 * N
    u = np.where(support, k / (0.4 * N), 0.0)
    psi = np.where(support, smooth_phase_error(u, quadratic_rad=6.0, cubic_rad=3.0, sinusoid_rad=2.0,
                                               sinusoid_cycles=1.5), 0.0)
    n_t = 12
    xs = rng.uniform(0.1 * N, 0.9 * N, n_t)
    rs = rng.choice(np.arange(20, N - 20, 8), n_t, replace=False) + rng.uniform(0, 1, n_t)
    amp = rng.uniform(0.6, 1.0, n_t) * np.exp(2j * np.pi * rng.uniform(size=n_t))
    # phase history (centred bins) of each target, and range response (unweighted sinc, 80 % band)
    hist = np.zeros((N, N), dtype=complex)
    r = np.arange(N)
    for x, r0, a in zip(xs, rs, amp):
        az = support * np.exp(2j * np.pi * k * x / N)
        rg = np.sinc(0.8 * (r - r0))
        hist += a * az[:, None] * rg[None, :]
    scale = 1.0 / support.sum()  # unit target → unit peak
    noise = (rng.standard_normal((N, N)) + 1j * rng.standard_normal((N, N))) * np.sqrt(0.5) * 10 ** (-50 / 20)
    ideal = np.fft.fft(np.fft.ifftshift(hist, axes=0), axis=0) * scale + noise
    bad_hist = np.fft.ifft(ideal, axis=0) * np.fft.ifftshift(np.exp(1j * psi))[:, None]
    return np.fft.fft(bad_hist, axis=0), ideal, support


def residual_rad(out: np.ndarray, ideal: np.ndarray, support: np.ndarray) -> float:
    cross = np.fft.fftshift((np.fft.ifft(out, axis=0) * np.conj(np.fft.ifft(ideal, axis=0))).sum(axis=1))
    ph = np.unwrap(np.angle(cross[support]))
    k = np.arange(ph.size)
    ph = ph - np.polyval(np.polyfit(k, ph, 1), k)
    return float(np.sqrt(np.mean(ph ** 2)))


FASTSAR_SNIPPET = r"""
import json, sys, time, numpy as np
from fastsar.autofocus import pga
img = np.load(sys.argv[1]); reps = int(sys.argv[2])
out = pga(img)  # warm-up
times = []
for _ in range(reps):
    t = time.perf_counter(); out = pga(img); times.append(time.perf_counter() - t)
np.save(sys.argv[3], np.asarray(out[0]))
print(json.dumps({"time_s": float(np.median(times)), "iterations": len(out[2])}))
"""


def chain_timings(repeat: int) -> None:
    """Median time of each step of the Monte Carlo chain for the airborne_xband preset."""
    from budget.presets import get_preset
    from budget.sar import (SarGeometry, Scene, form_image, los_offset_for_phase, measure_targets,
                            simulate_echoes)
    from budget.sar.phase import normalised_time
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene.default(g)
    off = los_offset_for_phase(g, smooth_phase_error(normalised_time(g), quadratic_rad=6.0, cubic_rad=3.0,
                                                     sinusoid_rad=2.0, sinusoid_cycles=1.5))
    rng = np.random.default_rng(0)
    steps = {"echoes": [], "image (rda)": [], "metrics": [], "pga": [], "metrics after": [], "total": []}
    for _ in range(repeat + 1):
        t0 = time.perf_counter()
        data = simulate_echoes(g, scene, off, rng)
        t1 = time.perf_counter()
        img = form_image(g, data, np.zeros((g.n_pulses, 3)))
        t2 = time.perf_counter()
        measure_targets(img, g, scene)
        t3 = time.perf_counter()
        res = pga(img.data)
        t4 = time.perf_counter()
        measure_targets(img.with_data(res.image), g, scene)
        t5 = time.perf_counter()
        for k, v in zip(steps, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t5 - t0)):
            steps[k].append(v)
    print(f"chain, airborne_xband ({g.n_pulses} pulses × {g.n_range} bins, 5 targets), median of {repeat}:")
    for k, v in steps.items():
        print(f"  {k:14s} {1e3 * float(np.median(v[1:])):7.1f} ms")
    print(f"  → {1.0 / float(np.median(steps['total'][1:])):.1f} trials/s (one process)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fastsar-python", default="/tmp/fastsar-venv/bin/python")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--no-chain", action="store_true", help="skip the chain timings")
    args = ap.parse_args()
    if not args.no_chain:
        chain_timings(max(args.repeat, 10))
    bad, ideal, support = make_image()
    print(f"image {N}×{N}, aperture {support.sum()} bins, injected phase error peak-to-peak "
          f"{np.ptp(np.angle(np.fft.ifft(bad, axis=0).sum(axis=1))):.1f} rad (wrapped view)")
    print(f"residual before autofocus: {residual_rad(bad, ideal, support):.3f} rad rms")
    for kernel in ("ml", "lumv"):
        res = pga(bad, kernel=kernel)
        times = []
        for _ in range(args.repeat):
            t = time.perf_counter()
            res = pga(bad, kernel=kernel)
            times.append(time.perf_counter() - t)
        ours = float(np.median(times))
        print(f"budget.sar.pga ({kernel}):  {1e3 * ours:8.1f} ms  residual {residual_rad(res.image, ideal, support):.4f} "
              f"rad rms  ({res.iterations} iterations, {res.reason})")
        if kernel == "ml":
            ours_ml = ours
    py = Path(args.fastsar_python)
    if not py.exists():
        print(f"fastsar: not run ({py} not found; install fastsar in a separate venv, see the docstring)")
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "img.npy", Path(tmp) / "out.npy"
        np.save(src, bad)
        proc = subprocess.run([str(py), "-c", FASTSAR_SNIPPET, str(src), str(args.repeat), str(dst)],
                              capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            print("fastsar: failed to run:", proc.stderr.strip().splitlines()[-1:])
            return 0
        info = json.loads(proc.stdout.strip().splitlines()[-1])
        out = np.load(dst)
    print(f"fastsar.autofocus.pga (ml): {1e3 * info['time_s']:8.1f} ms  residual "
          f"{residual_rad(out, ideal, support):.4f} rad rms  ({info['iterations']} iterations)")
    print(f"speed-up (ml): {info['time_s'] / ours_ml:.1f}×")
    return 0


if __name__ == "__main__":
    sys.exit(main())
