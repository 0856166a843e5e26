"""Measurement models of the aiding sensors: z = H x + v, with the sign conventions of
:mod:`budget.aiding.ins_error_model` (errors = estimate − truth, Ĉ = (I − [φ×]) C).

Every measurement is "INS-predicted quantity minus sensor quantity":

* **GNSS/DGPS position** at an antenna with lever arm l (body): z = (p̂ + Ĉ l) − p_gnss
  = δp + [(C l)×] φ + e_gm + v. (Because (Ĉ − C) l = −[φ×] C l = [(C l)×] φ.)
* **DVL velocity** (body frame, bias b_d): z = v̂ − Ĉ ṽ_b = δv − [v_n×] φ − C b_d − C v
  (the INS rotates the DVL reading with its own, erroneous attitude; lever-arm rotation terms
  ω × l are neglected — second order for a slowly turning vehicle).
* **Master INS transfer** (seeds 001, 002): the master's position and velocity moved through the
  lever arm with the master's attitude, p_m + C_m l and v_m + C_m (ω × l). With a flexible arm
  the true slave position is p_m + C (l + d), so z = [δp + C d − e_mp; δv + C ḋ − e_mv]: the
  slave's attitude error does not appear, the flexure d does (seed 002 (7)–(12)).
* **Star tracker attitude**: z = φ + v (seed 001, CNS).

Each model knows its augmented error states (GNSS Gauss–Markov error, DVL bias, flexure) as
:class:`AugBlock`; a block the filter does not estimate is still simulated in the truth and the
filter treats it as extra white noise of the same (stationary) variance.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from ..aiding_spec import DvlAiding, GnssAiding, MasterInsAiding, StarTrackerAiding, sigma3
from .flexure import flexure_blocks
from .ins_error_model import NominalTrajectory, StateLayout, skew

ARCSEC_RAD = math.pi / (180.0 * 3600.0)


@dataclass(frozen=True)
class AugBlock:
    """Error states a measurement adds: continuous F, noise density Qc, initial P0 (all (s, s))."""

    name: str
    F: np.ndarray
    Qc: np.ndarray
    P0: np.ndarray
    estimated: bool = True

    @property
    def size(self) -> int:
        return self.F.shape[0]


class Measurement(ABC):
    """Base of the four sensor models. Subclasses set ``name``, ``size``, ``rate_hz``,
    ``latency_s`` and implement ``_blocks(layout, traj, k)`` → {block: (rows, matrix)}."""

    name: str
    size: int
    rate_hz: float
    latency_s: float

    def aug_blocks(self) -> list[AugBlock]:
        return []

    def epochs(self, n_samples: int, dt_s: float) -> np.ndarray:
        """Sample indices where a measurement is valid: k_j = round(j / (rate·dt)), j ≥ 1."""
        step = 1.0 / (self.rate_hz * dt_s)
        if step < 1.0 - 1e-9:
            raise ValueError(f"{self.name}: rate {self.rate_hz:g} Hz above the sample rate "
                             f"{1.0 / dt_s:g} Hz")
        j = np.arange(1, int((n_samples - 1) / step) + 2)
        k = np.unique(np.rint(j * step).astype(int))
        return k[k < n_samples]

    def latency_steps(self, dt_s: float) -> int:
        return int(round(self.latency_s / dt_s))

    def H(self, layout: StateLayout, traj: NominalTrajectory, k: int) -> np.ndarray:
        """(m, n) for ``layout``; contributions of blocks absent from the layout are dropped."""
        out = np.zeros((self.size, layout.n))
        for block, (rows, mat) in self._blocks(traj, k).items():
            if layout.has(block):
                out[rows, layout.slice(block)] += mat
        return out

    @abstractmethod
    def R_white(self, traj: NominalTrajectory, k: int) -> np.ndarray:
        """Covariance (m, m) of the white measurement noise actually present."""

    def R_filter(self, layout: StateLayout, traj: NominalTrajectory, k: int) -> np.ndarray:
        """White R plus the stationary covariance of the augmented states the filter omits."""
        R = self.R_white(traj, k).copy()
        parts = self._blocks(traj, k)
        for b in self.aug_blocks():
            if not layout.has(b.name) and b.name in parts:
                rows, mat = parts[b.name]
                Hb = np.zeros((self.size, b.size))
                Hb[rows] = mat
                R += Hb @ b.P0 @ Hb.T
        return R

    @abstractmethod
    def _blocks(self, traj: NominalTrajectory, k: int) -> dict:
        """{state block: (measurement rows, matrix)} of H at sample k."""


class GnssPosition(Measurement):
    def __init__(self, cfg: GnssAiding, index: int = 0):
        self.name, self.size = f"gnss{index}", 3
        self.rate_hz, self.latency_s = cfg.rate_hz, cfg.latency_s
        self.sigma_m = np.array(sigma3(cfg.sigma_m))
        self.lever_arm_m = np.array(cfg.lever_arm_m, dtype=float)
        self.gm_sigma_m, self.gm_tau_s = cfg.correlated_sigma_m, cfg.correlation_time_s

    def aug_blocks(self):
        if self.gm_sigma_m <= 0:
            return []
        i3 = np.eye(3)
        return [AugBlock(f"{self.name}_gm", -i3 / self.gm_tau_s,
                         2.0 * self.gm_sigma_m ** 2 / self.gm_tau_s * i3, self.gm_sigma_m ** 2 * i3)]

    def _blocks(self, traj, k):
        rows = slice(0, 3)
        out = {"pos": (rows, np.eye(3)), "att": (rows, skew(traj.c_bn[k] @ self.lever_arm_m))}
        if self.gm_sigma_m > 0:
            out[f"{self.name}_gm"] = (rows, np.eye(3))
        return out

    def R_white(self, traj, k):
        return np.diag(self.sigma_m ** 2)


class DvlVelocity(Measurement):
    def __init__(self, cfg: DvlAiding, index: int = 0):
        self.name, self.size = f"dvl{index}", 3
        self.rate_hz, self.latency_s = cfg.rate_hz, cfg.latency_s
        self.sigma_m_s = np.array(sigma3(cfg.sigma_m_s))
        self.bias_sigma_m_s = cfg.bias_sigma_m_s
        self.bias_tau_s = cfg.bias_correlation_time_s

    def aug_blocks(self):
        if self.bias_sigma_m_s <= 0:
            return []
        i3, var = np.eye(3), self.bias_sigma_m_s ** 2
        if self.bias_tau_s is None:     # random constant
            return [AugBlock(f"{self.name}_bias", 0 * i3, 0 * i3, var * i3)]
        return [AugBlock(f"{self.name}_bias", -i3 / self.bias_tau_s,
                         2.0 * var / self.bias_tau_s * i3, var * i3)]

    def _blocks(self, traj, k):
        rows = slice(0, 3)
        out = {"vel": (rows, np.eye(3)), "att": (rows, -skew(traj.v_n[k]))}
        if self.bias_sigma_m_s > 0:
            out[f"{self.name}_bias"] = (rows, -traj.c_bn[k])
        return out

    def R_white(self, traj, k):
        c = traj.c_bn[k]
        return c @ np.diag(self.sigma_m_s ** 2) @ c.T


class MasterInsTransfer(Measurement):
    def __init__(self, cfg: MasterInsAiding, index: int = 0):
        self.name, self.size = f"master{index}", 6
        self.rate_hz, self.latency_s = cfg.rate_hz, cfg.latency_s
        self.sigma = np.concatenate([sigma3(cfg.sigma_position_m), sigma3(cfg.sigma_velocity_m_s)])
        self.lever_arm_m = np.array(cfg.lever_arm_m, dtype=float)
        self.flexure = cfg.flexure
        self.estimate_flexure = cfg.estimate_flexure

    def aug_blocks(self):
        if self.flexure is None:
            return []
        F, Qc, P = flexure_blocks(self.flexure)
        return [AugBlock(f"{self.name}_flex", F, Qc, P, estimated=self.estimate_flexure)]

    def _blocks(self, traj, k):
        out = {"pos": (slice(0, 3), np.eye(3)), "vel": (slice(3, 6), np.eye(3))}
        if self.flexure is not None:
            c = traj.c_bn[k]
            m = np.zeros((6, 6))
            m[:3, :3] = c       # C d in the position rows
            m[3:, 3:] = c       # C ḋ in the velocity rows
            out[f"{self.name}_flex"] = (slice(0, 6), m)
        return out

    def R_white(self, traj, k):
        return np.diag(self.sigma ** 2)


class StarTrackerAttitude(Measurement):
    def __init__(self, cfg: StarTrackerAiding, index: int = 0):
        self.name, self.size = f"star{index}", 3
        self.rate_hz, self.latency_s = cfg.rate_hz, cfg.latency_s
        self.sigma_rad = np.array(sigma3(cfg.sigma_arcsec)) * ARCSEC_RAD

    def _blocks(self, traj, k):
        return {"att": (slice(0, 3), np.eye(3))}

    def R_white(self, traj, k):
        return np.diag(self.sigma_rad ** 2)


_BY_TYPE = {"gnss": GnssPosition, "dvl": DvlVelocity, "master_ins": MasterInsTransfer,
            "star_tracker": StarTrackerAttitude}


def measurement_from_config(cfg, index: int = 0) -> Measurement:
    """The measurement model of one validated aiding config."""
    return _BY_TYPE[cfg.type](cfg, index)
