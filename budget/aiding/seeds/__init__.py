"""Seed-paper cases of issue 9, as library functions (examples/ runs them at full size)."""
