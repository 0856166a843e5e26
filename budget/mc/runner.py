"""Run the trial chain over many trials: serial, local processes, or a Dask cluster.

Determinism: trials are cut into fixed chunks of ``options.chunk_trials`` (a multiple of the
motion engine's 64-trial random-stream block); trial i always draws from streams keyed by
(seed, i). Chunks are aggregated in chunk order whatever finishes first, so the same seed gives
the same numbers for any worker count or backend.

Dask (``dask.distributed``) is the optional distributed backend: it is pure Python, installs
from PyPI, runs the same code on a ``LocalCluster`` for testing and on a real cluster unchanged,
and needs no separate object store or ray head node. Ray would do the job too but brings a much
heavier runtime for what is an embarrassingly parallel map of chunks.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from concurrent.futures import ProcessPoolExecutor
from functools import lru_cache
from typing import Callable

from ..catalog.fill import resolve_unspecified
from ..errors import InputError
from ..scenario import Scenario
from .aggregate import Aggregate
from .chain import ChainSetup, run_chunk
from .options import McOptions
from .result import McResult

ProgressFn = Callable[[int, int], None]


@lru_cache(maxsize=8)
def _cached_setup(scenario_json: str, options_json: str) -> ChainSetup:
    return ChainSetup.build(Scenario.model_validate_json(scenario_json),
                            McOptions.model_validate_json(options_json))


def _chunk_task(scenario_json: str, options_json: str, model, seed: int, start: int, stop: int,
                keep_detail: bool):
    """Top-level (picklable) task: one chunk, setup cached per process."""
    return run_chunk(_cached_setup(scenario_json, options_json), model, seed, start, stop, keep_detail)


def model_label(model) -> str:
    return getattr(model, "part_id", None) or getattr(model, "model", None) or "noise model"


def run_mc(scenario: Scenario, model, trials: int, seed: int, *, options: McOptions | None = None,
           workers: int = 1, backend: str = "auto", client=None, progress: ProgressFn | None = None,
           cancel: threading.Event | None = None, keep_detail: bool = False) -> McResult:
    """Monte Carlo verdict of ``model`` (catalog part or noise model) on ``scenario``.

    ``backend``: ``serial``, ``processes`` (local, ``workers`` processes), ``dask`` (needs
    ``client``: a ``dask.distributed.Client``) or ``auto`` (serial for one worker, else
    processes). ``progress(done, total)`` is called after each chunk; setting ``cancel`` stops
    the run after the chunks in flight and returns the trials completed (``cancelled=True``).
    ``keep_detail`` keeps images and phase histories of the worst trials (for inspection).
    """
    options = options or McOptions()
    if not isinstance(trials, int) or trials < 1:
        raise InputError("trials must be a positive integer", field="trials", value=trials)
    if not isinstance(seed, int) or seed < 0:
        raise InputError("seed must be a non-negative integer", field="seed", value=seed)
    if workers < 1:
        raise InputError("workers must be ≥ 1", field="workers", value=workers)
    if backend == "auto":
        backend = "serial" if workers == 1 else "processes"
    if backend not in ("serial", "processes", "dask"):
        raise InputError("unknown backend", field="backend", value=backend,
                         expected="serial, processes or dask")
    if backend == "dask" and client is None:
        raise InputError("the dask backend needs a dask.distributed Client", field="client")
    # No silent zeros: empty datasheet terms are filled, refused or stated zero (budget.catalog.fill)
    resolution = resolve_unspecified(model, options.unspecified)
    model = resolution.model
    scen_json, opt_json = scenario.model_dump_json(), options.model_dump_json()
    _cached_setup(scen_json, opt_json)  # fail early (e.g. a scenario beyond the simulation limits)
    step = options.chunk_trials
    chunks = [(s, min(s + step, trials)) for s in range(0, trials, step)]
    agg = Aggregate(keep_worst=options.keep_worst, keep_trial_metrics=options.keep_trial_metrics)
    cancelled = False

    def consume(outcomes, done):
        agg.add(outcomes)
        if progress:
            progress(done, trials)

    if backend == "serial":
        for s, e in chunks:
            if cancel is not None and cancel.is_set():
                cancelled = True
                break
            consume(_chunk_task(scen_json, opt_json, model, seed, s, e, keep_detail), e)
    else:
        if backend == "processes":
            pool = ProcessPoolExecutor(max_workers=workers)
            submit = lambda s, e: pool.submit(_chunk_task, scen_json, opt_json, model, seed, s, e, keep_detail)  # noqa: E731
            result_of = lambda f: f.result()  # noqa: E731
        else:
            pool = None
            submit = lambda s, e: client.submit(_chunk_task, scen_json, opt_json, model, seed, s, e,  # noqa: E731
                                                keep_detail, pure=False)
            result_of = lambda f: f.result()  # noqa: E731
        window = max(2, 2 * (workers if backend == "processes" else max(workers, 2)))
        pending: deque = deque()
        todo = deque(chunks)
        try:
            while todo or pending:
                while todo and len(pending) < window and not cancelled:
                    if cancel is not None and cancel.is_set():
                        cancelled = True
                        break
                    s, e = todo.popleft()
                    pending.append((e, submit(s, e)))
                if not pending:
                    break
                e, fut = pending.popleft()  # in chunk order: deterministic aggregation
                consume(result_of(fut), e)
                if cancel is not None and cancel.is_set():
                    cancelled = True
                    todo.clear()
        finally:
            for _, f in pending:
                f.cancel()
            if pool is not None:
                pool.shutdown(wait=True, cancel_futures=True)
    extra = {"prefilter": options.prefilter} if options.prefilter != "none" else {}
    extra["unspecified_terms"] = resolution.to_dict()
    return McResult(scenario_name=scenario.name, model_label=model_label(model), seed=seed,
                    tc_s=scenario.tc_s, agg=agg, cancelled=cancelled or agg.n < trials, extra=extra,
                    options=options, scenario=scenario,
                    judged_on=_cached_setup(scen_json, opt_json).describe())


def required_chunks(trials: int, options: McOptions) -> int:
    return math.ceil(trials / options.chunk_trials)
