"""PGA speed and accuracy, side by side with fastsar's PGA on the same images.

Run from the repository root:
    python3 benchmarks/bench_pga.py [--fastsar-python PATH] [--repeat N] [--gotcha DIR] [--no-chain]
                                    [--holdout]

Cases (all complex images, azimuth along axis 0, a smooth phase error multiplied onto the phase
history by this script's own code; nothing here calls the simulator):

(a) clutter: 512 × 512, aperture 80 % of the azimuth band, sinc range response (80 % band),
    10 or 40 point targets on distinct range lines with amplitudes log-uniform over 15 dB, complex
    Gaussian clutter band-limited to the same 2-D support at CTR −25 or −35 dB (mean clutter pixel
    power over the strongest target's peak power), receiver noise at SNR 30 dB, and an error
    6u² + 3c·u³ + 2 sin(1.5πu + φ0) scaled to 2 rad rms beyond a linear term (c, φ0 random);
    seeds 1–3;
(b) points: the former single case, 12 point targets, noise 50 dB below a unit target,
    6u² + 3u³ + 2 sin(1.5πu) rad;
(c) real chips: 128 × 128 chips of the Gotcha X-band image (pass 1, azimuth 0–4°, HH) formed by
    budget.sar.focus with the provider's recorded autofocus, then the same smooth 2 rad rms
    error injected along axis 0 (azimuth) or along axis 1 (the chip transposed, so that PGA works
    along the other axis). Skipped with a note if the data are absent. ``--holdout`` adds a second
    set: 32 chips on a 4 × 4 grid at other positions (offsets 20 … N − 148 pixels) with other
    error draws (seeds 500 …), never used to choose PGA's defaults, so that a default tuned to
    the 18 chips would show here.

Residual (method-agnostic): the phase of Σ_r G_out(k, r) G_ref*(k, r) over the bins that hold
signal, constant and linear terms removed (a shift), rms in rad: the phase error each corrected
image still carries relative to the reference, whatever convention the autofocus uses.

On the real chips the reference is the provider's focus, which is not a fixed point of either
autofocus: run on the unmodified chip, each PGA moves it (printed as "on ref"). The residual
against the reference then measures mostly that disagreement, so two reference-free figures are
printed beside it: *consistency*, the residual between a method's output with the injected error
and its own output without it (how much of the injected error it fails to absorb, whatever it
thinks of the reference), and the *sharpness gain* Σ|g|⁴/(Σ|g|²)² of its output over the
reference's (Fienup & Miller, JOSA A 20(4), 2003: a focus measure that needs no reference).
Times: median of --repeat runs after one warm-up, in one process each, on the same machine; wall
clock (time.perf_counter) and CPU seconds (time.process_time) — fastsar runs first, then ours, so
on a shared machine the two may meet different loads: the CPU ratio is the steadier one.

fastsar is NEVER a dependency of this project: install it only in a separate environment, e.g.
    python3 -m venv /tmp/fastsar-venv && /tmp/fastsar-venv/bin/pip install fastsar
and pass that interpreter with --fastsar-python (default /tmp/fastsar-venv/bin/python). Without
it, only this project's figures are printed.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from budget.sar.pga import pga  # noqa: E402
from budget.sar.phase import smooth_phase_error  # noqa: E402
from budget.sar.sharpness import image_sharpness  # noqa: E402

FRAC = 0.8


def _inject(ideal: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """``ideal`` with e^{jψ(k)} multiplied onto its phase history (inverse DFT along axis 0, ψ on
    centred bins)."""
    return np.fft.fft(np.fft.ifft(ideal, axis=0) * np.fft.ifftshift(np.exp(1j * psi))[:, None], axis=0)


def _smooth_error(support: np.ndarray, rms_rad: float, rng: np.random.Generator) -> np.ndarray:
    """6u² + 3c u³ + 2 sin(1.5πu + φ0) over the ``support`` bins, scaled to ``rms_rad`` beyond linear."""
    n = support.size
    k = np.arange(n) - n // 2
    idx = np.nonzero(support)[0]
    u = np.zeros(n)
    u[idx] = np.linspace(-1.0, 1.0, idx.size)
    psi = 6 * u ** 2 + 3 * rng.uniform(-1, 1) * u ** 3 + 2 * np.sin(1.5 * np.pi * u + rng.uniform(-np.pi, np.pi))
    beyond = psi[idx] - np.polyval(np.polyfit(k[idx], psi[idx], 1), k[idx])
    return np.where(support, psi * rms_rad / np.sqrt(np.mean(beyond ** 2)), 0.0)


def clutter_image(n_targets: int, ctr_db: float, seed: int, n: int = 512, snr_db: float = 30.0):
    """(defocused, reference, signal bins) of case (a)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n) - n // 2
    ap = np.abs(k) < FRAC * n / 2
    lines = rng.choice(np.arange(8, n - 8), n_targets, replace=False) + rng.uniform(-0.3, 0.3, n_targets)
    x = rng.uniform(0, n, n_targets)
    amp = 10 ** (-rng.uniform(0, 15.0, n_targets) / 20)
    amp[0] = 1.0
    amp = amp * np.exp(2j * np.pi * rng.uniform(size=n_targets))
    r = np.arange(n)
    hist = np.zeros((n, n), dtype=complex)
    for xi, ri, a in zip(x, lines, amp):
        hist += a * (ap * np.exp(2j * np.pi * k * xi / n))[:, None] * np.sinc(FRAC * (r - ri))[None, :]
    image = np.fft.fft(np.fft.ifftshift(hist, axes=0), axis=0) / ap.sum()
    band_r = np.fft.fftshift(np.abs(np.fft.fftfreq(n)) < FRAC / 2)
    spec = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) * ap[:, None] * band_r[None, :]
    clutter = np.fft.fft(np.fft.ifftshift(np.fft.ifft(np.fft.ifftshift(spec, axes=1), axis=1), axes=0), axis=0)
    clutter *= np.sqrt(10 ** (ctr_db / 10) / np.mean(np.abs(clutter) ** 2))
    noise = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) * np.sqrt(0.5 * 10 ** (-snr_db / 10))
    ideal = image + clutter + noise
    return _inject(ideal, _smooth_error(ap, 2.0, rng)), ideal, ap


def points_image(seed: int = 1, n: int = 512):
    """(defocused, reference, signal bins) of case (b)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n) - n // 2
    support = np.abs(k) < 0.4 * n
    u = np.where(support, k / (0.4 * n), 0.0)
    psi = np.where(support, smooth_phase_error(u, quadratic_rad=6.0, cubic_rad=3.0, sinusoid_rad=2.0,
                                               sinusoid_cycles=1.5), 0.0)
    n_t = 12
    xs = rng.uniform(0.1 * n, 0.9 * n, n_t)
    rs = rng.choice(np.arange(20, n - 20, 8), n_t, replace=False) + rng.uniform(0, 1, n_t)
    amp = rng.uniform(0.6, 1.0, n_t) * np.exp(2j * np.pi * rng.uniform(size=n_t))
    hist = np.zeros((n, n), dtype=complex)
    r = np.arange(n)
    for x, r0, a in zip(xs, rs, amp):
        hist += a * (support * np.exp(2j * np.pi * k * x / n))[:, None] * np.sinc(0.8 * (r - r0))[None, :]
    noise = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) * np.sqrt(0.5) * 10 ** (-50 / 20)
    ideal = np.fft.fft(np.fft.ifftshift(hist, axes=0), axis=0) / support.sum() + noise
    return _inject(ideal, psi), ideal, support


def gotcha_chips(data_dir: Path, size: int = 128, holdout: bool = False) -> list[tuple[str, np.ndarray]]:
    """Focused 128² chips (recorded autofocus) of the Gotcha image: a 3 × 3 grid, each also
    transposed (``holdout``: a 4 × 4 grid at other offsets). Returns [] when the files are absent."""
    files = sorted(data_dir.glob("data_3dsar_pass1_az00*_HH.mat"))
    if not files:
        return []
    from budget.sar.afrl import read_afrl
    from budget.sar.focus import FocusOptions, form_ground_image
    ph = read_afrl(files)
    img = form_ground_image(ph.with_recorded_autofocus(), FocusOptions()).data.astype(complex)
    out = []
    if holdout:
        offs = np.linspace(20, min(img.shape) - size - 20, 4).astype(int)
    else:
        offs = np.linspace(0, min(img.shape) - size, 3).astype(int)
    for i in offs:
        for j in offs:
            chip = img[i:i + size, j:j + size]
            out.append((f"chip {i:3d},{j:3d} axis 0", chip))
            out.append((f"chip {i:3d},{j:3d} axis 1", np.ascontiguousarray(chip.T)))
    return out


def chip_case(chip: np.ndarray, seed: int):
    """(defocused, reference, signal bins): the chip's bins within 20 dB of its peak energy get
    the smooth 2 rad rms error."""
    energy = np.fft.fftshift((np.abs(np.fft.ifft(chip, axis=0)) ** 2).sum(axis=1))
    support = energy >= 0.01 * energy.max()
    idx = np.nonzero(support)[0]
    support[idx[0]:idx[-1] + 1] = True
    return _inject(chip, _smooth_error(support, 2.0, np.random.default_rng(seed))), chip, support


def residual_rad(out: np.ndarray, ref: np.ndarray, support: np.ndarray) -> float:
    cross = np.fft.fftshift((np.fft.ifft(out, axis=0) * np.conj(np.fft.ifft(ref, axis=0))).sum(axis=1))
    ph = np.unwrap(np.angle(cross[support]))
    k = np.arange(ph.size)
    ph = ph - np.polyval(np.polyfit(k, ph, 1), k)
    return float(np.sqrt(np.mean(ph ** 2)))


FASTSAR_RUNNER = r"""
import json, sys, time, numpy as np
from fastsar.autofocus import pga
files = json.loads(sys.argv[1]); reps = int(sys.argv[2]); info = []
for src, dst in files:
    img = np.load(src)
    out = pga(img)  # warm-up
    times, cpu = [], []
    for _ in range(reps):
        t, c = time.perf_counter(), time.process_time(); out = pga(img)
        times.append(time.perf_counter() - t); cpu.append(time.process_time() - c)
    np.save(dst, np.asarray(out[0]))
    info.append({"time_s": float(np.median(times)), "cpu_s": float(np.median(cpu)), "iterations": len(out[2])})
print(json.dumps(info))
"""


def run_fastsar(py: Path, images: list[np.ndarray], repeat: int) -> list[tuple[np.ndarray, dict]] | str:
    if not py.exists():
        return f"not run ({py} not found; install fastsar in a separate venv, see the docstring)"
    with tempfile.TemporaryDirectory() as tmp:
        pairs = []
        for i, img in enumerate(images):
            src, dst = Path(tmp) / f"in{i}.npy", Path(tmp) / f"out{i}.npy"
            np.save(src, img)
            pairs.append((str(src), str(dst)))
        proc = subprocess.run([str(py), "-c", FASTSAR_RUNNER, json.dumps(pairs), str(repeat)],
                              capture_output=True, text=True, timeout=1200)
        if proc.returncode != 0:
            return "failed to run: " + " ".join(proc.stderr.strip().splitlines()[-1:])
        info = json.loads(proc.stdout.strip().splitlines()[-1])
        return [(np.load(dst).astype(complex), inf) for (_, dst), inf in zip(pairs, info)]


def run_ours(img: np.ndarray, repeat: int, **kw):
    """(result, median wall time s, median CPU time s) of ``repeat`` runs after one warm-up."""
    res = pga(img, **kw)
    times, cpu = [], []
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        res = pga(img, **kw)
        times.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return res, float(np.median(times)), float(np.median(cpu))


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
    print(f"  → {1.0 / float(np.median(steps['total'][1:])):.1f} trials/s (one process)\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fastsar-python", default="/tmp/fastsar-venv/bin/python")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--gotcha", default=str(REPO.parent / "shared" / "data" / "sar" / "gotcha"))
    ap.add_argument("--no-chain", action="store_true", help="skip the chain timings")
    ap.add_argument("--holdout", action="store_true",
                    help="also the 32 held-out Gotcha chips (other positions and error draws)")
    args = ap.parse_args()
    if not args.no_chain:
        chain_timings(10)
    cases = []  # (group, label, defocused, reference, support)
    for ctr in (-25.0, -35.0):
        for n_t in (10, 40):
            for seed in (1, 2, 3):
                cases.append(("clutter", f"CTR {ctr:g} dB, {n_t} targets, seed {seed}", *clutter_image(n_t, ctr, seed)))
    cases.append(("points", "12 points, noise −50 dB", *points_image()))
    t0 = time.perf_counter()
    chips = gotcha_chips(Path(args.gotcha))
    if chips:
        print(f"Gotcha image formed and cut into {len(chips)} chip cases in {time.perf_counter() - t0:.1f} s")
        for i, (label, chip) in enumerate(chips):
            cases.append(("gotcha", label, *chip_case(chip, 100 + i)))
        if args.holdout:
            for i, (label, chip) in enumerate(gotcha_chips(Path(args.gotcha), holdout=True)):
                cases.append(("gotcha held-out", label, *chip_case(chip, 500 + i)))
    else:
        print(f"Gotcha chips: skipped (no AFRL files in {args.gotcha})")
    refs = [i for i, c in enumerate(cases) if c[0] == "gotcha"]  # the unmodified chips, too
    fs = run_fastsar(Path(args.fastsar_python), [c[2] for c in cases] + [cases[i][3] for i in refs], args.repeat)
    fs_ref = {}
    if not isinstance(fs, str):
        fs_ref = dict(zip(refs, fs[len(cases):]))
        fs = fs[:len(cases)]
    if isinstance(fs, str):
        print("fastsar:", fs)
    hdr = (f"{'case':44s} {'before':>6s} | {'ours rad':>8s} {'ms':>7s} {'outcome':12s} | {'fastsar rad':>11s} {'ms':>7s} | "
           f"{'speed-up':>8s} {'cpu':>6s}")
    print(hdr)
    print("-" * len(hdr))
    summary: dict[str, list] = {}
    second: dict[str, list[int]] = {}  # per group: [cases, second pass ran, kept]
    chips_extra: list[tuple] = []
    for i, (group, label, bad, ref, sup) in enumerate(cases):
        res, t_ours, c_ours = run_ours(bad, args.repeat)
        r_ours = residual_rad(res.image, ref, sup)
        outcome = "converged" if res.converged else ("no scatterers" if res.failed else "not conv.")
        counts = second.setdefault(group, [0, 0, 0])
        counts[0] += 1
        counts[1] += bool(res.second_pass)
        counts[2] += bool(res.second_pass.get("kept"))
        line = f"{group + ': ' + label:44s} {residual_rad(bad, ref, sup):6.3f} | {r_ours:8.3f} {1e3 * t_ours:7.1f} {outcome:12s} |"
        if not isinstance(fs, str):
            out, inf = fs[i]
            r_fs = residual_rad(out, ref, sup)
            line += f" {r_fs:11.3f} {1e3 * inf['time_s']:7.1f} | {inf['time_s'] / t_ours:7.1f}× {inf['cpu_s'] / c_ours:5.1f}×"
            summary.setdefault(group, []).append((r_ours, r_fs, inf["time_s"] / t_ours, inf["cpu_s"] / c_ours))
        print(line)
        if group == "gotcha" and i in fs_ref:
            own_ref = pga(ref).image
            fs_out, fs_on_ref = fs[i][0], fs_ref[i][0]
            row = (residual_rad(own_ref, ref, sup), residual_rad(fs_on_ref, ref, sup),
                   residual_rad(res.image, own_ref, sup), residual_rad(fs_out, fs_on_ref, sup),
                   image_sharpness(res.image) / image_sharpness(ref), image_sharpness(fs_out) / image_sharpness(ref))
            chips_extra.append(row)
            print(f"{'':44s} on ref: ours {row[0]:.3f} fastsar {row[1]:.3f} | consistency: ours {row[2]:.3f} "
                  f"fastsar {row[3]:.3f} | sharpness gain: ours {row[4]:.3f} fastsar {row[5]:.3f}")
    for group, rows in summary.items():
        a = np.array(rows)
        print(f"{group}: ours no worse than fastsar in {int(np.sum(a[:, 0] <= a[:, 1]))}/{len(a)}; median residual "
              f"ours {np.median(a[:, 0]):.3f} rad vs fastsar {np.median(a[:, 1]):.3f} rad; "
              f"median speed-up {np.median(a[:, 2]):.1f}× (min {a[:, 2].min():.1f}×) wall, "
              f"{np.median(a[:, 3]):.1f}× (min {a[:, 3].min():.1f}×) CPU")
    for group, (n_cases, ran, kept) in second.items():
        print(f"{group}: PGA's second pass (after a correction > π rad rms) ran on {ran}/{n_cases}, kept on {kept}")
    if chips_extra:
        e = np.array(chips_extra)
        print(f"gotcha, reference-free: PGA on the unmodified chip moves it by (median) ours {np.median(e[:, 0]):.3f}, "
              f"fastsar {np.median(e[:, 1]):.3f} rad; consistency ours {np.median(e[:, 2]):.3f} vs fastsar "
              f"{np.median(e[:, 3]):.3f} rad (ours no worse in {int(np.sum(e[:, 2] <= e[:, 3]))}/{len(e)}); "
              f"sharpness gain ours {np.median(e[:, 4]):.3f} vs fastsar {np.median(e[:, 5]):.3f} "
              f"(ours at least as sharp in {int(np.sum(e[:, 4] >= e[:, 5]))}/{len(e)})")
    print(f"load average (1, 5, 15 min): {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
