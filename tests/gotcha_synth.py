"""What the SAR tests share about the Gotcha pass they read and imitate: its file names and a
circular track of the same geometry for synthetic phase histories (written independently of the
image former)."""

from __future__ import annotations

import numpy as np

#: The four azimuth files of pass 1, HH, in aperture order (``../shared/data/sar/gotcha``).
GOTCHA_FILES = [f"data_3dsar_pass1_az00{i}_HH.mat" for i in range(1, 5)]


def circular_track(n_pulses: int = 469, span_deg: float = 4.0, ground_m: float = 7090.0,
                   height_m: float = 7276.0) -> np.ndarray:
    """(n_pulses, 3) antenna positions, m, of a circular pass about the scene centre, centred on
    azimuth 0 (antenna along +x at mid-aperture), as the Gotcha pass flies it."""
    th = np.radians(np.linspace(-span_deg / 2, span_deg / 2, n_pulses))
    return np.stack([ground_m * np.cos(th), ground_m * np.sin(th), np.full(n_pulses, height_m)], axis=1)
