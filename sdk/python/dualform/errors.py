"""Exceptions: every failing C API call raises a :class:`DualformError`
subclass named after its ``dfm_result``, with the library's message."""

from __future__ import annotations

from typing import Dict, Type

from . import _native

RESULT_NAMES = (
    "DFM_OK",
    "DFM_ERROR_INVALID_ARGUMENT",
    "DFM_ERROR_NOT_FOUND",
    "DFM_ERROR_IO",
    "DFM_ERROR_PARSE",
    "DFM_ERROR_OUT_OF_RANGE",
    "DFM_ERROR_UNSUPPORTED",
    "DFM_ERROR_OUT_OF_MEMORY",
    "DFM_ERROR_NUMERICAL",
    "DFM_ERROR_INVALID_HANDLE",
    "DFM_ERROR_BUSY",
    "DFM_ERROR_DEVICE",
    "DFM_ERROR_CANCELLED",
    "DFM_ERROR_INTERNAL",
)


class DualformError(Exception):
    """A failing dfm_ call. ``result`` is the dfm_result code, ``name`` its
    name ("DFM_ERROR_PARSE") and ``message`` dfm_last_error_message()."""

    result: int = -1

    def __init__(self, result: int, name: str, message: str) -> None:
        super().__init__(f"{name}: {message}")
        self.result = result
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
    _cls.result = _code


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
