"""The library context, and a counting allocator for its memory hooks."""

from __future__ import annotations

import ctypes
import os
import threading
from pathlib import Path
from typing import Callable, List, Optional, Tuple, Union

from . import _native
from ._handle import Handle
from .errors import check
from .types import LogId, LogLevel

LogCallback = Callable[[LogLevel, LogId, str], None]

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


def default_models_directory() -> str:
    """$DUALFORM_MODELS, else ~/.cache/dualform/models (what tools/fetch-models
    fills): the folder the tools use for ``model:NAME``."""
    return os.environ.get("DUALFORM_MODELS") or str(Path.home() / ".cache" / "dualform" / "models")


class Context(Handle):
    """dfm_context: creates meshes. Configuration goes in here, never through
    the library's environment: ``models_directory`` for ``model:NAME``
    (``None``: :func:`default_models_directory`; ``""``: none)."""

    _kind = "context"

    def __init__(
        self,
        *,
        worker_count: int = 1,
        pick_thread_count: int = 1,
        models_directory: Optional[Union[str, os.PathLike]] = None,
        allocator: Optional[CountingAllocator] = None,
        log: Optional[LogCallback] = None,
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
        out = ctypes.c_void_p()
        check(lib.dfm_context_create(ctypes.byref(desc), ctypes.byref(out)))
        self.allocator = allocator
        super().__init__(out.value, lib.dfm_context_destroy, allocator, self._log_fn)

    def _on_log(self, user, level: int, log_id: int, message: bytes) -> None:
        entry = (LogLevel(level), LogId(log_id), message.decode(errors="replace"))
        self.log_messages.append(entry)
        if self._user_log is not None:
            self._user_log(*entry)

    @property
    def keep_alive(self) -> tuple:
        """What a handle made from this context must keep alive."""
        return (self, self.allocator, self._log_fn)
