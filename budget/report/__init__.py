"""Reports: one self-contained HTML file with the scenario, bounds, check, Monte Carlo P(pass)
with intervals, the check-vs-MC comparison, figures and provenance (``sar-budget report``, the
dashboard's "Download the report").

* :func:`build_report` → :class:`Report` (``html()``, ``save(path)``, ``to_dict()``, ``to_frame()``,
  ``summary()``)
* :func:`check_vs_mc` — does the analytic verdict agree with the Monte Carlo, and why not
  (:func:`check_vs_mc_text`: the same in one line)
"""

from .content import (MC_PASS_TARGET, Report, build_report, check_vs_mc, check_vs_mc_text,
                      mc_dict)

__all__ = ["MC_PASS_TARGET", "Report", "build_report", "check_vs_mc", "check_vs_mc_text", "mc_dict"]
