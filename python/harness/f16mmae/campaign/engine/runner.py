"""The loop every campaign kind shares: fly the planned runs that are not stored yet.

A campaign plans its runs as specs, each a plain dict with a unique ``run_key`` (a hash of
everything that shapes the run, ``store.run_key``). :func:`execute` submits the specs whose
key is not in the results store yet to a ``concurrent.futures.Executor`` (``run(spec)`` must
be a picklable module-level function returning the run's record), appends each record as it
finishes -- so an interrupted campaign keeps its finished runs and the same command resumes
-- and advances a progress bar. A run that raises stops the campaign with a
``CampaignError`` naming the run (``describe(spec)``) and where the finished runs are.
It returns the stored records of this plan only, one per run key, and the timing.

Tasks: each task the executor receives flies a chunk of consecutive specs (``chunks``:
guided, a quarter of each worker's share of the runs left, 1 to ``CHUNK_MAX`` runs) and
returns their records, so a pool pays its per-task messages once per chunk, not once per run,
while the last tasks stay single runs that keep both workers busy to the end.  In process
(``--workers 1``) the tasks are flown one after another, each stored before the next
(:func:`completed`).  A chunk
returns the records flown before a failing run along with its error, so they are stored too.
Within ``shared_flights.sharing()`` (one command flying several campaigns), a spec another
campaign of the command already flew with the same run function is not flown again: its record
is stored as flown (``Execution.shared`` counts them).

Code identity: the parent stamps each record it stores with ``code`` (``identity.code_identity()``:
git commit and dirty flag or source hash, JSBSim and LCM versions).  Before flying, stored
records of this plan whose identity differs from the running code's stop the campaign with a
``CampaignError`` naming both identities (resuming would mix results of different code),
unless ``allow_mixed``.
"""
from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from ...banks import load_bank
from . import identity, shared_flights
from .config import CampaignError
from .executor import InlineExecutor, default_workers
from .progress import Progress
from .store import ResultsStore, write_summary


#: The most runs one task flies (see the module docstring).
CHUNK_MAX = 16


def chunks(specs: Sequence[dict], workers: int) -> list[list[dict]]:
    """``specs`` in order, cut into tasks: each ``(runs left) // (4 workers)`` runs, at least 1
    and at most ``CHUNK_MAX``."""
    out, i = [], 0
    while i < len(specs):
        k = max(1, min(CHUNK_MAX, (len(specs) - i) // (4 * max(1, workers))))
        out.append(list(specs[i:i + k]))
        i += k
    return out


def run_chunk(run: Callable[[dict], dict], specs: list[dict]) -> tuple[list[dict], tuple[int, BaseException] | None]:
    """Fly ``specs`` in order (in a worker): their records, and (index, error) of the first run
    that raised (the runs after it are not flown), or None."""
    records = []
    for i, spec in enumerate(specs):
        try:
            records.append(run(spec))
        except Exception as exc:  # noqa: BLE001 -- delivered to the parent with its run
            return records, (i, exc)
    return records, None


def executor_workers(executor: Executor) -> int:
    """How many runs ``executor`` flies at once: a process pool's worker count, 1 inline, else
    this machine's cores (a cluster's share is not known here)."""
    if isinstance(executor, InlineExecutor):
        return 1
    return int(getattr(executor, "_max_workers", 0) or default_workers())


def completed(executor: Executor, run: Callable[[dict], dict], tasks: list[list[dict]]) -> Iterator[tuple[list[dict], Future]]:
    """(task, its future) of each task as it finishes. In process (``InlineExecutor``) one task is
    flown at a time, so each is stored before the next is flown: a long ``--workers 1`` campaign
    shows its progress and keeps what it flew when it is stopped. Any other executor gets every
    task at once."""
    if isinstance(executor, InlineExecutor):
        for task in tasks:
            yield task, executor.submit(run_chunk, run, task)
        return
    futures = {executor.submit(run_chunk, run, task): task for task in tasks}
    for fut in as_completed(futures):
        yield futures[fut], fut


@dataclass
class Execution:
    records: list[dict]            # the stored records of the plan, one per run key
    executed_records: list[dict]   # those flown by this call
    resumed: int                   # runs found in the store
    wall_s: float
    shared: int = 0                # of the executed, runs another campaign of this command flew

    def timing(self, executor_label: str = "") -> dict:
        """Wall time, runs executed / resumed, and the summed per-run truth / estimator time."""
        out = {"wall_s": round(self.wall_s, 3), "runs_executed": len(self.executed_records),
               "runs_resumed": self.resumed, "executor": executor_label}
        if self.shared:
            out["runs_shared"] = self.shared
        for k in ("wall_s", "truth_s", "estimator_s"):
            out[f"run_{k}_sum"] = round(sum(r["timing"].get(k, 0.0) for r in self.executed_records), 3)
        return out

    def finish(self, out: Path, summary: dict, executor_label: str = "", **timing) -> "CampaignOutcome":
        """Stamp ``summary`` with this execution's timing (plus the ``timing`` fields given),
        write it to ``out/summary.json`` and return the campaign's outcome."""
        summary["timing"] = {**self.timing(executor_label), **timing}
        path = write_summary(Path(out) / "summary.json", summary)
        return CampaignOutcome(summary, path, len(self.executed_records), self.resumed, self.records)


def execute(specs: Sequence[dict], store: ResultsStore, executor: Executor, run: Callable[[dict], dict], *,
            describe: Callable[[dict], str], progress_label: str = "runs", show_progress: bool = True,
            after_each: Callable[[dict], None] | None = None, allow_mixed: bool = False,
            progress_note: Callable[[int], str] | None = None) -> Execution:
    """Fly the specs not yet in ``store``; see the module docstring. ``after_each(spec)`` is
    called in this process after each record is stored (e.g. per-group progress notes);
    ``progress_note(done)`` adds to the progress bar (``Progress(note=...)``)."""
    code = identity.code_identity()
    planned = {s["run_key"] for s in specs}
    stored_records = [r for r in store.records() if r["run_key"] in planned]
    if not allow_mixed:
        check_identity(stored_records, code, store)
    stored = {r["run_key"] for r in stored_records}
    todo = [s for s in specs if s["run_key"] not in stored]
    t0 = time.perf_counter()
    bar = Progress(len(specs), progress_label, already_done=len(specs) - len(todo), enabled=show_progress,
                   note=progress_note)
    flown: list[dict] = []

    def keep(spec: dict, record: dict) -> None:
        stamped = {**record, "code": code}
        store.append(stamped)
        flown.append(stamped)
        bar.advance()
        if after_each is not None:
            after_each(spec)

    try:
        to_fly = []
        for spec in todo:  # flown already by another campaign of this command (shared_flights)
            record = shared_flights.take(run, spec)
            if record is None:
                to_fly.append(spec)
            else:
                keep(spec, record)
        shared = len(todo) - len(to_fly)
        for chunk, fut in completed(executor, run, chunks(to_fly, executor_workers(executor))):
            try:
                records, failed = fut.result()
            except CampaignError:
                raise
            except Exception as exc:  # the task itself failed (e.g. its worker died)
                raise CampaignError(
                    f"the task flying {describe(chunk[0])}" + (f" and {len(chunk) - 1} more" if len(chunk) > 1 else "")
                    + f" failed: {type(exc).__name__}: {exc}; the {bar.done} runs finished so far are "
                    f"stored in {store.path}") from exc
            for spec, record in zip(chunk, records):
                keep(spec, record)
                shared_flights.offer(run, spec, record)
            if failed is not None:
                index, exc = failed
                if isinstance(exc, CampaignError):
                    raise exc
                # a run that cannot fly: say which, keep what is stored
                raise CampaignError(
                    f"{describe(chunk[index])} failed: {type(exc).__name__}: {exc}; the {bar.done} runs "
                    f"finished so far are stored in {store.path}") from exc
    finally:
        bar.close()
        store.close()
    wall_s = time.perf_counter() - t0
    by_key = {r["run_key"]: r for r in (*stored_records, *flown)}  # a key stored twice counts once
    executed = {s["run_key"] for s in todo}
    records = list(by_key.values())
    return Execution(records, [r for r in records if r["run_key"] in executed], len(specs) - len(todo), wall_s,
                     shared)


def check_identity(stored: Sequence[dict], code: dict, store: ResultsStore) -> None:
    """CampaignError when a stored record of the plan was flown by other code than ``code``."""
    other = [r for r in stored if not identity.same(r.get("code"), code)]
    if other:
        raise CampaignError(
            f"{store.path} holds {len(other)} run(s) of this campaign flown by "
            f"{identity.describe(other[0].get('code'))}, but this is {identity.describe(code)}: "
            f"resuming would mix results of different code. Start fresh with another --out "
            f"directory (or move {store.path.name} away), or pass --allow-mixed to keep the stored "
            f"runs and fly the rest with this code")


@dataclass
class CampaignOutcome:
    """What a campaign run returns: its summary (also written to ``summary_path``), how many
    runs it flew and how many it found stored, and the records of its plan."""
    summary: dict
    summary_path: Path
    executed: int
    resumed: int
    records: list[dict] = field(default_factory=list)


def planned_bank(spec: dict):
    """The ModelBank a spec names (``spec["bank"]``), checked against the hash it was planned
    with: CampaignError when this process would fly another bank."""
    _, _, bank = load_bank(spec["bank"])
    if bank.content_hash != spec["bank_hash"]:
        raise CampaignError(
            f"bank {spec['bank']} on this worker has hash {bank.content_hash}, the campaign "
            f"planned {spec['bank_hash']}: the file changed, or workers run another install"
        )
    return bank
