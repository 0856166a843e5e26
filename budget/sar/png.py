"""Minimal PNG writer (8-bit greyscale, zlib, no dependency beyond the standard library and NumPy)
for SAR magnitude images in dB, written atomically.

PNG layout (ISO/IEC 15948): signature, IHDR (width, height, bit depth 8, colour type 0), one IDAT
with the zlib-compressed scanlines (filter byte 0 each), IEND; every chunk with its CRC-32.
"""

from __future__ import annotations

import os
import struct
import tempfile
import zlib
from pathlib import Path

import numpy as np

from ..errors import InputError


def _chunk(kind: bytes, payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF)


def png_bytes(gray: np.ndarray) -> bytes:
    """PNG file content of an 8-bit greyscale array (rows top to bottom)."""
    g = np.asarray(gray)
    if g.ndim != 2 or g.shape[0] < 1 or g.shape[1] < 1 or g.dtype != np.uint8:
        raise InputError(f"image has shape {g.shape}, dtype {g.dtype}", field="image",
                         expected="a 2-D uint8 array")
    h, w = g.shape
    raw = np.concatenate([np.zeros((h, 1), np.uint8), g], axis=1).tobytes()
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + _chunk(b"IDAT", zlib.compress(raw, 9)) + _chunk(b"IEND", b""))


def db_to_gray(db: np.ndarray, dynamic_range_db: float = 40.0) -> np.ndarray:
    """dB values (0 = white) mapped linearly to 0–255 over ``dynamic_range_db``; below is black."""
    x = (np.asarray(db, dtype=float) + dynamic_range_db) / dynamic_range_db
    return np.round(255.0 * np.clip(np.nan_to_num(x, nan=0.0), 0.0, 1.0)).astype(np.uint8)


def write_png(path: str | Path, gray: np.ndarray) -> None:
    """Write ``gray`` (uint8) as a PNG through a temporary file and ``os.replace``."""
    path = Path(path)
    data = png_bytes(gray)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
