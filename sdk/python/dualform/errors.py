"""Exceptions: every failing C API call raises a :class:`DualformError`
subclass named after its ``dfm_result``, with the library's message."""

from __future__ import annotations

import enum
from typing import Dict, Type, Union

from . import _native


class Result(enum.IntEnum):
    """dfm_result: what a call, or a frame (``FrameInfo.status``), came to.
    ``str(Result.ERROR_NUMERICAL)`` is the C name, "DFM_ERROR_NUMERICAL"."""

    OK = 0
    ERROR_INVALID_ARGUMENT = 1
    ERROR_NOT_FOUND = 2
    ERROR_IO = 3
    ERROR_PARSE = 4
    ERROR_OUT_OF_RANGE = 5
    ERROR_UNSUPPORTED = 6
    ERROR_OUT_OF_MEMORY = 7
    ERROR_NUMERICAL = 8
    ERROR_INVALID_HANDLE = 9
    ERROR_BUSY = 10
    ERROR_DEVICE = 11
    ERROR_CANCELLED = 12
    ERROR_INTERNAL = 13

    def __str__(self) -> str:
        return "DFM_" + self.name


def as_result(code: int) -> Union[Result, int]:
    """``code`` as a :class:`Result`; a code this package does not know (a
    newer library's) stays a plain int."""
    try:
        return Result(code)
    except ValueError:
        return code


class DualformError(Exception):
    """A failing dfm_ call. ``result`` is the dfm_result (a :class:`Result`),
    ``name`` its C name ("DFM_ERROR_PARSE") and ``message``
    dfm_last_error_message(). For a solve that failed as the context's
    work (``Session.wait``), ``frame`` is the frame's ``FrameInfo``."""

    result: Union[Result, int] = -1
    frame = None

    def __init__(self, result: int, name: str, message: str) -> None:
        super().__init__(f"{name}: {message}")
        self.result = as_result(result)
        self.name = name
        self.message = message


class InvalidArgumentError(DualformError, ValueError):
    """DFM_ERROR_INVALID_ARGUMENT"""


class NotFoundError(DualformError, LookupError):
    """DFM_ERROR_NOT_FOUND"""


class IOFailedError(DualformError, OSError):
    """DFM_ERROR_IO"""


class ParseError(DualformError, ValueError):
    """DFM_ERROR_PARSE"""


class OutOfRangeError(DualformError, IndexError):
    """DFM_ERROR_OUT_OF_RANGE"""


class UnsupportedError(DualformError):
    """DFM_ERROR_UNSUPPORTED"""


class OutOfMemoryError(DualformError, MemoryError):
    """DFM_ERROR_OUT_OF_MEMORY"""


class NumericalError(DualformError, ArithmeticError):
    """DFM_ERROR_NUMERICAL"""


class InvalidHandleError(DualformError):
    """DFM_ERROR_INVALID_HANDLE"""


class BusyError(DualformError):
    """DFM_ERROR_BUSY (also a wait's timeout)"""


class DeviceError(DualformError):
    """DFM_ERROR_DEVICE"""


class CancelledError(DualformError):
    """DFM_ERROR_CANCELLED"""


class InternalError(DualformError):
    """DFM_ERROR_INTERNAL: a defect of Dualform's"""


_BY_CODE: Dict[int, Type[DualformError]] = {
    1: InvalidArgumentError,
    2: NotFoundError,
    3: IOFailedError,
    4: ParseError,
    5: OutOfRangeError,
    6: UnsupportedError,
    7: OutOfMemoryError,
    8: NumericalError,
    9: InvalidHandleError,
    10: BusyError,
    11: DeviceError,
    12: CancelledError,
    13: InternalError,
}
for _code, _cls in _BY_CODE.items():
    _cls.result = Result(_code)


def result_name(result: int) -> str:
    """dfm_result_name()."""
    return _native.lib().dfm_result_name(result).decode()


def error_for(result: int, message: str) -> DualformError:
    """The exception for ``result`` with ``message``."""
    cls = _BY_CODE.get(result, DualformError)
    return cls(result, result_name(result), message)


def check(result: int) -> None:
    """Raises the exception for a failing result with the thread's last
    message (read right after the call, on the calling thread)."""
    if result != 0:
        message = _native.lib().dfm_last_error_message().decode(errors="replace")
        raise error_for(result, message)
