"""The aided error-state system: INS error model + aiding measurements, truth and filter views.

:func:`build_system` assembles, for one nominal trajectory shared by all trials,

* the **truth** state (INS blocks of the true IMU model + every augmented measurement-error
  block) and the **filter** state (INS blocks of the filter's IMU model + the augmented blocks
  it estimates); both start with pos, vel, att at indices 0–8;
* their discrete transitions Φ_k, Qd_k (Van Loan; computed once for a constant trajectory,
  in cached chunks otherwise);
* the measurement models with their epochs.

:func:`simulate_truth` draws truth trajectories from the same linear model (a consistent
filter is then exactly consistent: the NEES tests rely on it); :func:`embed_ins_truth` takes
pos/vel/att errors from elsewhere (the motion engine's free-inertial propagation) and adds the
measurement-error states; :func:`simulate_measurements` forms z = H x + v at every epoch.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag

from .ins_error_model import (ImuErrorModel, NominalTrajectory, StateLayout, ins_dynamics,
                              ins_initial_covariance, ins_noise, van_loan)
from .lti import psd_sqrt, sample_initial, sample_lti, sample_ltv
from .measurements import Measurement, measurement_from_config


#: memory the transition memo of one system may use (bytes)
MEMO_BYTES = 256 * 2 ** 20


@dataclass(frozen=True)
class InitialUncertainty:
    """1σ of the INS errors when the filter starts (scalars or 3-vectors): m, m/s, rad."""

    position_m: object = 1.0
    velocity_m_s: object = 0.1
    attitude_rad: object = 1e-3


class TransitionCache:
    """Φ_k, Qd_k of the step k → k+1, computed in chunks (or once for a constant model)."""

    def __init__(self, system: "AidedSystem", which: str, chunk: int = 2000):
        self._sys, self._which, self._chunk = system, which, chunk
        self._start, self._phis, self._qds = -1, None, None
        if system.trajectory.constant:
            phi, qd = system.transitions(which, 0, 1)
            self._const = (phi[0], qd[0])
        else:
            self._const = None

    def get(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        if self._const is not None:
            return self._const
        if not (self._start <= k < self._start + self._chunk) or self._start < 0:
            n_steps = self._sys.trajectory.n_samples - 1
            self._start = (k // self._chunk) * self._chunk
            stop = min(self._start + self._chunk, n_steps)
            self._phis, self._qds = self._sys.transitions(self._which, self._start, stop)
        return self._phis[k - self._start], self._qds[k - self._start]


class AidedSystem:
    """See the module docstring. ``which`` is ``"truth"`` or ``"filter"`` throughout."""

    def __init__(self, trajectory: NominalTrajectory, imu: ImuErrorModel,
                 measurements: list[Measurement], initial: InitialUncertainty,
                 filter_imu: ImuErrorModel | None = None):
        self.trajectory = trajectory
        self.imu = {"truth": imu, "filter": filter_imu or imu}
        self.measurements = list(measurements)
        names = [m.name for m in self.measurements]
        if len(set(names)) != len(names):
            raise ValueError(f"measurement names must be unique, got {names}")
        self.aug_blocks = [b for m in self.measurements for b in m.aug_blocks()]
        self.layout = {
            "truth": StateLayout(tuple(imu.blocks())).with_blocks(
                [(b.name, b.size) for b in self.aug_blocks]),
            "filter": StateLayout(tuple(self.imu["filter"].blocks())).with_blocks(
                [(b.name, b.size) for b in self.aug_blocks if b.estimated]),
        }
        self.initial = initial
        n, dt = trajectory.n_samples, trajectory.dt_s
        self.epochs = {m.name: m.epochs(n, dt) for m in self.measurements}
        self._h_cache: dict = {}
        self._memo: dict = {}
        self._memo_bytes = 0

    # --- model pieces -------------------------------------------------------------------
    @property
    def dt_s(self) -> float:
        return self.trajectory.dt_s

    @property
    def n_samples(self) -> int:
        return self.trajectory.n_samples

    def _aug(self, which):
        return [b for b in self.aug_blocks if which == "truth" or b.estimated]

    def P0(self, which: str) -> np.ndarray:
        lay, imu, ini = self.layout[which], self.imu[which], self.initial
        P = ins_initial_covariance(lay, imu, position_m=ini.position_m,
                                   velocity_m_s=ini.velocity_m_s, attitude_rad=ini.attitude_rad)
        for b in self._aug(which):
            s = lay.slice(b.name)
            P[s, s] = b.P0
        return P

    def continuous(self, which: str, start: int, stop: int) -> tuple[np.ndarray, np.ndarray]:
        """F (stop−start, n, n) at samples start … stop−1 and the constant Qc (n, n)."""
        lay, imu, tr = self.layout[which], self.imu[which], self.trajectory
        F = ins_dynamics(lay, imu, tr.f_n[start:stop], tr.c_bn[start:stop])
        Qc = ins_noise(lay, imu)
        for b in self._aug(which):
            s = lay.slice(b.name)
            F[:, s, s] = b.F
            Qc[s, s] = b.Qc
        return F, Qc

    def transitions(self, which: str, start: int, stop: int) -> tuple[np.ndarray, np.ndarray]:
        """Φ, Qd stacks for the steps k → k+1, k = start … stop−1 (F held at sample k).

        The INS blocks vary along the trajectory; the augmented blocks are time-invariant and
        uncoupled from them, so they are discretised once and placed on the block diagonal.
        Chunks are memoised (up to ``MEMO_BYTES``) so the filter, the smoother and repeated
        runs on the same system share them.
        """
        key = (which, start, stop)
        if key in self._memo:
            return self._memo[key]
        lay = self.layout[which]
        n_ins = len(self.imu[which].blocks()) * 3
        F, Qc = self.continuous(which, start, stop)
        if n_ins == lay.n:
            phi, qd = van_loan(F, Qc, self.dt_s)
        else:
            phi = np.zeros(F.shape)
            qd = np.zeros(F.shape)
            phi[:, :n_ins, :n_ins], qd[:, :n_ins, :n_ins] = van_loan(
                F[:, :n_ins, :n_ins], Qc[:n_ins, :n_ins], self.dt_s)
            pa, qa = van_loan(F[0, n_ins:, n_ins:], Qc[n_ins:, n_ins:], self.dt_s)
            phi[:, n_ins:, n_ins:], qd[:, n_ins:, n_ins:] = pa, qa
        size = phi.nbytes + qd.nbytes
        if self._memo_bytes + size <= MEMO_BYTES:
            self._memo[key] = (phi, qd)
            self._memo_bytes += size
        return phi, qd

    def H(self, which: str, m: Measurement, k: int) -> np.ndarray:
        key = (which, m.name, 0 if self.trajectory.constant else k)
        if key not in self._h_cache:
            self._h_cache[key] = m.H(self.layout[which], self.trajectory, k)
        return self._h_cache[key]

    def R_filter(self, m: Measurement, k: int) -> np.ndarray:
        key = ("R", m.name, 0 if self.trajectory.constant else k)
        if key not in self._h_cache:
            self._h_cache[key] = m.R_filter(self.layout["filter"], self.trajectory, k)
        return self._h_cache[key]

    def consistent(self) -> bool:
        """True when the filter models the truth exactly (then NEES/NIS tests apply)."""
        return (self.layout["truth"] == self.layout["filter"]
                and self.imu["truth"] == self.imu["filter"])


def build_system(trajectory: NominalTrajectory, imu: ImuErrorModel, aiding: list,
                 initial: InitialUncertainty | None = None,
                 filter_imu: ImuErrorModel | None = None) -> AidedSystem:
    """System from validated aiding configs (see :mod:`budget.aiding_spec`).

    Measurements are numbered per type (``gnss0``, ``dvl0``, ``gnss1`` …), so the same sensor
    has the same name — and the same augmented-state names — in systems that share it
    (:func:`transfer_truth` relies on this for common random numbers).
    """
    counts: dict[str, int] = {}
    meas = []
    for cfg in aiding:
        meas.append(measurement_from_config(cfg, counts.get(cfg.type, 0)))
        counts[cfg.type] = counts.get(cfg.type, 0) + 1
    return AidedSystem(trajectory, imu, meas, initial or InitialUncertainty(), filter_imu)


def simulate_truth(system: AidedSystem, trials: int, rng: np.random.Generator) -> np.ndarray:
    """True error states (T, N, n_truth) drawn from the truth model, x0 ~ N(0, P0)."""
    x0 = sample_initial(system.P0("truth"), trials, rng)
    if system.trajectory.constant:
        phi, qd = system.transitions("truth", 0, 1)
        return sample_lti(phi[0], qd[0], x0, system.n_samples, rng)
    return sample_ltv(lambda a, b: system.transitions("truth", a, b), x0, system.n_samples, rng)


@dataclass
class TruthParts:
    """Truth kept as its pieces — INS pos/vel/att (T, N, 3) each and the augmented states
    (T, N, n_aug) — so that no (T, N, n_truth) array is built (the Monte Carlo path).
    Bias states, which no measurement sees, are zero."""

    layout: StateLayout
    pos: np.ndarray
    vel: np.ndarray
    att: np.ndarray
    aug: np.ndarray | None
    aug_start: int

    @property
    def shape(self) -> tuple[int, int]:
        return self.pos.shape[:2]

    def at(self, k: int) -> np.ndarray:
        """Full truth state vector (T, n_truth) at sample k."""
        x = np.zeros((self.pos.shape[0], self.layout.n))
        x[:, self.layout.slice("pos")] = self.pos[:, k]
        x[:, self.layout.slice("vel")] = self.vel[:, k]
        x[:, self.layout.slice("att")] = self.att[:, k]
        if self.aug is not None:
            x[:, self.aug_start:] = self.aug[:, k]
        return x


def embed_ins_truth(system: AidedSystem, position_error_m, velocity_error_m_s, attitude_error_rad,
                    rng: np.random.Generator, *, parts: bool = False):
    """Truth (T, N, n_truth) from given INS errors (T, N, 3 each, n frame, estimate − truth).

    Bias states are left at zero (no measurement sees them directly); the augmented
    measurement-error states (GNSS GM error, DVL bias, flexure) are drawn from their models.
    ``parts=True`` returns a :class:`TruthParts` instead (same content, no big copy).
    """
    arrays = [np.asarray(a, dtype=float) for a in (position_error_m, velocity_error_m_s,
                                                   attitude_error_rad)]
    shape = (arrays[0].shape[0], system.n_samples, 3)
    for a in arrays:
        if a.shape != shape:
            raise ValueError(f"INS error arrays must have shape {shape} (trials, samples, 3), "
                             f"got {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError("INS error arrays contain NaN or infinity")
    lay = system.layout["truth"]
    aug = system.aug_blocks
    xa, start = None, lay.n
    if aug:
        F = block_diag(*[b.F for b in aug])
        Qc = block_diag(*[b.Qc for b in aug])
        P0 = block_diag(*[b.P0 for b in aug])
        phi, qd = van_loan(F, Qc, system.dt_s)
        xa = sample_lti(phi, qd, sample_initial(P0, shape[0], rng), system.n_samples, rng)
        start = lay.slice(aug[0].name).start
    if parts:
        return TruthParts(lay, *arrays, xa, start)
    truth = np.zeros(shape[:2] + (lay.n,))
    for name, a in zip(("pos", "vel", "att"), arrays):
        truth[..., lay.slice(name)] = a
    if xa is not None:
        truth[..., start:] = xa
    return truth


def transfer_truth(target: AidedSystem, source: AidedSystem, truth: np.ndarray) -> np.ndarray:
    """Truth of ``source`` (T, N, n_source) rearranged for ``target``'s truth layout, block by
    block name (every block of the target must exist in the source)."""
    src, dst = source.layout["truth"], target.layout["truth"]
    out = np.empty(truth.shape[:2] + (dst.n,))
    for name, _ in dst.blocks:
        if not src.has(name):
            raise ValueError(f"truth block {name!r} missing from the source system")
        out[..., dst.slice(name)] = truth[..., src.slice(name)]
    return out


def simulate_measurements(system: AidedSystem, truth, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """z (T, E, m) per measurement name: H_truth x_truth + white noise, at its epochs.

    ``truth``: (T, N, n_truth) array or :class:`TruthParts`.
    """
    out = {}
    T = truth.shape[0]
    at = truth.at if isinstance(truth, TruthParts) else (lambda k: truth[:, k])
    for m in system.measurements:
        ep = system.epochs[m.name]
        z = np.empty((T, len(ep), m.size))
        for j, k in enumerate(ep):
            L = psd_sqrt(m.R_white(system.trajectory, k))
            z[:, j] = at(k) @ system.H("truth", m, k).T + rng.standard_normal((T, m.size)) @ L.T
        out[m.name] = z
    return out
