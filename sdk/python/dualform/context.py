"""The library context, and a counting allocator for its memory hooks."""

from __future__ import annotations

import collections
import ctypes
import os
import threading
from pathlib import Path
from typing import Callable, Deque, List, Optional, Tuple, Union

from . import _arrays, _native
from ._handle import Handle
from .errors import check
from .types import LogId, LogLevel, WorkMode

LogCallback = Callable[[LogLevel, LogId, str], None]
#: A host's job system: called with each job the library hands over (an
#: opaque int), which the host then runs exactly once with :func:`run_job`.
JobSystem = Callable[[int], None]

_libc = ctypes.CDLL(None)
_libc.posix_memalign.argtypes = [ctypes.POINTER(ctypes.c_void_p), ctypes.c_size_t, ctypes.c_size_t]
_libc.posix_memalign.restype = ctypes.c_int
_libc.free.argtypes = [ctypes.c_void_p]
_libc.free.restype = None


class CountingAllocator:
    """Host memory hooks (dfm_allocator) that count what the library holds
    through them: the objects behind handles and their state records. After
    every handle made with it is closed, ``outstanding`` is 0 again; a
    handle that leaks keeps it above 0. Called from any thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._sizes: dict = {}
        self.allocations = 0
        self.frees = 0
        self.mismatched_frees = 0
        self._alloc = _native.ALLOC_FN(self._on_alloc)
        self._free = _native.FREE_FN(self._on_free)

    def _on_alloc(self, user, size: int, alignment: int) -> Optional[int]:
        memory = ctypes.c_void_p()
        if _libc.posix_memalign(ctypes.byref(memory), max(alignment, ctypes.sizeof(ctypes.c_void_p)),
                                max(size, 1)) != 0:
            return None
        with self._lock:
            self._sizes[memory.value] = size
            self.allocations += 1
        return memory.value

    def _on_free(self, user, memory: Optional[int], size: int) -> None:
        if memory is None:
            return
        with self._lock:
            if self._sizes.pop(memory, None) != size:
                self.mismatched_frees += 1
            self.frees += 1
        _libc.free(memory)

    @property
    def outstanding(self) -> int:
        """Blocks allocated and not yet freed."""
        with self._lock:
            return len(self._sizes)

    @property
    def outstanding_bytes(self) -> int:
        with self._lock:
            return sum(self._sizes.values())

    def to_c(self) -> _native.Allocator:
        return _native.Allocator(self._alloc, self._free, None)


def run_job(job: int) -> None:
    """dfm_job_run: runs a job a context handed to the host's job system,
    on this thread, without the GIL."""
    _native.lib().dfm_job_run(job)


class JobQueue:
    """A host's job system of ``threads`` Python threads, for a context
    made with ``work_mode=WorkMode.JOB_SYSTEM, job_system=queue``: each job
    the library hands over runs on one of them (the library's work runs
    without the GIL). Close the context, and so every job it handed over,
    before the queue: ``with JobQueue(2) as jobs, Context(...) as ctx``."""

    def __init__(self, threads: int = 2) -> None:
        self._ready = threading.Condition()
        self._jobs: Deque[int] = collections.deque()
        self._stopping = False
        self._threads = [threading.Thread(target=self._drain, name=f"jobs-{i}", daemon=True)
                         for i in range(threads)]
        for t in self._threads:
            t.start()

    def __call__(self, job: int) -> None:
        with self._ready:
            self._jobs.append(job)
            self._ready.notify()

    def _drain(self) -> None:
        while True:
            with self._ready:
                self._ready.wait_for(lambda: self._stopping or self._jobs)
                if not self._jobs:
                    return
                job = self._jobs.popleft()
            run_job(job)

    def close(self) -> None:
        """Runs what is queued, then stops the threads; idempotent."""
        with self._ready:
            self._stopping = True
            self._ready.notify_all()
        for t in self._threads:
            t.join()

    def __enter__(self) -> "JobQueue":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def default_models_directory() -> str:
    """$DUALFORM_MODELS, else ~/.cache/dualform/models (what tools/fetch-models
    fills): the folder the tools use for ``model:NAME``."""
    return os.environ.get("DUALFORM_MODELS") or str(Path.home() / ".cache" / "dualform" / "models")


class Context(Handle):
    """dfm_context: creates meshes. Configuration goes in here, never through
    the library's environment: ``models_directory`` for ``model:NAME``
    (``None``: :func:`default_models_directory`; ``""``: none).

    ``work_mode`` says where the sessions' work runs: ``WorkMode.POOL``, the
    context's own ``worker_count`` threads; ``WorkMode.JOB_SYSTEM``, the
    host's ``job_system`` (a :class:`JobQueue`, or any callable that queues
    a job for :func:`run_job`), at most ``worker_count`` jobs at once;
    ``WorkMode.HOST_STEPPED``, no thread: :meth:`step` and the waits run it."""

    _kind = "context"

    def __init__(
        self,
        *,
        worker_count: int = 1,
        pick_thread_count: int = 1,
        models_directory: Optional[Union[str, os.PathLike]] = None,
        allocator: Optional[CountingAllocator] = None,
        log: Optional[LogCallback] = None,
        work_mode: WorkMode = WorkMode.POOL,
        job_system: Optional[JobSystem] = None,
    ) -> None:
        lib = _native.lib()
        self.log_messages: List[Tuple[LogLevel, LogId, str]] = []
        self._user_log = log
        self._log_fn = _native.LOG_FN(self._on_log)
        folder = default_models_directory() if models_directory is None else os.fspath(models_directory)
        self._models = folder.encode()
        desc = _native.ContextDesc()
        desc.struct_size = ctypes.sizeof(desc)
        desc.header_version = _native.HEADER_VERSION
        if allocator is not None:
            desc.allocator = allocator.to_c()
        desc.log = self._log_fn
        desc.worker_count = worker_count
        desc.pick_thread_count = pick_thread_count
        desc.models_directory = self._models
        desc.work_mode = WorkMode(work_mode)
        self._job_system = job_system
        self._enqueue_fn = (_native.ENQUEUE_FN(lambda user, job: job_system(job))
                            if job_system is not None else _native.ENQUEUE_FN())
        desc.job_system.enqueue = self._enqueue_fn
        out = ctypes.c_void_p()
        check(lib.dfm_context_create(ctypes.byref(desc), ctypes.byref(out)))
        self.allocator = allocator
        self.work_mode = WorkMode(work_mode)
        super().__init__(out.value, lib.dfm_context_destroy, allocator, self._log_fn,
                         self._enqueue_fn, job_system)

    def step(self, budget_us: int = 0) -> bool:
        """dfm_context_step (``WorkMode.HOST_STEPPED``): runs the queued work on
        this thread, without the GIL, for about ``budget_us`` microseconds (0:
        until none is left); returns whether work is left."""
        left = ctypes.c_bool()
        check(_native.lib().dfm_context_step(self.pointer, _arrays.unsigned(budget_us, "budget_us"),
                                             ctypes.byref(left)))
        return left.value

    def _on_log(self, user, level: int, log_id: int, message: bytes) -> None:
        entry = (LogLevel(level), LogId(log_id), message.decode(errors="replace"))
        self.log_messages.append(entry)
        if self._user_log is not None:
            self._user_log(*entry)

    @property
    def keep_alive(self) -> tuple:
        """What a handle made from this context must keep alive."""
        return (self, self.allocator, self._log_fn, self._enqueue_fn, self._job_system)
