"""The one way a Python object owns a C handle: freed exactly once."""

from __future__ import annotations

import threading
from typing import Callable, Optional

from .errors import InvalidHandleError


class Handle:
    """Owns one dfm handle; ``close()`` frees it once (later calls do
    nothing), as does leaving a ``with`` block or, as a fallback, garbage
    collection. Using a closed handle raises :class:`InvalidHandleError`."""

    _kind = "handle"

    def __init__(self, pointer: int, destroy: Callable[[int], None], *keep_alive: object):
        self._pointer: Optional[int] = pointer
        self._destroy = destroy
        self._close_lock = threading.Lock()
        # Python objects the C object may call back into (the context's
        # allocator and log) live at least as long as this handle.
        self._keep_alive = keep_alive

    @property
    def pointer(self) -> int:
        """The C handle; raises once closed."""
        p = self._pointer
        if p is None:
            raise InvalidHandleError(9, "DFM_ERROR_INVALID_HANDLE", f"this {self._kind} is closed")
        return p

    @property
    def closed(self) -> bool:
        return self._pointer is None

    def close(self) -> None:
        """Frees the C handle; idempotent."""
        with self._close_lock:
            p, self._pointer = self._pointer, None
        if p is not None:
            self._destroy(p)

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self) -> None:
        if getattr(self, "_pointer", None) is not None:
            self.close()
