"""What the seed-paper example scripts share: the package importable from a checkout (this
folder's parent goes first on ``sys.path``) and their ``--trials`` / ``--seed`` arguments."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def seed_run_parser(doc: str, trials: int, seed: int) -> argparse.ArgumentParser:
    """Parser described by the first line of ``doc`` with ``--trials`` and ``--seed`` defaults."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--trials", type=int, default=trials, help=f"Monte Carlo trials (default {trials})")
    ap.add_argument("--seed", type=int, default=seed, help=f"random seed (default {seed})")
    return ap
