"""Render a job list on a Ray cluster: jobs (a .jsonl file or dicts, as `chiaro batch`
reads them) flow in; each job's folder under `output` (written by `chiaro.render_jobs`,
atomically) and a summary dict flow out.

    import chiaro.ray
    summary = chiaro.ray.render_dataset("jobs.jsonl", "out/", gpus_per_worker=1)

Ray is an optional dependency: `pip install "chiaro[ray]"`. Two ways in:

- `render_dataset` starts one Ray actor per worker, each holding one `chiaro.Renderer`
  made once on the GPU Ray gave it, and hands out jobs as workers become idle.
- `ChiaroRenderStage` is a callable class for Ray Data's `map_batches`, for pipelines that
  already hold their jobs as a dataset with a "job" column of JSON strings.

Chiaro does not schedule: Ray places the workers, restarts them and retries their tasks.
Jobs are idempotent and written atomically, so a job run twice (a worker died after
writing it, a rerun of the whole list) leaves one folder, and a rerun skips what is done.

`render_dataset` returns a `DatasetSummary`, the stage a `StageStatuses` (TypedDicts for
type checkers; plain dicts at run time). Ray itself is untyped here: its objects are Any.

See docs/scale.md for Ray, Ray Data, Slurm and Kubernetes.
"""

from __future__ import annotations

import collections
import json
import math
import os
import unicodedata
from typing import TYPE_CHECKING, Any, Deque, Dict, Iterable, List, Mapping, Optional, Tuple, TypedDict, Union

from ._types import DeviceArg, JobsSummary, PathArg, RendererDevice, SettingsArg

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["ChiaroRenderStage", "DatasetSummary", "StageStatuses", "render_dataset"]

_INSTALL_HINT = 'chiaro.ray needs Ray: pip install "chiaro[ray]" (or pip install "ray>=2.9")'

Job = Dict[str, Any]
"""A job, as `chiaro batch` reads it (docs/batch.md): {"id": ..., "scene": ..., ...}."""
_Entry = Tuple[int, Job]
"""A job and its line: the 1-based line of a .jsonl file, or its position in a list from 1."""


class DatasetSummary(JobsSummary):
    """What `render_dataset` returns: `chiaro.JobsSummary`'s counts over every worker, and
    what Ray did."""

    workers: int
    """Ray actors started, each with one Renderer."""
    restarts: int
    """Worker restarts seen (a worker answering from a new process)."""
    retried: int
    """Tasks the driver gave to another worker after theirs died for good."""


class StageStatuses(TypedDict):
    """What a `ChiaroRenderStage` returns for a batch: columns of one row per job, in the
    batch's order, each a numpy array of Python strings (dtype object)."""

    id: NDArray[np.object_]
    """The job's id."""
    status: NDArray[np.object_]
    """The job's status: "done", "skipped" (its folder was current) or "failed"."""
    error: NDArray[np.object_]
    """The failure's message; "" unless the job failed."""


class _Task(TypedDict):
    """Jobs handed to a worker at once, and how often the driver gave them out again."""

    jobs: List[_Entry]
    resubmits: int


def _import_ray() -> Any:
    """The ray module (untyped: Any), or ImportError saying how to install it."""
    try:
        import ray
    except ImportError as e:
        raise ImportError("%s (%s)" % (_INSTALL_HINT, e)) from e
    return ray


def _worker_device(device: DeviceArg) -> DeviceArg:
    """The device a worker renders on: `device` when given, else "cuda:0" when Ray gave
    the worker GPUs (Ray sets CUDA_VISIBLE_DEVICES to them, so the first one is cuda:0,
    matched to its Vulkan adapter by PCI bus id), else "auto" (which CHIARO_DEVICE sets)."""
    if device is not None:
        return device
    ray = _import_ray()
    return "cuda:0" if ray.is_initialized() and ray.get_gpu_ids() else "auto"


# As `chiaro batch` checks ids (docs/batch.md): an id names the job's folder.
MAX_ID_BYTES = 200
ERROR_SUFFIX = ".error.json"


def _check_id(job_id: object, where: str) -> None:
    """ValueError, naming `where`, unless `job_id` can name a job's folder."""
    if not isinstance(job_id, str):
        raise ValueError("%s: \"id\" must be a string, not %r" % (where, job_id))
    problem = None
    if not job_id:
        problem = "is empty"
    elif len(job_id.encode("utf-8", "surrogatepass")) > MAX_ID_BYTES:
        problem = "is longer than %d bytes" % MAX_ID_BYTES
    elif any(c in "/\\" or unicodedata.category(c) == "Cc" for c in job_id):
        problem = "holds a slash or a control character; an id is a folder name"
    elif job_id.startswith("."):
        problem = "starts with '.'; those names are the batch's temporary folders"
    elif job_id.endswith(ERROR_SUFFIX):
        problem = "ends with %r, the name of a failed job's report" % ERROR_SUFFIX
    if problem:
        raise ValueError("%s: id %r %s" % (where, job_id, problem))


def _load_jobs(jobs: Union[str, bytes, os.PathLike[str], os.PathLike[bytes], Iterable[Any]]) -> List[_Entry]:
    """The jobs as a list of (line, dict), ids checked as `chiaro batch` checks them
    (strings naming a folder, each used once); line is the 1-based line of a .jsonl file,
    or the position in a list from 1, as `render_jobs` numbers a list. A path is read as
    `chiaro batch` reads it: one JSON object a line, blank lines ignored but counted.
    ValueError names the line (or the position in the list) and the problem."""
    if isinstance(jobs, (str, bytes, os.PathLike)):
        path = os.fsdecode(jobs)
        with open(path, encoding="utf-8-sig", newline="") as f:
            text = f.read()
        entries: List[Tuple[str, int, Any]] = []
        for number, line in enumerate(text.split("\n"), 1):
            if not line.strip():
                continue
            where = "%s:%d" % (path, number)
            try:
                job = json.loads(line)
            except ValueError as e:
                raise ValueError("%s: not JSON: %s" % (where, e)) from None
            entries.append((where, number, job))
    elif isinstance(jobs, dict):
        raise TypeError("jobs: expected a .jsonl path or an iterable of job dicts, not one dict")
    else:
        entries = [("jobs[%d]" % i, i + 1, job) for i, job in enumerate(jobs)]
    first_seen: Dict[str, str] = {}
    out: List[_Entry] = []
    for where, number, job in entries:
        if not isinstance(job, dict):
            raise ValueError("%s: a job is a JSON object, not %s" % (where, type(job).__name__))
        if "id" not in job:
            raise ValueError("%s: no \"id\": every job needs a string id, the name of its folder" % where)
        job_id = job["id"]
        _check_id(job_id, where)
        if job_id in first_seen:
            first = first_seen[job_id]
            raise ValueError("%s: id %r is already the id of %s; ids must be unique" % (where, job_id, first))
        first_seen[job_id] = where
        out.append((number, job))
    return out


def _chunks(entries: List[_Entry], size: int) -> List[List[_Entry]]:
    """(line, job) pairs grouped by scene (in the order scenes first appear, keeping the
    list's order within a scene), then cut into chunks of at most `size` jobs of one
    scene: a worker loads a chunk's scene once."""
    by_scene: Dict[str, List[_Entry]] = collections.OrderedDict()
    for entry in entries:
        by_scene.setdefault(json.dumps(entry[1].get("scene"), sort_keys=True), []).append(entry)
    chunks: List[List[_Entry]] = []
    for group in by_scene.values():
        chunks.extend(group[i:i + size] for i in range(0, len(group), size))
    return chunks


class _Worker:
    """A Ray actor's body: one Renderer, made once, for every job the actor is given."""

    def __init__(self, output: str, settings: SettingsArg, device: DeviceArg) -> None:
        import chiaro

        self._output = output
        self._renderer = chiaro.Renderer(device=_worker_device(device), settings=settings)

    def ready(self) -> Tuple[int, RendererDevice]:
        """The process id (a restarted worker has a new one) and the device in use."""
        return os.getpid(), self._renderer.device

    def render(self, jobs: List[Job]) -> Tuple[int, JobsSummary]:
        """Renders `jobs` (dicts) into the output folder; returns (pid, render_jobs' summary)."""
        import chiaro

        return os.getpid(), chiaro.render_jobs(jobs, self._output, renderer=self._renderer)


def _write_error(output: str, line: int, job: Job, message: str) -> None:
    """DIR/<id>.error.json, with the keys `chiaro batch` writes, for a job no worker could
    finish (it kept ending its worker), written whole where the driver sees the output
    folder; where it does not, only the summary holds the message."""
    import chiaro

    if not os.path.isdir(output):
        return
    report = {"id": job["id"], "line": line, "job": job, "error": message, "chiaro_version": chiaro.__version__}
    path = os.path.join(output, job["id"] + ERROR_SUFFIX)
    temp = os.path.join(output, ".%s.error-%d.tmp" % (job["id"], os.getpid()))
    try:
        with open(temp, "w", encoding="utf-8") as f:
            json.dump(report, f)
        os.replace(temp, path)
    except (OSError, TypeError, ValueError):
        try:
            os.remove(temp)
        except OSError:
            pass


def render_dataset(jobs: Union[str, bytes, os.PathLike[str], os.PathLike[bytes], Iterable[Job]], output: PathArg,
                   num_workers: Optional[int] = None, gpus_per_worker: float = 1, settings: SettingsArg = None,
                   max_retries: int = 3, *, cpus_per_worker: float = 1, jobs_per_task: int = 8,
                   device: DeviceArg = None, max_restarts: int = -1) -> DatasetSummary:
    """Renders every job of `jobs` into `output` on Ray actors and returns a summary
    (`DatasetSummary`).

    jobs: the path of a .jsonl file (one job object a line, as `chiaro batch` reads) or an
    iterable of job dicts. Ids are checked here, before anything is submitted: each a
    string that can name a folder, used once; ValueError names the line and the id.
    Everything else about a job is checked where it is rendered, as `chiaro batch` does.
    Relative scene paths are read from the workers' working directory, which is the
    driver's on a local Ray; on a cluster give absolute paths on a shared file system.
    output: the folder that receives DIR/<id>/ per job; it must be the same shared folder
    for every worker (a network file system on a cluster).
    num_workers: how many actors, each with one Renderer. Default: the cluster's GPUs
    divided by gpus_per_worker (its CPUs divided by cpus_per_worker when gpus_per_worker is
    0), at least 1; never more than there are tasks to run.
    gpus_per_worker: GPUs Ray reserves for each actor (0.5 lets two share one). A worker
    renders on the first of them, "cuda:0" once Ray has set CUDA_VISIBLE_DEVICES; more than
    1 reserves GPUs that sit idle. 0 renders with device "auto" (CHIARO_DEVICE sets it),
    lavapipe where there is no GPU.
    settings: a settings.toml path (read by each worker: give a path they can all read) or
    a dict, for every worker's Renderer; a job's own "settings" apply on top as in
    `chiaro batch`.
    max_retries: how many times a task is run again after the worker running it died
    (Ray's max_task_retries): it runs again on the restarted worker. When a worker is gone
    for good (its Renderer could not be made again, its node is gone), the driver gives its
    task to another worker, again up to max_retries times. A task of several jobs that
    still cannot finish is split, each job tried alone, so that only a job that ends every
    worker it runs on is counted failed, with a DIR/<id>.error.json where the driver sees
    the output folder (a job that fails without killing its worker is reported by
    `render_jobs` as usual and not retried: it would fail again).
    cpus_per_worker: CPUs Ray reserves for each actor (lavapipe renders with all of the
    machine's cores whatever this says).
    jobs_per_task: at most this many jobs of one scene go to a worker at once, so that it
    loads the scene once for them; it is lowered so that every worker gets work. Jobs are
    grouped by scene first. Idle workers take the next task: nothing is split in advance.
    device: the device every worker renders on, instead of the choice above.
    max_restarts: how many times Ray restarts a dead worker (-1: always, as Ray Data
    does). A worker whose process keeps crashing while it starts is restarted again and
    again; Ray's log says why.

    Ray is started locally (`ray.init()`) when it is not running yet, and left running for
    the next call; the actors are ended before this returns.

    Returns {"done": jobs rendered, "skipped": jobs found done already, "failed": jobs that
    could not be rendered, "errors": {id: message} for those, "workers": actors started,
    "restarts": worker restarts seen (a worker answering from a new process), "retried":
    tasks the driver gave to another worker}. A job that fails (a scene that will not
    load, a camera that is not there) does not stop the others; rerunning the same call
    renders only what is missing or failed. Raises ImportError without Ray, and
    RuntimeError when no worker can make its Renderer (the first worker's error).
    """
    entries = _load_jobs(jobs)
    summary: DatasetSummary = {"done": 0, "skipped": 0, "failed": 0, "errors": {}, "workers": 0, "restarts": 0,
                               "retried": 0}
    _check_counts(num_workers, gpus_per_worker, cpus_per_worker, max_retries, max_restarts, jobs_per_task)
    if not entries:
        return summary
    ray = _import_ray()
    if not ray.is_initialized():
        ray.init()
    output = os.path.abspath(os.fsdecode(output))
    os.makedirs(output, exist_ok=True)
    if isinstance(settings, (str, bytes, os.PathLike)):
        settings = os.path.abspath(os.fsdecode(settings))

    if num_workers is None:
        num_workers = _workers_the_cluster_holds(ray.cluster_resources(), gpus_per_worker, cpus_per_worker)
    num_workers = min(num_workers, len(entries))
    chunks = _chunks(entries, min(jobs_per_task, math.ceil(len(entries) / num_workers)))
    num_workers = min(num_workers, len(chunks))

    options: Dict[str, Any] = {"num_cpus": cpus_per_worker, "num_gpus": gpus_per_worker,
                               "max_restarts": max_restarts, "max_task_retries": max_retries}
    worker_class = ray.remote(_Worker)
    actors = [worker_class.options(**options).remote(output, settings, device) for _ in range(num_workers)]
    summary["workers"] = num_workers
    dispatch = _Dispatch(ray, output, summary, max_retries, chunks)
    try:
        dispatch.run(actors)
    finally:
        for actor in actors:
            ray.kill(actor)
    dispatch.fail_the_rest()
    return summary


def _check_counts(num_workers: Optional[int], gpus_per_worker: float, cpus_per_worker: float, max_retries: int,
                  max_restarts: int, jobs_per_task: int) -> None:
    if num_workers is not None:
        _check_whole("num_workers", num_workers, 1)
    if gpus_per_worker < 0 or cpus_per_worker < 0:
        raise ValueError("gpus_per_worker and cpus_per_worker cannot be negative")
    _check_whole("max_retries", max_retries, 0)
    _check_whole("max_restarts", max_restarts, -1)
    _check_whole("jobs_per_task", jobs_per_task, 1)


def _workers_the_cluster_holds(resources: Mapping[str, float], gpus_per_worker: float,
                               cpus_per_worker: float) -> int:
    """How many workers fit the cluster's GPUs (its CPUs when gpus_per_worker is 0), at least 1."""
    if gpus_per_worker > 0:
        gpus = resources.get("GPU", 0)
        if gpus < gpus_per_worker:
            raise ValueError("gpus_per_worker=%g: this Ray cluster has %g GPUs; pass gpus_per_worker=0 to "
                             "render on CPUs, or num_workers to wait for GPUs an autoscaler will add"
                             % (gpus_per_worker, gpus))
        return max(1, int(gpus // gpus_per_worker))
    cpus = resources.get("CPU", 1)
    return max(1, int(cpus // cpus_per_worker) if cpus_per_worker > 0 else int(cpus))


class _Dispatch:
    """Hands tasks to idle workers until every task is done, failed or left without a
    worker, adding what the workers report to `summary`."""

    def __init__(self, ray: Any, output: str, summary: DatasetSummary, max_retries: int,
                 chunks: List[List[_Entry]]) -> None:
        self.ray = ray
        self.output = output
        self.summary = summary
        self.max_retries = max_retries
        self.queue: Deque[_Task] = collections.deque({"jobs": chunk, "resubmits": 0} for chunk in chunks)
        # Object ref -> (actor, task), task None for a ready call: made at the start, and
        # after a failure to ask whether the worker still answers.
        self.pending: Dict[Any, Tuple[Any, Optional[_Task]]] = {}
        self.idle: List[Any] = []
        self.pids: Dict[Any, int] = {}
        self.first_error: Optional[BaseException] = None
        # Ray from 2.10 or so tells a worker gone for good (ActorDiedError) from one being
        # restarted (ActorUnavailableError); older ones raise RayActorError for both.
        self.died_type = getattr(ray.exceptions, "ActorDiedError", None)

    def run(self, actors: List[Any]) -> None:
        ray = self.ray
        self.pending = {actor.ready.remote(): (actor, None) for actor in actors}
        while self.pending or (self.queue and self.idle):
            while self.queue and self.idle:
                actor, task = self.idle.pop(), self.queue.popleft()
                self.pending[actor.render.remote([job for _, job in task["jobs"]])] = (actor, task)
            if not self.pending:
                break
            (ref,), _ = ray.wait(list(self.pending), num_returns=1)
            actor, maybe_task = self.pending.pop(ref)
            try:
                answer = ray.get(ref)
            except ray.exceptions.RayActorError as e:
                self._worker_died(actor, maybe_task, e)
                continue
            except ray.exceptions.RayTaskError as e:
                # render_jobs raised instead of reporting (an output folder it cannot write);
                # a ready call returns what it holds and raises nothing of the kind.
                assert maybe_task is not None
                if not _split(self.queue, maybe_task):
                    self.fail(maybe_task, _message(e))
                self.idle.append(actor)
                continue
            self._answered(actor, maybe_task, answer)

    def _worker_died(self, actor: Any, task: Optional[_Task], error: BaseException) -> None:
        if task is None:
            # The worker is gone for good (its Renderer could not be made, or max_restarts
            # is spent): it gets no more tasks.
            self.first_error = self.first_error or error
        elif self.died_type is not None and not isinstance(error, self.died_type):
            # The worker is being restarted, and this task has spent max_retries: it ended
            # its worker every time it ran.
            if not _split(self.queue, task):
                self.fail(task, "its worker died %d times rendering it: %s" % (self.max_retries + 1, _message(error)))
            self.idle.append(actor)
        else:
            # The worker died for good (or an older Ray cannot say): the task goes to the
            # next idle worker, and a ready call asks after this one.
            if task["resubmits"] < self.max_retries:
                task["resubmits"] += 1
                self.summary["retried"] += 1
                self.queue.appendleft(task)
            elif not _split(self.queue, task):
                times = self.max_retries + 1
                self.fail(task, "its worker died each of the %d times it was given out: %s" % (times, _message(error)))
            self.pending[actor.ready.remote()] = (actor, None)

    def _answered(self, actor: Any, task: Optional[_Task], answer: Tuple[int, JobsSummary]) -> None:
        pid = answer[0]
        if actor in self.pids and self.pids[actor] != pid:
            self.summary["restarts"] += 1
        self.pids[actor] = pid
        if task is not None:
            result = answer[1]
            self.summary["done"] += int(result.get("done", 0))
            self.summary["skipped"] += int(result.get("skipped", 0))
            self.summary["failed"] += int(result.get("failed", 0))
            self.summary["errors"].update(result.get("errors") or {})
        self.idle.append(actor)

    def fail(self, task: _Task, message: str) -> None:
        for line, job in task["jobs"]:
            self.summary["failed"] += 1
            self.summary["errors"][job["id"]] = message
            _write_error(self.output, line, job, message)

    def fail_the_rest(self) -> None:
        """Counts the tasks no worker was left to run as failed; raises RuntimeError when no
        worker ever made its Renderer."""
        if self.queue and not self.pids and self.first_error is not None:
            raise RuntimeError("no Ray worker could make a chiaro.Renderer: %s" % _message(self.first_error))
        while self.queue:
            self.fail(self.queue.popleft(), "every worker died before it could render this job")


def _check_whole(name: str, value: object, least: int) -> None:
    """ValueError, naming `name`, unless `value` is an int (not a bool) of at least `least`."""
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise ValueError("%s: expected a whole number of at least %d, not %r" % (name, least, value))


def _split(queue: Deque[_Task], task: _Task) -> bool:
    """Puts a task of several jobs back at the queue's head as one task per job, so that
    the job to blame fails alone; False for a task of one job."""
    if len(task["jobs"]) < 2:
        return False
    queue.extendleft({"jobs": [entry], "resubmits": 0} for entry in reversed(task["jobs"]))
    return True


def _message(error: BaseException) -> str:
    """The part of a Ray error worth a summary line: its cause's message where it has one,
    the exception at the end of a traceback it quotes (a worker's __init__ that raised),
    else its first line."""
    cause = getattr(error, "cause", None)
    if isinstance(cause, BaseException):
        return "%s: %s" % (type(cause).__name__, cause)
    text = str(error)
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    if not lines:
        return type(error).__name__
    return lines[-1] if "Traceback" in text or getattr(error, "actor_init_failed", False) else lines[0]


class ChiaroRenderStage:
    """A Ray Data stage: renders the jobs of a batch with one Renderer per actor.

        ds = ray.data.from_items([{"job": json.dumps(job)} for job in jobs])
        statuses = ds.map_batches(ChiaroRenderStage, compute=ray.data.ActorPoolStrategy(size=4),
                                  num_gpus=1, batch_size=16,
                                  fn_constructor_kwargs={"output": "/shared/out"})

    output: the shared folder that receives DIR/<id>/ per job. settings: a settings.toml
    path or dict for the Renderer. device: as for `render_dataset` (default: "cuda:0" when
    Ray gave the actor a GPU, else "auto").

    A batch holds a "job" column of job objects as JSON strings (or dicts). The batch's
    jobs go to one `chiaro.render_jobs` call, which keeps a scene loaded while consecutive
    jobs use it: sort rows by scene. Returns the columns "id", "status" ("done",
    "skipped" or "failed") and "error" (the message, "" unless failed), one row per job.
    A job that fails is a row with status "failed" and a DIR/<id>.error.json, not an
    exception; a batch whose worker dies is rerun by Ray Data, which restarts its actors.
    Ids must be unique over the whole dataset: each batch checks its own.
    """

    def __init__(self, output: PathArg, settings: SettingsArg = None, device: DeviceArg = None) -> None:
        import chiaro

        self._output = os.path.abspath(os.fsdecode(output))
        os.makedirs(self._output, exist_ok=True)
        self._renderer = chiaro.Renderer(device=_worker_device(device), settings=settings)

    def _meta_stamp(self, job_id: str) -> Optional[Tuple[int, int, int]]:
        """Which meta.json job `job_id` has (inode, mtime in ns, size); None for none."""
        try:
            st = os.stat(os.path.join(self._output, job_id, "meta.json"))
        except OSError:
            return None
        return st.st_ino, st.st_mtime_ns, st.st_size

    def __call__(self, batch: Mapping[str, Any]) -> StageStatuses:
        """Renders the batch's jobs (its "job" column) and returns their ids and statuses."""
        import chiaro
        import numpy as np

        jobs = [json.loads(j) if isinstance(j, (str, bytes)) else dict(j) for j in batch["job"]]
        jobs = [job for _, job in _load_jobs(jobs)]
        before = {job["id"]: self._meta_stamp(job["id"]) for job in jobs}
        result = chiaro.render_jobs(jobs, self._output, renderer=self._renderer)
        errors = result.get("errors") or {}
        ids, statuses, messages = [], [], []
        for job in jobs:
            job_id = job["id"]
            after = self._meta_stamp(job_id)
            if job_id in errors:
                status, message = "failed", str(errors[job_id])
            elif after is None:
                status, message = "failed", "no meta.json was written"
            else:
                # A job rendered now has a new meta.json (its folder was renamed into
                # place); a job skipped keeps the one it had.
                status, message = ("skipped" if after == before[job_id] else "done"), ""
            ids.append(job_id)
            statuses.append(status)
            messages.append(message)
        return {"id": np.array(ids, dtype=object), "status": np.array(statuses, dtype=object),
                "error": np.array(messages, dtype=object)}
