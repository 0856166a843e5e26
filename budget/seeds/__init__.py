"""Seed-paper applications built on the library (``examples/`` runs them at full size).

* :mod:`.master_slave` — seed 001: master–slave transfer, error within an imaging period;
* :mod:`.prf_slaving` — seed 001 (4): PRF slaved to the aided forward speed;
* :mod:`.transfer_alignment` — seed 002: distributed POS, KF vs RTS with flexure;
* :mod:`.large_misalignment` — seed 002: large heading misalignment, DDF2-RTS vs KF-RTS;
* :mod:`.sonar_fusion` — seed 003: INS + GPS + DVL fusion for synthetic-aperture sonar.

These modules sit above the aiding library, the presets and the SAR point-target helper and
import from them; nothing in the library imports them.
"""
