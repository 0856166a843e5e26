"""Safe readers: compressed inputs opened with a counted size limit and
integrity errors as one-line InputErrors naming the file; JSON/YAML nesting, size, alias and
integer limits; long values shortened in messages."""

from __future__ import annotations

import bz2
import gzip
import json
import lzma
import tarfile
import tracemalloc
import zipfile

import pytest

from budget.catalog.io import read_parts
from budget.errors import InputError, short_repr
from budget.fileio import check_input_file, read_bytes
from budget.structured import MAX_DEPTH, read_structured
from budget.noise import read_log
from budget.noise.logs import _estimate_rows
from budget.scenario import Scenario

LOG = "time_s,gyro_x_dps,accel_z_mps2\n" + "".join(f"{i / 100:.2f},0.0{i % 7},9.8{i % 5}\n"
                                                   for i in range(2000))


def _gz(tmp_path, name="log.csv.gz", text=LOG):
    p = tmp_path / name
    p.write_bytes(gzip.compress(text.encode()))
    return p


def test_plain_and_compressed_logs_read_the_same(tmp_path):
    plain = tmp_path / "log.csv"
    plain.write_text(LOG)
    z = tmp_path / "log.zip"
    with zipfile.ZipFile(z, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("log.csv", LOG)
    ref = read_log(plain).channels["gyro_x"]
    for p in (_gz(tmp_path), z):
        assert (read_log(p).channels["gyro_x"] == ref).all()


@pytest.mark.parametrize("kind", ["gz", "bz2", "xz"])
def test_truncated_stream_is_named(tmp_path, kind):
    comp = {"gz": gzip.compress, "bz2": bz2.compress, "xz": lzma.compress}[kind]
    data = comp(LOG.encode())
    p = tmp_path / f"log.csv.{kind}"
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="damaged or truncated") as e:
        read_log(p)
    assert str(p) in str(e.value)


def test_forged_gzip_size_trailer_is_not_trusted(tmp_path):
    p = _gz(tmp_path)
    data = bytearray(p.read_bytes())
    data[-4:] = (2 ** 32 - 1).to_bytes(4, "little")  # claims 4 GiB decompressed
    p.write_bytes(bytes(data))
    # the row estimate (used to preallocate) ignores the forged size …
    est = _estimate_rows(p)
    assert est is None or est < 100_000
    # … and reading reports the inconsistent stream instead of allocating for it
    tracemalloc.start()
    with pytest.raises(InputError, match="damaged"):
        read_log(p)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 50e6


def test_decompression_bomb_is_stopped_by_counting(tmp_path):
    p = tmp_path / "bomb.json.gz"
    p.write_bytes(gzip.compress(b" " * 30_000_000))  # 30 MB of spaces, ~30 kB compressed
    with pytest.raises(InputError, match="decompresses to more than"):
        read_bytes(p, 10_000_000)


def test_zip_with_two_members_tar_and_zstd_are_refused(tmp_path):
    z = tmp_path / "two.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("a.csv", LOG)
        zf.writestr("b.csv", LOG)
    with pytest.raises(InputError, match="holds 2 files"):
        read_log(z)
    t = tmp_path / "log.tar"
    src = tmp_path / "log.csv"
    src.write_text(LOG)
    with tarfile.open(t, "w") as tf:
        tf.add(src, arcname="log.csv")
    with pytest.raises(InputError, match="not supported"):
        read_log(t)
    zst = tmp_path / "log.csv.zst"
    zst.write_bytes(b"\x28\xb5\x2f\xfd" + bytes(32))
    with pytest.raises(InputError, match="not supported"):
        read_log(zst)
    tgz = tmp_path / "log.tar.gz"
    tgz.write_bytes(gzip.compress(t.read_bytes()))
    with pytest.raises(InputError, match="not supported"):
        check_input_file(tgz)


def test_folder_as_input_is_an_input_error(tmp_path):
    with pytest.raises(InputError):
        Scenario.load(tmp_path)
    with pytest.raises(InputError):
        read_parts(tmp_path)


@pytest.mark.parametrize("suffix,text", [
    (".json", '{"a": ' + "[" * 100_000 + "]" * 100_000 + "}"),
    (".yaml", "a: " + "[" * 800 + "]" * 800 + "\n"),
    (".json", '{"a": ' + "[" * (MAX_DEPTH + 5) + "]" * (MAX_DEPTH + 5) + "}"),
])
def test_deep_nesting_is_refused(tmp_path, suffix, text):
    p = tmp_path / f"deep{suffix}"
    p.write_text(text)
    with pytest.raises(InputError, match="nested"):
        read_structured(p, "a scenario")


@pytest.mark.parametrize("suffix", [".json", ".yaml"])
def test_huge_integers_are_refused(tmp_path, suffix):
    p = tmp_path / f"s{suffix}"
    digits = "9" * 5000
    p.write_text(f'{{"carrier_frequency_hz": {digits}}}' if suffix == ".json"
                 else f"carrier_frequency_hz: {digits}\n")
    with pytest.raises(InputError, match="digits") as e:
        Scenario.load(p)
    assert len(str(e.value)) < 400


def test_billion_laughs_is_refused_before_it_is_built(tmp_path):
    lines = ["a: &a [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for i in range(1, 10):
        prev, cur = chr(ord("a") + i - 1), chr(ord("a") + i)
        lines.append(f"{cur}: &{cur} [" + ", ".join([f"*{prev}"] * 9) + "]")
    lines.append("carrier_frequency_hz: *j")  # lands in an invalid field: 9^10 leaves
    p = tmp_path / "lol.yaml"
    p.write_text("\n".join(lines) + "\n")
    tracemalloc.start()
    with pytest.raises(InputError, match="expands to more than"):
        Scenario.load(p)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 50e6


def test_recursive_yaml_alias_is_refused(tmp_path):
    p = tmp_path / "rec.yaml"
    p.write_text("a: &x [1, *x]\n")
    with pytest.raises(InputError):
        read_structured(p, "a scenario")


def test_messages_shorten_huge_values(tmp_path):
    cell = "x" * 5_000_000
    for row, field in ((f"P2,{cell},ds", "grade"), (f"P2,tactical,{cell}", "source")):
        p = tmp_path / "big.csv"
        p.write_text(f"part_id,grade,source\nP1,tactical,ds\n{row}\n")
        with pytest.raises(InputError) as e:
            read_parts(p)
        msg = str(e.value)
        assert "row 3" in msg and f"field {field}" in msg and len(msg) < 600
    assert len(short_repr(list(range(10 ** 6)))) < 100
    nested = [[[[[["deep"]]]]]]
    assert len(short_repr(nested)) < 100


def test_scenario_errors_name_file_and_field_for_json_values(tmp_path):
    p = tmp_path / "s.json"
    p.write_text(json.dumps({"carrier_frequency_hz": "x" * 100_000, "slant_range_m": 1,
                             "azimuth_resolution_m": 1, "range_resolution_m": 1,
                             "platform_speed_m_s": 1}))
    with pytest.raises(InputError) as e:
        Scenario.load(p)
    assert "s.json" in str(e.value) and "carrier_frequency_hz" in str(e.value)
    assert len(str(e.value)) < 500


def test_unreadable_file_is_an_input_error(tmp_path, monkeypatch):
    # the tests run as root, where chmod 000 does not stop reading: fake the OS refusal
    from budget import fileio

    def refuse(*a, **k):
        raise PermissionError(13, "Permission denied", str(a[0]))

    p = tmp_path / "s.json"
    p.write_text("{}")
    monkeypatch.setattr(fileio, "open", refuse, raising=False)
    for fn in (lambda: read_structured(p, "a scenario"), lambda: read_log(p), lambda: read_parts(p)):
        with pytest.raises(InputError, match="Permission denied"):
            fn()
