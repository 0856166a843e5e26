"""Run the trial chain over many trials: serial, local processes, or a Dask cluster.

Determinism: trials are cut into fixed chunks of ``options.chunk_trials`` (a multiple of the
motion engine's 64-trial random-stream block); trial i always draws from streams keyed by
(seed, i), and is imaged in the formation batch of its index (:data:`~budget.mc.chain.FORMATION_BATCH`).
Work is handed out in chunks, or in pieces of chunks when there are fewer than two chunks per
worker (:func:`work_units`), and aggregated in trial order whatever finishes first, so the same
seed gives the same numbers for any worker count or backend.

Parallel speed: each worker process builds (or, forked, inherits) the setup once, runs with one
BLAS thread (:func:`single_threaded_blas`), and returns only the small per-trial outcomes; the
parent only aggregates them.

Dask (``dask.distributed``) is the optional distributed backend: it is pure Python, installs
from PyPI, runs the same code on a ``LocalCluster`` for testing and on a real cluster unchanged,
and needs no separate object store or ray head node. Ray would do the job too but brings a much
heavier runtime for what is an embarrassingly parallel map of chunks.
"""

from __future__ import annotations

import math
import os
import threading
from collections import deque
from collections.abc import Mapping
from concurrent.futures import ProcessPoolExecutor
import warnings
from functools import lru_cache
from typing import Callable

from threadpoolctl import threadpool_limits

from ..aiding_spec import AidingPlan
from ..catalog.fill import resolve_unspecified
from ..errors import InputError, whole_number
from ..motion.engine import engine_notes
from ..scenario import Scenario
from .aggregate import Aggregate
from .chain import FORMATION_BATCH, ChainSetup, chain_plan, run_chunk, scene_reference
from .defocus import RoomChoice, defocus_room
from .notes import run_notes
from .options import McOptions
from .result import McResult

ProgressFn = Callable[[int, int], None]


def single_threaded_blas():
    """Context manager: BLAS on one thread inside the block, restored after (threadpoolctl finds
    every BLAS loaded in the process — numpy's and scipy's wheels each ship their own OpenBLAS).
    The chain's matrix products are small (a few 10⁵ multiply-adds): BLAS threads only add
    hand-over latency, and with one process per core they oversubscribe the machine (measured: a
    64-trial chunk took 6× the CPU time with OpenBLAS's default threads on a loaded 2-core
    machine)."""
    return threadpool_limits(limits=1, user_api="blas")


@lru_cache(maxsize=8)
def _cached_setup(scenario_json: str, options_json: str) -> ChainSetup:
    with warnings.catch_warnings():  # the scenario's notes were shown when the caller built it
        warnings.simplefilter("ignore", UserWarning)
        scenario = Scenario.model_validate_json(scenario_json)
    setup = ChainSetup.build(scenario, McOptions.model_validate_json(options_json))
    chain_plan(setup)  # built here, so that forked workers inherit it with the setup
    scene_reference(setup)  # likewise the perfect-IMU reference of a cluttered or noisy scene
    return setup


def _chunk_task(scenario_json: str, options_json: str, model, seed: int, start: int, stop: int,
                keep_detail: bool, only: tuple[int, int] | None = None):
    """Top-level (picklable) task: one chunk (or the trials ``only`` of it), setup cached per
    process, BLAS on one thread."""
    with single_threaded_blas():
        return run_chunk(_cached_setup(scenario_json, options_json), model, seed, start, stop, keep_detail, only)


def work_units(trials: int, chunk_trials: int, workers: int) -> list[tuple[int, int, int, int]]:
    """(chunk start, chunk stop, first trial, stop trial) of each task. Chunks are the unit of
    the random streams; when there are fewer than two chunks per worker (e.g. the default 64
    trials on 2 workers) each chunk is shared out in pieces of whole formation batches, so that
    every worker has work. Which trials a task images never changes a number."""
    chunks = [(s, min(s + chunk_trials, trials)) for s in range(0, trials, chunk_trials)]
    pieces = 1 if workers <= 1 else max(1, math.ceil(2 * workers / len(chunks)))
    out = []
    for s, e in chunks:
        size = max(FORMATION_BATCH, math.ceil((e - s) / pieces / FORMATION_BATCH) * FORMATION_BATCH)
        out.extend((s, e, lo, min(lo + size, e)) for lo in range(s, e, size))
    return out


#: Most local worker processes a run starts (backend ``processes``): each is a full Python with
#: the simulation's arrays, and the results do not depend on the count (``--workers 100000``
#: tried to fork as many processes before).
MAX_LOCAL_WORKERS = 64


#: Most trials one run takes. At 10⁶ the 95 % Wilson interval is ±0.001 wide at most, and the
#: chain (≈ 20–40 trials/s on two cores) needs about 10 h; more only fills memory — the run's
#: task list, and the per-trial metric lists unless ``keep_trial_metrics`` is off (10¹² trials
#: exhausted 22 GB before the first trial).
MAX_TRIALS = 1_000_000


def check_run_counts(trials, seed, workers=1, backend: str = "auto") -> tuple[int, int, int]:
    """``trials``, ``seed`` and ``workers`` of a run, checked (:func:`whole_number`): trials at
    most :data:`MAX_TRIALS`; local processes (backend ``auto`` or ``processes``) at most
    :data:`MAX_LOCAL_WORKERS`."""
    checked = (whole_number("trials", trials, 1, "a whole number of trials ≥ 1, e.g. 64"),
               whole_number("seed", seed, 0, "a whole number ≥ 0, e.g. 1"),
               whole_number("workers", workers, 1, "a whole number of processes ≥ 1"))
    if checked[0] > MAX_TRIALS:
        raise InputError(f"more trials than one run takes ({MAX_TRIALS:,}; the chain runs ≈ 20–40 trials/s "
                         "on two cores, and at 10⁶ trials P(pass) is known to ±0.001)", field="trials",
                         value=checked[0], expected=f"1 … {MAX_TRIALS:,} (for more, runs with other seeds: "
                         "their trials are independent)")
    if backend in ("auto", "processes") and checked[2] > MAX_LOCAL_WORKERS:
        raise InputError(f"more local worker processes than {MAX_LOCAL_WORKERS}", field="workers",
                         value=checked[2], expected=f"1 … {MAX_LOCAL_WORKERS} (this machine has "
                         f"{os.cpu_count() or 1} CPUs; the results do not depend on the count)")
    return checked


def check_options(options) -> McOptions:
    """``options`` as :class:`McOptions`: None → the defaults, a mapping → :meth:`McOptions.build`
    (errors name the field), anything else → :class:`InputError`."""
    if options is None:
        return McOptions()
    if isinstance(options, McOptions):
        return options
    if isinstance(options, Mapping):
        return McOptions.build(**dict(options))
    raise InputError(f"cannot use a {type(options).__name__} as Monte Carlo options", field="options",
                     expected="a budget.mc.McOptions, a mapping of its fields, or None")


def resolve_defocus_room(scenario: Scenario, options: McOptions, model) -> tuple[McOptions, RoomChoice | None]:
    """``options`` with a ``defocus_room_cells`` of "auto" replaced by the room that holds the
    defocus of ``model``'s errors (:func:`budget.mc.defocus.defocus_room`), and that choice;
    options with a room set are returned as they are, with None."""
    if options.defocus_room_cells != "auto":
        return options, None
    choice = defocus_room(scenario, model, disturbance=options.platform_motion.disturbance_for(scenario),
                          window=options.window_for(scenario))
    return options.model_copy(update={"defocus_room_cells": choice.cells}), choice


def model_label(model) -> str:
    return getattr(model, "part_id", None) or getattr(model, "model", None) or "noise model"


def model_spec(model) -> dict | None:
    """The values of the model simulated, JSON-ready (datasheet units, as a catalog row or a
    noise-model file writes them; unspecified terms as filled), so that a verdict says which
    row it judged — a user's row under a shipped part's id included. None for a model given in
    SI (``NoiseModelSI``: its label is all a result names)."""
    if hasattr(model, "to_dict") and hasattr(model, "effects"):  # NoiseModel: its effects too
        return model.to_dict()
    if hasattr(model, "model_dump"):
        return model.model_dump(mode="json")
    return None


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
    options = check_options(options)
    trials, seed, workers = check_run_counts(trials, seed, workers, backend)
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
    options, room = resolve_defocus_room(scenario, options, model)
    scen_json, opt_json = scenario.model_dump_json(), options.model_dump_json()
    _cached_setup(scen_json, opt_json)  # fail early (e.g. a scenario beyond the simulation limits)
    # the motion engine's notes, once per run: the engine runs for the defocus pilot and for every
    # chunk (in every worker), each of which warned them again (two or more identical lines)
    for note in engine_notes(scenario, AidingPlan.from_scenario(scenario)):
        warnings.warn(note, UserWarning, stacklevel=2)
    units = work_units(trials, options.chunk_trials, 1 if backend == "serial" else workers)
    agg = Aggregate(keep_worst=options.keep_worst, keep_trial_metrics=options.keep_trial_metrics)
    cancelled = False

    def consume(outcomes, done):
        agg.add(outcomes)
        if progress:
            progress(done, trials)

    if backend == "serial":
        for s, e, _, _ in units:
            if cancel is not None and cancel.is_set():
                cancelled = True
                break
            consume(_chunk_task(scen_json, opt_json, model, seed, s, e, keep_detail), e)
    else:
        if backend == "processes":
            pool = ProcessPoolExecutor(max_workers=min(workers, len(units)))  # no idle processes
            submit = lambda u: pool.submit(_chunk_task, scen_json, opt_json, model, seed, u[0], u[1],  # noqa: E731
                                           keep_detail, (u[2], u[3]))
            result_of = lambda f: f.result()  # noqa: E731
        else:
            pool = None
            submit = lambda u: client.submit(_chunk_task, scen_json, opt_json, model, seed, u[0], u[1],  # noqa: E731
                                             keep_detail, (u[2], u[3]), pure=False)
            result_of = lambda f: f.result()  # noqa: E731
        window = max(2, 2 * (workers if backend == "processes" else max(workers, 2)))
        pending: deque = deque()
        todo = deque(units)
        try:
            while todo or pending:
                while todo and len(pending) < window and not cancelled:
                    if cancel is not None and cancel.is_set():
                        cancelled = True
                        break
                    u = todo.popleft()
                    pending.append((u[3], submit(u)))
                if not pending:
                    break
                e, fut = pending.popleft()  # in trial order: deterministic aggregation
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
    judged = _cached_setup(scen_json, opt_json).describe()
    judged.update(run_notes(scenario, options, model))
    if room is not None:
        judged["defocus_room"] = room.note()
        extra["defocus_room"] = room.to_dict()
    return McResult(scenario_name=scenario.name, model_label=model_label(model), seed=seed,
                    tc_s=scenario.tc_s, agg=agg, cancelled=cancelled or agg.n < trials, extra=extra,
                    options=options, scenario=scenario, judged_on=judged, model_spec=model_spec(model))
