"""Benchmark: validating a 50 MB parts catalog (formerly 74 s and 1.1 GB of memory).

Writes two valid 50 MB catalogs to a temporary folder — (a) the shipped rows repeated with
new ids (long quoted source/notes cells, ~80 k rows) and (b) compact rows (7 columns, ~750 k
rows) — then times, in a fresh process each (so the memory peak is the run's own):

* ``count_valid_parts`` — the vectorised validation ``sar-budget catalog validate`` uses;
* ``read_parts`` — the same plus one pydantic ``PartSpec`` per row (what the commands load).

Usage: ``python benchmarks/bench_catalog.py [MB]`` (default 50).
"""

from __future__ import annotations

import csv
import io
import random
import subprocess
import sys
import tempfile
from pathlib import Path

from budget.catalog.io import shipped_catalog_dir

RUN = ("import resource, sys, time\n"
       "from budget.catalog import io as cio\n"
       "t = time.perf_counter(); n = getattr(cio, sys.argv[1])(sys.argv[2])\n"
       "dt = time.perf_counter() - t\n"
       "n = n if isinstance(n, int) else len(n)\n"
       "rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024\n"
       "print(f'{sys.argv[1]:<18} {n:>8} parts  {dt:6.2f} s  peak RSS {rss:6.0f} MB')\n")


def shipped_rows(path: Path, size: int) -> None:
    rows = list(csv.reader(io.StringIO((shipped_catalog_dir() / "parts.csv").read_text())))
    header, body = rows[0], rows[1:]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    i = 0
    while buf.tell() < size:
        r = list(body[i % len(body)])
        r[0] = f"P{i:07d}"
        w.writerow(r)
        i += 1
    path.write_text(buf.getvalue())


def compact_rows(path: Path, size: int) -> None:
    rng = random.Random(0)
    lines = ["part_id,grade,gyro_arw_deg_rt_h,gyro_bias_instability_deg_h,accel_vrw_m_s_rt_h,"
             "accel_bias_instability_ug,source"]
    n, i = len(lines[0]), 0
    while n < size:
        line = (f"Q{i:07d},tactical,{rng.uniform(0, 10):.6g},{rng.uniform(0, 100):.6g},"
                f"{rng.uniform(0, 1):.6g},{rng.uniform(0, 1000):.6g},datasheet rev {i % 7}")
        lines.append(line)
        n += len(line) + 1
        i += 1
    path.write_text("\n".join(lines) + "\n")


def main() -> None:
    mb = float(sys.argv[1]) if len(sys.argv) > 1 else 50.0
    with tempfile.TemporaryDirectory(prefix="bench_catalog_") as d:
        for name, make in (("shipped rows", shipped_rows), ("compact rows", compact_rows)):
            path = Path(d) / f"{name.split()[0]}.csv"
            make(path, int(mb * 1e6))
            print(f"{name}: {path.stat().st_size / 1e6:.1f} MB")
            for fn in ("count_valid_parts", "read_parts"):
                r = subprocess.run([sys.executable, "-c", RUN, fn, str(path)], capture_output=True,
                                   text=True, check=True)
                print("  " + r.stdout.strip())


if __name__ == "__main__":
    main()
