"""Model-gap workflow on the real ADIS16405 recordings against the catalog part ADIS16405.

Inputs (read in place, never copied): ``../shared/data/logs/adis16405_static_{1,2}.csv.gz``
(100 Hz, 10⁶ samples each) and the published Allan table ``../shared/data/adev/adis16405.csv``
(of log 1). For each one: :func:`budget.gap.run_gap` against ``ADIS16405``, then written to
``docs/gap/`` (or ``--out``): the JSON report, the updated model (catalog row + named effects),
the figures as HTML (plotly) and, for the README, PNG copies of the log-1 figures (through
kaleido when installed, else redrawn with matplotlib from the same traces). A second pass with
each updated model, with the same seed (it starts where the first pass stopped) and with
another seed (fresh realizations), checks what is still named. Prints a Markdown summary.

    python3 examples/gap_adis16405.py [--out docs/gap] [--seed 0] [--max-rows N] [--max-steps 20]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout too

from budget.fileio import atomic_write_text  # noqa: E402
from budget.gap import run_gap  # noqa: E402
from budget.plots.gap import adev_figure, gap_figure, psd_figure, write_figures  # noqa: E402

DATA = ROOT.parent / "shared" / "data"
PART = "ADIS16405"


def save_png(fig, path: Path) -> None:
    """PNG of a plotly figure: kaleido if present, else the same traces drawn by matplotlib."""
    try:
        fig.write_image(str(path), width=900, height=520)
        return
    except (ValueError, ImportError, RuntimeError):
        pass
    try:
        import matplotlib
    except ImportError:
        print(f"no PNG for {path.name}: neither kaleido nor matplotlib is installed (the HTML is written)")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lay = fig.layout
    f, ax = plt.subplots(figsize=(9, 5.2), dpi=100)
    bars = [t for t in fig.data if t.type == "bar"]
    for i, t in enumerate(bars):
        x = list(range(len(t.x)))
        w = 0.8 / len(bars)
        ax.bar([v - 0.4 + w * (i + 0.5) for v in x], t.y, w, label=t.name, color=t.marker.color)
        ax.set_xticks(x, list(t.x))
    for t in fig.data:
        if t.type != "scatter":
            continue
        if t.fill == "toself":
            ax.fill(t.x, t.y, color="0.85", label=t.name, lw=0)
        elif t.marker is not None and t.marker.symbol == "line-ew-open":
            ax.scatter(range(len(t.x)), t.y, marker="_", s=900, color="k", label=t.name)
        else:
            dash = {"dash": "--", "dot": ":"}.get(t.line.dash, "-")
            ax.plot(t.x, t.y, dash, color=t.line.color, lw=t.line.width or 1.5, label=t.name,
                    marker="o" if t.mode and "markers" in t.mode else None, ms=3)
    if lay.xaxis.type == "log":
        ax.set_xscale("log")
    if lay.yaxis.type == "log":
        ax.set_yscale("log")
    ax.set_xlabel(lay.xaxis.title.text or "")
    ax.set_ylabel(lay.yaxis.title.text or "")
    ax.set_title(lay.title.text or "", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    f.tight_layout()
    f.savefig(path)
    plt.close(f)


def run_one(name: str, measured, out: Path, seed: int, **kw):
    t0 = time.perf_counter()
    rep = run_gap(measured, PART, seed=seed, **kw)
    dt = time.perf_counter() - t0
    rep.save(out / f"{name}_report.json")
    rep.updated_model.save(out / f"{name}_updated_model.json")
    write_figures(rep, out / f"{name}_figures")
    again = []
    for k, s in enumerate((seed, seed + 1)):
        rerun = run_gap(measured, out / f"{name}_updated_model.json", seed=s, **kw)
        rerun.save(out / f"{name}_rerun{k}_report.json")
        again.append(rerun)
    return rep, again, dt


def markdown(name: str, rep, again, dt: float) -> str:
    lines = [f"### {name}: {rep.n_samples:,} samples at {rep.rate_hz:g} Hz ({rep.kind}), {dt:.0f} s "
             f"(seed {rep.seed}, {rep.realizations} realizations per channel)",
             "", f"overall gap {rep.gap_before:.4g} → {rep.gap_after:.4g} ("
             f"{'within' if rep.within_noise else 'NOT within'} noise: threshold "
             f"{rep.null_after.overall_threshold:.3g}); stop: {rep.stop_reason}", "",
             "| step | effect | channel | parameters (SI) | channel gap before → after |",
             "|---|---|---|---|---|"]
    for i, s in enumerate(rep.steps, 1):
        par = ", ".join(f"{k} = {v:.4g}" for k, v in s.params.items())
        lines.append(f"| {i} | {s.name} | {s.channel} | {par} | {s.gap_before:.4g} → {s.gap_after:.4g} |")
    lines += ["", "| channel | gap before | gap after | threshold | strongest remaining disagreement |",
              "|---|---|---|---|---|"]
    from budget.gap.report import localize
    for ch, c in rep.channels.items():
        top = localize(c.terms_after)["top"][:2]
        where = "; ".join(f"{t['statistic']} {t['where']} (z = {t['z']:+.0f})" for t in top) or "—"
        lines.append(f"| {ch} | {c.gap_before:.4g} | {c.gap_after:.4g} | "
                     f"{rep.null_after.channel_threshold(ch):.3g} | {where} |")
    for rerun, how in zip(again, ("the same seed", "another seed")):
        named = ", ".join(f"{s.name}@{s.channel}" for s in rerun.steps) or "nothing"
        lines.append(f"Second pass with the updated model and {how}: gap {rerun.gap_before:.4g}, "
                     f"names {named}.")
    lines.append("")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "gap")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-rows", type=int, default=None, help="use only the first rows of each log")
    ap.add_argument("--max-steps", type=int, default=20,
                    help="most effects per run (default 20: run until nothing passes the test)")
    args = ap.parse_args()
    if not DATA.is_dir():
        sys.exit(f"real data not found at {DATA}")
    args.out.mkdir(parents=True, exist_ok=True)
    text = []
    for i in (1, 2):
        name = f"adis16405_static_{i}"
        rep, again, dt = run_one(name, DATA / "logs" / f"{name}.csv.gz", args.out, args.seed,
                                 max_rows=args.max_rows, max_steps=args.max_steps)
        text.append(markdown(name, rep, again, dt))
        if i == 1:
            save_png(gap_figure(rep), args.out / "log1_gap.png")
            for ch in ("gyro_z", "accel_x"):
                save_png(adev_figure(rep, ch), args.out / f"log1_{ch}_adev.png")
                save_png(psd_figure(rep, ch), args.out / f"log1_{ch}_psd.png")
    rep, again, dt = run_one("adis16405_adev_table", DATA / "adev" / "adis16405.csv", args.out,
                             args.seed, rate_hz=100.0, samples=1_000_000, max_steps=args.max_steps)
    text.append(markdown("adis16405 Allan table (log 1)", rep, again, dt))
    summary = "\n".join(text)
    atomic_write_text(args.out / "summary.md", summary)
    print(summary)


if __name__ == "__main__":
    main()
