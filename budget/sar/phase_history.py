"""A recorded SAR phase history: samples per pulse and frequency, with the antenna track.

Convention (spotlight data deramped to the scene centre, as the AFRL Gotcha release): a point
scatterer of complex reflectivity a at ground position p contributes to pulse n, frequency f

    S(n, f) = a · exp(−j 4π f / c · (|A_n − p| − R0_n)),                                  (1)

with A_n the antenna phase centre and R0_n the recorded range to the scene centre. An image is
formed by backprojection with the conjugate phase (:mod:`budget.sar.focus`). A per-pulse phase
error ψ_n multiplies pulse n by exp(jψ_n); a correction by exp(−jψ_n).

The provider's autofocus solution (when recorded) is a range correction ΔR_n (added to R0_n) and a
phase correction χ_n (each pulse multiplied by exp(jχ_n)). By (1), replacing R0_n with R0_n + ΔR_n
multiplies pulse n by exp(−j 4π f ΔR_n / c), so the net correction at frequency f is
χ_n − 4π f ΔR_n / c, and the phase error it implies is its negative.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np
import pandas as pd

from ..errors import InputError
from ..units import C_LIGHT, two_way_wavenumber_at_frequency_rad_m

C_M_S = C_LIGHT


#: Radar frequencies a phase history may hold, Hz (the scenarios' radar carrier range).
RADAR_FREQUENCY_RANGE_HZ = (1e6, 1e13)
RADAR_FREQUENCY_EXPECTED = "radar frequencies in Hz, 1 MHz … 10 THz"


def radar_frequency_problem(frequency_hz) -> str:
    """"" when every frequency (Hz) is within :data:`RADAR_FREQUENCY_RANGE_HZ`, else what is wrong,
    naming the unit that would fit (9.6 read in Hz is 9.6 GHz written in GHz)."""
    f = np.asarray(frequency_hz, dtype=float).ravel()
    lo, hi = RADAR_FREQUENCY_RANGE_HZ
    if f.size == 0 or (f.min() >= lo and f.max() <= hi):
        return ""
    text = f"frequencies {f.min():.4g}–{f.max():.4g} Hz are not radar frequencies"
    fits = [(abs(np.log10(np.sqrt(f.min() * f.max()) * factor) - 9.5), factor, unit)
            for factor, unit in ((1e9, "GHz"), (1e6, "MHz"), (1e3, "kHz"))
            if f.min() * factor >= lo and f.max() * factor <= hi]
    if fits:  # the unit that puts the band nearest the usual radar bands (≈ 3 GHz in log)
        _, factor, unit = min(fits)
        return text + f" (in {unit}? × {factor:.0e} gives {f.min() * factor:.4g}–{f.max() * factor:.4g} Hz)"
    return text


@dataclass
class PhaseHistory:
    """Complex ``samples`` (n_pulses, n_freq), pulses along axis 0, in the convention (1) above.

    ``antenna_m`` (n_pulses, 3) and the ground plane z = 0 are in the scene-centred local frame.
    ``pulse_source`` names the file of each pulse (several files are concatenated in order).
    """

    samples: np.ndarray = field(repr=False)
    frequency_hz: np.ndarray = field(repr=False)
    antenna_m: np.ndarray = field(repr=False)
    scene_range_m: np.ndarray = field(repr=False)
    pulse_source: np.ndarray = field(repr=False)
    recorded_range_correction_m: np.ndarray | None = field(default=None, repr=False)
    recorded_phase_correction_rad: np.ndarray | None = field(default=None, repr=False)
    azimuth_deg: np.ndarray | None = field(default=None, repr=False)
    elevation_deg: np.ndarray | None = field(default=None, repr=False)
    #: Phase error per pulse (rad) added by :meth:`with_phase_error` (an injection experiment):
    #: known, so that an autofocus estimate can be scored against it.
    injected_phase_rad: np.ndarray | None = field(default=None, repr=False)
    #: Line-of-sight range error per pulse (m, Δr = R_true − R_assumed) added by
    #: :meth:`with_range_error`; its phase at the reference frequency is in
    #: :attr:`injected_phase_rad`, the rest is the range migration (:meth:`with_range_error`, eq. 4).
    injected_range_m: np.ndarray | None = field(default=None, repr=False)
    #: Time of each pulse, s (optional; the AFRL Gotcha files carry none): gives the platform
    #: speed in :func:`budget.sar.acquisition.describe_acquisition`.
    pulse_time_s: np.ndarray | None = field(default=None, repr=False)
    #: What the file names say of the data (:func:`budget.sar.afrl.read_afrl`: the Gotcha names'
    #: ``pass`` and ``polarisation``), empty when they say nothing.
    name_tags: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        s = np.asarray(self.samples)
        if s.ndim != 2 or s.shape[0] < 2 or s.shape[1] < 2 or not np.iscomplexobj(s):
            raise InputError(f"samples have shape {s.shape}", field="samples",
                             expected="a complex (n_pulses ≥ 2, n_freq ≥ 2) array")
        n, k = s.shape
        f = np.asarray(self.frequency_hz, dtype=float).ravel()
        if f.size != k:
            raise InputError(f"{f.size} frequencies for {k} samples per pulse", field="frequency_hz")
        if not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise InputError("frequencies must be finite and > 0", field="frequency_hz")
        problem = radar_frequency_problem(f)
        if problem:
            raise InputError(problem, field="frequency_hz", expected=RADAR_FREQUENCY_EXPECTED)
        step = np.diff(f)
        if np.any(step <= 0) or np.ptp(step) > 1e-3 * abs(step.mean()):
            raise InputError("frequencies must increase in equal steps", field="frequency_hz",
                             expected="a uniform, increasing frequency axis")
        a = np.asarray(self.antenna_m, dtype=float)
        if a.shape != (n, 3) or not np.all(np.isfinite(a)):
            raise InputError(f"antenna positions have shape {a.shape}", field="antenna_m",
                             expected=f"finite ({n}, 3) positions in m")
        r = np.asarray(self.scene_range_m, dtype=float).ravel()
        if r.size != n or not np.all(np.isfinite(r)) or np.any(r <= 0):
            raise InputError("scene ranges must be finite, > 0, one per pulse", field="scene_range_m")
        if not np.all(np.isfinite(s)):
            raise InputError("samples hold NaN or infinite values", field="samples", expected="finite values")
        self.samples, self.frequency_hz, self.antenna_m, self.scene_range_m = s, f, a, r
        self.pulse_source = np.asarray(self.pulse_source, dtype=object).ravel()
        if self.pulse_source.size != n:
            raise InputError("one source name per pulse expected", field="pulse_source")
        for name in ("recorded_range_correction_m", "recorded_phase_correction_rad", "azimuth_deg",
                     "elevation_deg", "injected_phase_rad", "injected_range_m", "pulse_time_s"):
            v = getattr(self, name)
            if v is not None:
                v = np.asarray(v, dtype=float).ravel()
                if v.size != n or not np.all(np.isfinite(v)):
                    raise InputError("must be finite, one value per pulse", field=name)
                setattr(self, name, v)
        if self.pulse_time_s is not None and np.any(np.diff(self.pulse_time_s) <= 0):
            raise InputError("pulse times must increase", field="pulse_time_s", expected="one time per pulse, s")
        self.name_tags = {str(k): str(v) for k, v in dict(self.name_tags or {}).items()}

    # --- axes -------------------------------------------------------------------------------
    @property
    def n_pulses(self) -> int:
        return int(self.samples.shape[0])

    @property
    def n_frequencies(self) -> int:
        return int(self.samples.shape[1])

    @property
    def frequency_step_hz(self) -> float:
        return float((self.frequency_hz[-1] - self.frequency_hz[0]) / (self.n_frequencies - 1))

    @property
    def reference_frequency_hz(self) -> float:
        """Frequency of sample n_freq // 2: the carrier of the range-compressed profiles."""
        return float(self.frequency_hz[0] + (self.n_frequencies // 2) * self.frequency_step_hz)

    @property
    def bandwidth_hz(self) -> float:
        return self.n_frequencies * self.frequency_step_hz

    @property
    def has_recorded_autofocus(self) -> bool:
        return self.recorded_range_correction_m is not None and self.recorded_phase_correction_rad is not None

    # --- corrections ------------------------------------------------------------------------
    def with_phase_error(self, phase_rad) -> "PhaseHistory":
        """A copy with pulse n multiplied by exp(j phase_rad[n]) (an injected or removed error),
        added to :attr:`injected_phase_rad`."""
        ph = np.asarray(phase_rad, dtype=float).ravel()
        if ph.size != self.n_pulses or not np.all(np.isfinite(ph)):
            raise InputError("one finite phase per pulse expected", field="phase_rad",
                             expected=f"{self.n_pulses} values in rad")
        injected = ph if self.injected_phase_rad is None else self.injected_phase_rad + ph
        return self._replace(samples=self.samples * np.exp(1j * ph)[:, None].astype(self.samples.dtype),
                             injected_phase_rad=injected)

    def with_range_error(self, range_error_m) -> "PhaseHistory":
        """A copy carrying a line-of-sight range error Δr_n (m per pulse, Δr = R_true − R_assumed,
        the motion engine's sign: :func:`budget.motion.geometry.range_error`), exactly: pulse n at
        frequency f_k multiplied by

            exp(−j 4π f_k Δr_n / c)                                                          (4)

        — by (1), the echo of a true antenna Δr_n farther from every scene point than the recorded
        track says. The same sign as :meth:`with_phase_error`: its per-pulse phase at the reference
        frequency f_r, ψ_n = −4π f_r Δr_n / c (the package's ψ = −4πΔr/λ, :mod:`budget`), is added
        to :attr:`injected_phase_rad`, so :meth:`known_phase_error_rad` scores an autofocus against
        it; what is left, exp(−j 4π (f_k − f_r) Δr_n / c), is a shift of pulse n's range profile by
        Δr_n (range migration, which no per-pulse phase correction removes), recorded with Δr in
        :attr:`injected_range_m`."""
        dr = np.asarray(range_error_m, dtype=float).ravel()
        if dr.size != self.n_pulses or not np.all(np.isfinite(dr)):
            raise InputError("one finite range error per pulse expected", field="range_error_m",
                             expected=f"{self.n_pulses} values in m")
        k = two_way_wavenumber_at_frequency_rad_m(self.frequency_hz, C_M_S)  # 4π f_k / c, rad/m
        # float64 phase before the cast: Δr of metres at 10 GHz is thousands of radians
        turn = np.exp(-1j * np.outer(dr, k)).astype(self.samples.dtype)
        psi = -two_way_wavenumber_at_frequency_rad_m(self.reference_frequency_hz, C_M_S) * dr
        injected = psi if self.injected_phase_rad is None else self.injected_phase_rad + psi
        ranges = dr if self.injected_range_m is None else self.injected_range_m + dr
        return self._replace(samples=self.samples * turn, injected_phase_rad=injected, injected_range_m=ranges)

    def with_smooth_phase_error(self, quadratic_rad: float, cubic_rad: float, sinusoid_rad: float,
                                sinusoid_cycles: float) -> "PhaseHistory":
        """:meth:`with_phase_error` of ψ(u) = q u² + c u³ + s sin(π N u) over the pulses,
        u = −1 … 1 (:func:`budget.sar.phase.smooth_phase_error`), with a note saying so."""
        from .phase import check_phase_sampled, smooth_phase_error  # the SAR simulation's model; only here
        values = {"quadratic_rad": quadratic_rad, "cubic_rad": cubic_rad, "sinusoid_rad": sinusoid_rad,
                  "sinusoid_cycles": sinusoid_cycles}
        for name, v in values.items():
            if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not np.isfinite(v):
                raise InputError("must be a finite number", field=name, value=v, expected="rad (cycles for N)")
        psi = smooth_phase_error(np.linspace(-1.0, 1.0, self.n_pulses), **{k: float(v) for k, v in values.items()})
        check_phase_sampled(psi, "quadratic_rad, cubic_rad, sinusoid_rad")
        out = self.with_phase_error(psi)
        out.notes.append(f"injected phase error {quadratic_rad:g} u² + {cubic_rad:g} u³ + {sinusoid_rad:g} "
                         f"sin({sinusoid_cycles:g}πu) rad over the pulses (u = −1 … 1)")
        return out

    def known_phase_error_rad(self) -> np.ndarray | None:
        """The phase error per pulse the data are known to carry (rad, the sign of (1)'s ψ_n): the
        recorded solution's (:meth:`recorded_phase_error_rad`) plus the injected one, either
        alone, or None when neither is known."""
        rec = self.recorded_phase_error_rad() if self.has_recorded_autofocus else None
        inj = self.injected_phase_rad
        if rec is None:
            return None if inj is None else inj.copy()
        return rec if inj is None else rec + inj

    def with_recorded_autofocus(self) -> "PhaseHistory":
        """The provider's correction applied: R0 + ΔR and each pulse × exp(jχ) (module docstring).
        The copy carries no recorded solution any more (it is in the data), so an error injected
        into it afterwards is all :meth:`known_phase_error_rad` reports."""
        if not self.has_recorded_autofocus:
            raise InputError("the phase history has no recorded autofocus solution", field="af",
                             expected="files with data.af.r_correct and data.af.ph_correct")
        chi = np.exp(1j * self.recorded_phase_correction_rad)[:, None].astype(self.samples.dtype)
        out = self._replace(samples=self.samples * chi,
                            scene_range_m=self.scene_range_m + self.recorded_range_correction_m,
                            recorded_range_correction_m=None, recorded_phase_correction_rad=None)
        out.notes = self.notes + ["recorded autofocus solution applied (R0 + r_correct, × exp(j ph_correct))"]
        return out

    def recorded_phase_error_rad(self, frequency_hz: float | None = None) -> np.ndarray:
        """Phase error per pulse implied by the recorded solution at ``frequency_hz`` (default the
        reference frequency): −(χ_n − 4π f ΔR_n / c), unwrapped along the pulses, rad."""
        if not self.has_recorded_autofocus:
            raise InputError("the phase history has no recorded autofocus solution", field="af")
        f = self.reference_frequency_hz if frequency_hz is None else float(frequency_hz)
        k = two_way_wavenumber_at_frequency_rad_m(f, C_M_S)
        net = self.recorded_phase_correction_rad - k * self.recorded_range_correction_m
        return -np.unwrap(net)

    def _replace(self, **changes) -> "PhaseHistory":
        kw = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "notes"}
        kw.update(changes)
        return PhaseHistory(**kw, notes=list(self.notes))

    # --- result protocol --------------------------------------------------------------------
    def summary(self) -> str:
        """A few lines: pulses, frequencies, band, track length, sources and notes."""
        d = self.description()
        lines = [f"{d['pulses']} pulses × {d['frequencies']} frequencies, {d['frequency_min_hz'] / 1e9:.4g}–"
                 f"{d['frequency_max_hz'] / 1e9:.4g} GHz (bandwidth {d['bandwidth_hz'] / 1e6:.4g} MHz); track "
                 f"{d['track_length_m']:.4g} m at mean range {d['scene_range_mean_m']:.5g} m",
                 f"sources: {', '.join(map(str, d['sources']))}; recorded autofocus: "
                 f"{'yes' if d['recorded_autofocus'] else 'no'}"]
        lines += [f"note: {n}" for n in d["notes"]]
        return "\n".join(lines)

    def description(self) -> dict:
        """Scalar description: sizes, frequency band (Hz), track length (m), sources, notes."""
        track = np.linalg.norm(np.diff(self.antenna_m, axis=0), axis=1).sum()
        out = {"pulses": self.n_pulses, "frequencies": self.n_frequencies,
               "frequency_min_hz": float(self.frequency_hz[0]), "frequency_max_hz": float(self.frequency_hz[-1]),
               "frequency_step_hz": self.frequency_step_hz, "bandwidth_hz": self.bandwidth_hz,
               "track_length_m": float(track), "scene_range_mean_m": float(self.scene_range_m.mean()),
               "sources": list(dict.fromkeys(self.pulse_source.tolist())),
               "recorded_autofocus": self.has_recorded_autofocus, "notes": list(self.notes)}
        if self.injected_range_m is not None:
            out["injected_range_peak_m"] = float(np.max(np.abs(self.injected_range_m)))
        if self.injected_phase_rad is not None:
            out["injected_phase_rms_rad"] = float(np.sqrt(np.mean(self.injected_phase_rad ** 2)))
        if self.azimuth_deg is not None:
            out["azimuth_span_deg"] = [float(self.azimuth_deg[0]), float(self.azimuth_deg[-1])]
        if self.elevation_deg is not None:
            out["elevation_mean_deg"] = float(self.elevation_deg.mean())
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per pulse: source, antenna x/y/z (m), R0 (m), recorded corrections when present."""
        df = pd.DataFrame({"source": self.pulse_source, "antenna_x_m": self.antenna_m[:, 0],
                           "antenna_y_m": self.antenna_m[:, 1], "antenna_z_m": self.antenna_m[:, 2],
                           "scene_range_m": self.scene_range_m})
        if self.has_recorded_autofocus:
            df["recorded_range_correction_m"] = self.recorded_range_correction_m
            df["recorded_phase_correction_rad"] = self.recorded_phase_correction_rad
        df.index.name = "pulse"
        return df

    def to_dict(self) -> dict:
        """JSON-ready: :meth:`description` and one record per pulse (:meth:`to_frame`)."""
        return {**self.description(), "pulse_records": self.to_frame().reset_index().to_dict(orient="records")}


#: A step between consecutive pulses longer than this many times the median step is an aperture
#: gap (pulses missing: a file left out, dropped pulses), as a log's sample gap is > 1.5 periods.
GAP_FACTOR = 1.5

#: A step that goes back along the track by more than this fraction of the median step is the
#: track reversing: pulses out of order (files given out of aperture order, or one file twice).
BACKWARD_FRACTION = 0.5


@dataclass(frozen=True)
class TrackOrder:
    """How the antenna advances from pulse to pulse (:func:`track_order`). ``backward``: the first
    pulse index i whose step i → i+1 goes back along the track (None when none does); ``gaps``:
    (i, steps) for every step i → i+1 that is a gap (:func:`track_order`), with its length in
    median steps; ``median_step_m``: the median distance between consecutive pulses;
    ``repeated``: the pulses recorded where the pulse before was."""

    median_step_m: float
    backward: int | None
    gaps: tuple[tuple[int, float], ...]
    #: pulses i + 1 recorded at the position of pulse i (a step < 10⁻³ median steps: duplicated)
    repeated: tuple[int, ...] = ()


def track_order(antenna_m) -> TrackOrder:
    """Check that the antenna positions (n_pulses, 3), m, advance along one track in even steps.

    The direction at pulse i is that of the previous step (a curved track, a circular pass, turns
    slowly from step to step), so a step i → i+1 is *backward* when its component along the
    previous step is below −:data:`BACKWARD_FRACTION` × the median step; it is a *gap* when its
    length exceeds :data:`GAP_FACTOR` × the median step and the median step + 5 robust σ of the
    steps (a noisy track's longest steps are not gaps). Image formation windows the aperture and
    PGA estimates its phase over the pulse index, which both assume pulses in track order at an
    even spacing."""
    a = np.asarray(antenna_m, dtype=float)
    d = np.diff(a, axis=0)
    step = np.sqrt(np.einsum("ij,ij->i", d, d))
    if step.size == 0:
        return TrackOrder(0.0, None, ())
    med = float(np.median(step))
    if not med > 0:  # the antenna does not move (a turntable or a test): no track to check
        return TrackOrder(med, None, ())
    along = np.einsum("ij,ij->i", d[1:], d[:-1]) / np.maximum(step[:-1], 1e-300)
    back = np.flatnonzero(along < -BACKWARD_FRACTION * med)
    backward = int(back[0]) + 1 if back.size else None
    # a noisy track (positions per pulse from raw GNSS) spreads the steps: a gap must also stand
    # 5 robust σ out of that spread (1.4826 × the median absolute deviation)
    sigma = 1.4826 * float(np.median(np.abs(step - med)))
    long = np.flatnonzero(step > max(GAP_FACTOR * med, med + 5.0 * sigma))
    repeated = tuple(int(i) + 1 for i in np.flatnonzero(step < 1e-3 * med))
    return TrackOrder(med, backward, tuple((int(i), float(step[i] / med)) for i in long), repeated)
