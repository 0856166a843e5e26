"""``--platform-motion`` and its parameters, shared by ``check``, ``mc``, ``sweep`` and ``report``
(a module of its own, light to import: ``check --help`` need not load the Monte Carlo)."""

from __future__ import annotations

from ..errors import InputError
from ..nav.manoeuvre import KINDS as PLATFORM_MOTIONS


def platform_motion_from_args(args) -> dict | None:
    """``--platform-motion`` and its parameters as the ``platform_motion`` option (None: not given);
    a parameter of another kind, or ``--disturbance`` without ``custom``, is refused."""
    kind = getattr(args, "platform_motion", None)
    given = {f: getattr(args, a, None) for f, a in (("peak_rate_deg_s", "manoeuvre_rate"),
                                                   ("period_s", "manoeuvre_period"),
                                                   ("angle_deg", "manoeuvre_angle"))}
    given = {k: v for k, v in given.items() if v is not None}
    path = getattr(args, "disturbance", None)
    if kind is None:
        if given or path:
            raise InputError("manoeuvre parameters need --platform-motion", field="--platform-motion",
                             expected="oscillation, attitude_change or custom")
        return None
    out = {"kind": kind, **given}
    if kind == "custom":
        if not path:
            raise InputError("--platform-motion custom needs --disturbance D.json", field="--disturbance")
        from ..nav.platform import Disturbance
        out["disturbance"] = Disturbance.load(path)
    elif path:
        raise InputError("--disturbance is the custom platform motion", field="--disturbance", value=path,
                         expected="--platform-motion custom")
    return out


def add_platform_motion_options(p, *, unset: str = "straight (default; gyro scale factor and misalignment "
                                                  "then have no effect)") -> None:
    """``--platform-motion`` and its parameters (:func:`platform_motion_from_args` reads them);
    ``unset`` says what the command does without the option."""
    p.add_argument("--platform-motion", choices=PLATFORM_MOTIONS, default=None,
                   help=f"what the platform does over the aperture: {unset}, oscillation (roll/pitch/yaw at "
                        "the scenario's platform_rate_deg_s), attitude_change (a roll through Θ over the "
                        "aperture, the gyro-scale-factor bound's manoeuvre) or custom (--disturbance)")
    p.add_argument("--manoeuvre-rate", type=float, default=None, metavar="DEG_S",
                   help="oscillation: peak rate per axis in deg/s (default the scenario's platform_rate_deg_s)")
    p.add_argument("--manoeuvre-period", type=float, default=None, metavar="S",
                   help="oscillation: period in s (default 10)")
    p.add_argument("--manoeuvre-angle", type=float, default=None, metavar="DEG",
                   help="attitude_change: roll change Θ in degrees (default 57.3 = 1 rad)")
    p.add_argument("--disturbance", metavar="D.json", default=None,
                   help="custom: platform disturbance JSON (sinusoids / random PSD per axis)")
