"""File helpers shared by every reader and writer: bounded text reads and atomic writes."""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from .errors import InputError


def read_text(path: Path, max_bytes: int = 10_000_000) -> str:
    """Read a small UTF-8 text file; empty, huge or non-UTF-8 files raise :class:`InputError`."""
    size = path.stat().st_size
    if size == 0:
        raise InputError("file is empty", file=path)
    if size > max_bytes:
        raise InputError(f"file is {size} bytes", file=path, expected=f"at most {max_bytes} bytes")
    try:
        return path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(f"not UTF-8 text (byte {err.start})", file=path, expected="UTF-8 encoding") from None


def _target_mode(path: Path) -> int:
    try:
        return path.stat().st_mode & 0o7777
    except FileNotFoundError:
        return 0o666 & ~_umask()


def _umask() -> int:
    """The process umask, read without changing it (os.umask would race other threads)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass  # no /proc (not Linux): fall through to the usual default
    return 0o022


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and ``os.replace``: never half-written."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        # mkstemp creates 0600; give the file the mode it had, or what the umask allows
        os.chmod(tmp, _target_mode(path))
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def read_structured(path: str | Path, what: str, max_bytes: int = 10_000_000) -> dict:
    """Read a JSON or YAML mapping (by suffix; YAML also reads JSON) for ``what`` (e.g.
    "a scenario"); a missing, empty, malformed or non-mapping file raises :class:`InputError`."""
    import json

    import yaml

    path = Path(path)
    if not path.is_file():
        raise InputError("file not found", file=path, expected=f"{what} JSON/YAML file")
    text = read_text(path, max_bytes=max_bytes)
    is_yaml = path.suffix.lower() in (".yaml", ".yml")
    try:
        data = yaml.safe_load(text) if is_yaml else json.loads(text)
    except (json.JSONDecodeError, yaml.YAMLError) as err:
        raise InputError(f"not valid {'YAML' if is_yaml else 'JSON'}: {str(err).splitlines()[0]}",
                         file=path) from None
    if not isinstance(data, dict):
        raise InputError(f"{what} must be a mapping of keys to values", file=path,
                         expected="a JSON object / YAML mapping")
    return data


def json_safe(obj):
    """``obj`` made JSON-safe: numpy scalars/arrays to Python, non-finite floats to ``None``."""
    if isinstance(obj, dict):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def json_text(obj) -> str:
    """Indented JSON text of ``obj`` (through :func:`json_safe`), newline-terminated."""
    return json.dumps(json_safe(obj), indent=2, ensure_ascii=False) + "\n"
