"""File helpers shared by every reader and writer: bounded, decompressing reads; atomic writes
(spreadsheet-safe CSV text and printable terminal text: :mod:`budget.safe_text`); JSON/YAML with
depth, size and alias limits is :mod:`budget.structured`.

Limits (each refused with an :class:`~budget.errors.InputError` naming the file):

* compressed input (gzip, bzip2, xz, a zip with one member) is decompressed as a stream and
  the decompressed bytes are *counted* — a size field in the container (gzip's trailer, zip's
  header) is never trusted; ``.zst`` and tar archives are refused; a truncated or damaged
  stream is reported as such;
* JSON/YAML: :mod:`budget.structured`.
"""

from __future__ import annotations

import bz2
import codecs
import contextlib
import gzip
import io
import json
import lzma
import math
import os
import re
import stat
import tempfile
import time
import warnings
import zipfile
import zlib
from pathlib import Path

import numpy as np

from .errors import InputError, OutputError

#: Default cap on the decompressed size of any compressed input (bytes).
MAX_DECOMPRESSED_BYTES = 4_000_000_000

_MAGIC = ((b"\x1f\x8b", "gzip"), (b"BZh", "bzip2"), (b"\xfd7zXZ\x00", "xz"),
          (b"PK\x03\x04", "zip"), (b"PK\x05\x06", "zip"), (b"\x28\xb5\x2f\xfd", "zstd"))
_DAMAGED = (EOFError, zlib.error, lzma.LZMAError, zipfile.BadZipFile, gzip.BadGzipFile, OSError)


@contextlib.contextmanager
def _reading(path):
    """Turn the operating system's errors on opening ``path`` into :class:`InputError`."""
    try:
        yield
    except FileNotFoundError:
        raise InputError("file not found", file=path) from None
    except IsADirectoryError:
        raise InputError("is a folder, not a file", file=path) from None
    except OSError as err:
        raise InputError(f"cannot read the file ({err.strerror or type(err).__name__})",
                         file=path) from None


def compression_of(path: Path) -> str | None:
    """Container format of ``path`` from its first bytes (not its suffix): gzip, bzip2, xz, zip,
    zstd, tar or None (plain); an unreadable file raises :class:`InputError`."""
    with _reading(path):
        with open(path, "rb") as fh:
            head = fh.read(262)
    for magic, name in _MAGIC:
        if head.startswith(magic):
            return name
    if head[257:262] == b"ustar":
        return "tar"
    return None


class _Counted(io.RawIOBase):
    """A read-only stream that counts what it passes on and maps decompression errors."""

    def __init__(self, inner, path: Path, limit: int, kind: str | None):
        self._inner, self._path, self._limit, self._kind = inner, path, limit, kind
        self.count = 0

    def readable(self) -> bool:
        return True

    def readinto(self, buf) -> int:
        try:
            data = self._inner.read(len(buf))
        except InputError:
            raise
        except _DAMAGED as err:
            what = f"{self._kind} data" if self._kind else "file"
            raise InputError(f"{what} is damaged or truncated ({type(err).__name__}: "
                             f"{str(err)[:120]})", file=self._path,
                             expected="a complete file (download or copy it again)") from None
        n = len(data)
        self.count += n
        if self.count > self._limit:
            raise InputError(f"decompresses to more than {self._limit:,} bytes", file=self._path,
                             expected=f"at most {self._limit:,} bytes of text")
        buf[:n] = data
        return n

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self._inner.close()
        super().close()


def _open_inner(path: Path, kind: str | None):
    if kind is None:
        return open(path, "rb")
    if kind == "gzip":
        return gzip.open(path, "rb")
    if kind == "bzip2":
        return bz2.open(path, "rb")
    if kind == "xz":
        return lzma.open(path, "rb")
    if kind == "zip":
        try:
            zf = zipfile.ZipFile(path)
        except (zipfile.BadZipFile, OSError, EOFError) as err:
            raise InputError(f"not a readable zip archive ({err})", file=path) from None
        members = [m for m in zf.infolist() if not m.is_dir()]
        if len(members) != 1:
            zf.close()
            raise InputError(f"zip archive holds {len(members)} files", file=path,
                             expected="exactly one file in the zip (or the plain/.gz file)")
        try:
            inner = zf.open(members[0])
        except (NotImplementedError, RuntimeError, zipfile.BadZipFile) as err:
            zf.close()
            raise InputError(f"zip member cannot be read ({err})", file=path,
                             expected="an unencrypted zip (deflate, bzip2 or lzma)") from None
        return _ZipMember(inner, zf)
    what = {"zstd": "Zstandard (.zst)", "tar": "a tar archive"}[kind]
    raise InputError(f"{what} is not supported", file=path,
                     expected="a plain, .gz, .bz2, .xz or single-file .zip file")


class _ZipMember:
    def __init__(self, member, zf):
        self._m, self._zf = member, zf

    def read(self, n=-1):
        return self._m.read(n)

    def close(self):
        self._m.close()
        self._zf.close()


@contextlib.contextmanager
def open_input(path: str | Path, max_bytes: int = MAX_DECOMPRESSED_BYTES):
    """Open ``path`` for binary reading, decompressing gzip/bzip2/xz/single-file zip (detected
    by content), with at most ``max_bytes`` decompressed bytes; every problem is an
    :class:`InputError` naming the file."""
    path = Path(path)
    with _reading(path):
        kind = compression_of(path)
        inner = _open_inner(path, kind)
    raw = _Counted(inner, path, max_bytes, kind)
    stream = io.BufferedReader(raw, buffer_size=1 << 20)
    try:
        yield stream
    finally:
        stream.close()


_REFUSED_SUFFIXES = (".zst", ".zstd", ".tar", ".tgz", ".tbz2", ".txz")


def check_input_file(path: str | Path, max_bytes: int = MAX_DECOMPRESSED_BYTES) -> str | None:
    """Make sure ``path`` can be read to the end before a reader (e.g. pandas) starts on it:
    readable, not a tar/zstd archive, a zip with one member, and a compressed stream that is
    complete, undamaged and at most ``max_bytes`` decompressed (streamed and counted, in
    bounded memory). Returns the compression found (None = plain); raises :class:`InputError`."""
    path = Path(path)
    name = path.name.lower()
    if name.endswith(_REFUSED_SUFFIXES) or ".tar." in name:
        raise InputError("archives (tar) and Zstandard files are not supported", file=path,
                         expected="a plain, .gz, .bz2, .xz or single-file .zip file")
    try:
        kind = compression_of(path)
    except OSError as err:
        raise InputError(f"cannot read the file ({err.strerror or type(err).__name__})",
                         file=path) from None
    if kind is None:
        return None
    with open_input(path, max_bytes) as fh:
        while fh.read(1 << 20):
            pass
    return kind


def require_file(path: str | Path, expected: str | None = None) -> Path:
    """``path`` if it is a regular file (or a link to one); otherwise :class:`InputError` saying
    what it is instead: not found, a folder, or not a regular file (a device, a pipe)."""
    path = Path(path)
    if path.is_file():
        return path
    if path.is_dir():
        raise InputError("is a folder, not a file", file=path, expected=expected)
    if path.exists():
        raise InputError("is not a regular file", file=path, expected=expected)
    raise InputError("file not found", file=path, expected=expected)


def read_bytes(path: str | Path, max_bytes: int) -> bytes:
    """All (decompressed) bytes of ``path``, at most ``max_bytes``; errors as :class:`InputError`."""
    path = Path(path)
    if path.is_dir():
        raise InputError("is a folder, not a file", file=path)
    with open_input(path, max_bytes) as fh:
        return fh.read()


#: Byte-order marks → the codec that reads the text they start (Excel's "CSV UTF-8" writes the
#: UTF-8 one, a spreadsheet's "Unicode text" export UTF-16). Longest first: the UTF-32 LE mark
#: begins with the UTF-16 LE one. The "utf-16"/"utf-32" codecs read the mark's byte order.
BYTE_ORDER_MARKS = ((b"\xff\xfe\x00\x00", "utf-32"), (b"\x00\x00\xfe\xff", "utf-32"),
                    (b"\xef\xbb\xbf", "utf-8-sig"), (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"))


def text_encoding(head: bytes) -> str:
    """The codec of text whose first bytes are ``head`` (4 are enough): the one its byte-order
    mark names (:data:`BYTE_ORDER_MARKS`), else UTF-8. The one place where a reader of delimited
    text (IMU logs, Allan tables) finds its encoding."""
    return next((codec for bom, codec in BYTE_ORDER_MARKS if head.startswith(bom)), "utf-8")


#: Bytes at the start of a file looked at for its 8-bit encoding (:func:`input_encoding`).
ENCODING_PROBE_BYTES = 1 << 16
#: The codec of delimited text without a byte-order mark that is not UTF-8: Windows' 8-bit code
#: page (Latin-1 with printable 0x80–0x9F), in which Windows loggers and spreadsheet exports write
#: ``°/s`` and ``µg`` (0xB0, 0xB5) — read as UTF-8 they became ``�/s``, a unit refused as unknown.
EIGHT_BIT_CODEC = "cp1252"


def input_encoding(path: str | Path) -> str:
    """:func:`text_encoding` of ``path``'s (decompressed) first bytes; without a byte-order mark,
    :data:`EIGHT_BIT_CODEC` when the first :data:`ENCODING_PROBE_BYTES` are not UTF-8 (a
    multi-byte character cut at the probe's end is no evidence)."""
    with open_input(path) as fh:
        head = fh.read(ENCODING_PROBE_BYTES)
    codec = text_encoding(head[:4])
    if codec != "utf-8":
        return codec
    try:
        codecs.getincrementaldecoder("utf-8")().decode(head, final=False)
    except UnicodeDecodeError:
        return EIGHT_BIT_CODEC
    return codec


def read_text(path: Path, max_bytes: int = 10_000_000, expected: str | None = None, *,
              wide: bool = False) -> str:
    """Read a small UTF-8 text file (optionally compressed); a missing, non-regular, empty, huge,
    unreadable, non-UTF-8 or binary (NUL bytes) file raises :class:`InputError`, whose
    ``expected`` says what the file should be (``expected``, e.g. "a catalog CSV file").
    ``wide``: UTF-16/32 text with its byte-order mark is read too (:func:`text_encoding`) — for
    readers that never write the file back (a catalog is appended to in UTF-8, so it stays
    UTF-8 only)."""
    path = Path(path)
    if not path.exists():
        raise InputError("file not found", file=path, expected=expected)
    if not path.is_file() and not path.is_dir():
        raise InputError("is not a regular file", file=path, expected=expected)
    if path.is_file() and path.stat().st_size == 0:
        raise InputError("file is empty", file=path, expected=expected)
    if path.is_file() and compression_of(path) is None and path.stat().st_size > max_bytes:
        raise InputError(f"file is {path.stat().st_size} bytes", file=path,
                         expected=f"at most {max_bytes} bytes")
    data = read_bytes(path, max_bytes)
    codec = text_encoding(data[:4])
    if codec in ("utf-8", "utf-8-sig") or not wide:
        codec = "utf-8-sig"
    try:
        text = data.decode(codec)
    except UnicodeDecodeError as err:
        wide_mark = text_encoding(data[:4]) not in ("utf-8", "utf-8-sig")
        reason = (f"{text_encoding(data[:4]).upper()} text (its byte-order mark), not UTF-8" if wide_mark and not wide
                  else f"not {codec.replace('-sig', '').upper()} text (byte {err.start})")
        raise InputError(reason, file=path, expected="UTF-8 encoding") from None
    if "\x00" in text:
        raise InputError("contains NUL bytes (binary file?)", file=path, expected=expected or "UTF-8 text")
    if not text.strip():
        raise InputError("file is empty", file=path, expected=expected)
    return text


# --- atomic writes ---------------------------------------------------------------------------

#: Temporary files of :func:`atomic_write_text` are named ``.<target>.sar-budget-<random>.tmp``;
#: ones older than this (left by a killed process) are removed by the next write to the target.
STALE_TMP_S = 3600.0
TMP_TAG = ".sar-budget-"


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


def _clean_stale(path: Path) -> None:
    now = time.time()
    with contextlib.suppress(OSError):
        for old in path.parent.glob(f".{glob_escape(path.name)}{TMP_TAG}*.tmp"):
            with contextlib.suppress(OSError):
                if now - old.lstat().st_mtime > STALE_TMP_S:
                    old.unlink()


def glob_escape(name: str) -> str:
    return re.sub(r"([*?\[])", r"[\1]", name)


def read_only_reason(path: str | Path) -> str | None:
    """Why an existing file must not be overwritten (``None`` when it may be): the user cannot
    write it, or it has no write permission bit at all (``chmod a-w``: marked read-only on
    purpose; root's ``os.access`` says yes to it, and ``os.replace`` would replace it anyway)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None
    if not stat.S_ISREG(mode):
        return None
    if not mode & 0o222:
        return f"file is read-only (mode {mode & 0o7777:04o}); make it writable (chmod u+w) or give another file"
    if not os.access(path, os.W_OK):
        return "file is read-only for this user; make it writable or give another file"
    return None


def atomic_write_text(path: str | Path, text: str, *, create_dirs: bool = True) -> None:
    """Write ``text`` to ``path`` through a temporary file and ``os.replace``: never half-written.

    A symbolic link is followed (its target is updated, the link stays). An existing target
    that is read-only (:func:`read_only_reason`) is refused with :class:`OutputError` and left
    as it is: the rename would otherwise replace it whatever its permissions. The temporary file
    (``.<name>.sar-budget-XXXX.tmp`` beside the target) is removed on any failure or
    interruption; stale ones left by a killed process are cleaned after an hour. ``create_dirs``:
    a missing folder of ``path`` is created, with a :class:`UserWarning` naming it (the command
    line prints it as a warning line); False refuses it with :class:`OutputError`.
    """
    given = path
    path = Path(os.path.realpath(path))
    if path.is_dir():
        raise OutputError("is a folder; give a file name", file=given)
    locked = read_only_reason(path)
    if locked:
        raise OutputError(locked, file=given)
    if not create_dirs and not path.parent.is_dir():
        raise OutputError(f"folder {path.parent} does not exist", file=given)
    if create_dirs and not path.parent.is_dir():
        created = [d for d in (path.parent, *path.parent.parents) if not d.exists()]
        path.parent.mkdir(parents=True, exist_ok=True)
        # an output's missing folders are created (as documented for --json, --out, --report …),
        # and said: a mistyped folder would otherwise appear silently
        many = len(created) > 1
        warnings.warn(f"created folder{'s' if many else ''} {', '.join(str(d) for d in reversed(created))} "
                      f"({'they' if many else 'it'} did not exist) to write {given}", UserWarning, stacklevel=2)
    _clean_stale(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}{TMP_TAG}", suffix=".tmp", dir=path.parent)
    try:
        # mkstemp creates 0600; give the file the mode it had, or what the umask allows
        os.chmod(tmp, _target_mode(path))
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


# --- JSON / YAML -----------------------------------------------------------------------------

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
