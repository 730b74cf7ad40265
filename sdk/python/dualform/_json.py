"""The dualform tool's JSON, in Python: a strict reader (RFC 8259) whose
every value knows its line and column, and the tool's compact writer, so
that ``python -m dualform`` reads scenarios and words its messages and
reports as ``dualform`` does (tools/json in the repository is the C++
original; the parity test compares the two on the malformed corpus).

Bytes in, UTF-8 checked; columns count code points, a tab as one."""

from __future__ import annotations

import decimal
import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

MAX_DEPTH = 256

NULL, BOOLEAN, NUMBER, STRING, ARRAY, OBJECT = range(6)
TYPE_PHRASES = ("null", "a boolean", "a number", "a string", "an array", "an object")

_WORD = frozenset(b"0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_.+-")
_DIGITS = frozenset(b"0123456789")
_ESCAPES = {ord('"'): '"', ord("\\"): "\\", ord("/"): "/", ord("b"): "\b", ord("f"): "\f",
            ord("n"): "\n", ord("r"): "\r", ord("t"): "\t"}


class JsonError(ValueError):
    """A text that is not JSON; the message starts with its location."""


@dataclass
class Value:
    """One value: ``kind`` is NULL ... OBJECT; only its kind's fields mean
    anything. ``at`` is (line, column) of its first character."""

    kind: int = NULL
    at: Tuple[int, int] = (1, 1)
    boolean: bool = False
    number: float = 0.0
    integer: bool = False  # written without fraction or exponent
    beyond_double: bool = False  # a number past a double's range, kept as +-inf
    text: str = ""  # a string, or the text of a number beyond a double
    items: List["Value"] = field(default_factory=list)
    members: List["Member"] = field(default_factory=list)

    def find(self, key: str) -> Optional["Member"]:
        for m in self.members:
            if m.key == key:
                return m
        return None


@dataclass
class Member:
    key: str
    at: Tuple[int, int]
    value: Value


def location(source: str, at: Tuple[int, int]) -> str:
    """"SOURCE:LINE:COL: ", the start of every located message."""
    return f"{source}:{at[0]}:{at[1]}: "


def printable(text: str) -> str:
    """A key or string fit for a message: control characters as \\xNN, at
    most 40 characters, then "..."."""
    out = []
    for i, ch in enumerate(text):
        if i == 40:
            out.append("...")
            break
        c = ord(ch)
        out.append(f"\\x{c:02x}" if c < 0x20 or c == 0x7F else ch)
    return "".join(out)


def number_text(value: float) -> str:
    """The shortest text that reads back as exactly ``value``, chosen as
    C++'s std::to_chars chooses it: fixed or scientific, whichever is
    shorter, fixed on a tie."""
    if math.isnan(value):
        return "-nan" if math.copysign(1.0, value) < 0 else "nan"
    if math.isinf(value):
        return "-inf" if value < 0 else "inf"
    sign = "-" if math.copysign(1.0, value) < 0 else ""
    if value == 0.0:
        return sign + "0"
    digits_tuple, exponent = decimal.Decimal(repr(abs(value))).as_tuple()[1:]
    digits = "".join(map(str, digits_tuple)).rstrip("0")
    exponent += len("".join(map(str, digits_tuple))) - len(digits)
    digits = digits.lstrip("0")
    point = exponent + len(digits) - 1  # the first digit's power of ten
    mantissa = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    scientific = f"{mantissa}e{'-' if point < 0 else '+'}{abs(point):02d}"
    if point >= 0:
        whole = digits[:point + 1].ljust(point + 1, "0")
        rest = digits[point + 1:]
        fixed = whole + ("." + rest if rest else "")
    else:
        fixed = "0." + "0" * (-point - 1) + digits
    return sign + (fixed if len(fixed) <= len(scientific) else scientific)


class _Parser:
    def __init__(self, text: bytes, source: str, keep_huge_numbers: bool) -> None:
        self.text = text
        self.source = source
        self.keep_huge = keep_huge_numbers
        self.pos = 0
        self.line = 1
        self.column = 1

    # -- the cursor
    def at_end(self) -> bool:
        return self.pos == len(self.text)

    def peek(self) -> int:
        return 0 if self.at_end() else self.text[self.pos]

    def here(self) -> Tuple[int, int]:
        return (self.line, self.column)

    def advance(self) -> None:
        c = self.text[self.pos]
        self.pos += 1
        if c == 0x0A:
            self.line += 1
            self.column = 1
        elif c & 0xC0 != 0x80:
            self.column += 1

    def skip_whitespace(self) -> None:
        while not self.at_end() and self.peek() in b" \t\n\r":
            self.advance()

    # -- messages
    def error(self, at: Tuple[int, int], what: str) -> JsonError:
        return JsonError(location(self.source, at) + what)

    def expected(self, what: str, at: Optional[Tuple[int, int]] = None) -> JsonError:
        return self.error(at or self.here(), f"expected {what}, found {self.found()}")

    def found(self) -> str:
        if self.at_end():
            return "the end of the text"
        c = self.peek()
        if c in (0x0A, 0x0D):
            return "a line break"
        if c < 0x20 or c >= 0x7F:
            return f"the byte \\x{c:02x}"
        end = self.pos + 1
        if c in _WORD:
            while end < len(self.text) and end - self.pos < 32 and self.text[end] in _WORD:
                end += 1
        return "'" + self.text[self.pos:end].decode("ascii") + "'"

    # -- the grammar
    def document(self) -> Value:
        if self.text.startswith(b"\xef\xbb\xbf"):
            self.pos = 3
        self.skip_whitespace()
        root = self.value(0)
        self.skip_whitespace()
        if not self.at_end():
            raise self.expected("the end of the text after the top-level value")
        return root

    def value(self, depth: int) -> Value:
        out = Value(at=self.here())
        c = self.peek()
        if c in (ord("{"), ord("[")):
            if depth == MAX_DEPTH:
                raise self.error(self.here(),
                                 f"arrays and objects nest deeper than {MAX_DEPTH} levels")
            if c == ord("{"):
                self.object(out, depth + 1)
            else:
                self.array(out, depth + 1)
        elif c == ord('"'):
            out.kind = STRING
            out.text = self.string()
        elif c == ord("-") or c in _DIGITS:
            self.number(out)
        elif self.literal(b"true"):
            out.kind, out.boolean = BOOLEAN, True
        elif self.literal(b"false"):
            out.kind = BOOLEAN
        elif not self.literal(b"null"):
            raise self.expected("a value")
        return out

    def literal(self, word: bytes) -> bool:
        end = self.pos + len(word)
        if self.text[self.pos:end] != word:
            return False
        if end < len(self.text) and self.text[end] in _WORD:
            return False
        for _ in word:
            self.advance()
        return True

    def digits(self) -> None:
        while self.peek() in _DIGITS and not self.at_end():
            self.advance()

    def number(self, out: Value) -> None:
        start = self.pos
        out.kind, out.integer = NUMBER, True
        if self.peek() == ord("-"):
            self.advance()
        if self.at_end() or self.peek() not in _DIGITS:
            raise self.expected("a digit after '-'")
        if self.peek() == ord("0"):
            self.advance()
            if not self.at_end() and self.peek() in _DIGITS:
                raise self.error(out.at, "a number cannot start with a leading zero")
        else:
            self.digits()
        if self.peek() == ord("."):
            out.integer = False
            self.advance()
            if self.at_end() or self.peek() not in _DIGITS:
                raise self.expected("a digit after the decimal point")
            self.digits()
        if self.peek() in (ord("e"), ord("E")):
            out.integer = False
            self.advance()
            if self.peek() in (ord("+"), ord("-")):
                self.advance()
            if self.at_end() or self.peek() not in _DIGITS:
                raise self.expected("a digit in the exponent")
            self.digits()
        written = self.text[start:self.pos].decode("ascii")
        out.number = float(written)
        if math.isinf(out.number):
            if not self.keep_huge:
                raise self.error(out.at, f"the number {printable(written)} is beyond the range "
                                         "of a double")
            out.beyond_double = True
            out.text = written

    def string(self) -> str:
        open_at = self.here()
        self.advance()
        out = bytearray()
        while True:
            if self.at_end() or self.peek() == 0x0A:
                raise self.expected(f"'\"' to end the string started at {open_at[0]}:{open_at[1]}")
            c = self.peek()
            if c == ord('"'):
                self.advance()
                return out.decode("utf-8", "surrogatepass")
            if c == ord("\\"):
                self.escape(out)
            elif c < 0x20:
                raise self.error(self.here(), f"a control character (\\x{c:02x}) must be written "
                                              "as an escape in a string")
            elif c < 0x80:
                out.append(c)
                self.advance()
            else:
                n = _utf8_length(self.text, self.pos)
                if n == 0:
                    raise self.error(self.here(), f"invalid UTF-8 in a string at byte \\x{c:02x}")
                out += self.text[self.pos:self.pos + n]
                for _ in range(n):
                    self.advance()

    def escape(self, out: bytearray) -> None:
        at = self.here()
        self.advance()
        c = self.peek()
        if c == ord("u") and not self.at_end():
            self.unicode_escape(out, at)
            return
        if self.at_end() or c not in _ESCAPES:
            raise self.expected("an escape after '\\' (one of \" \\ / b f n r t u)", at)
        out += _ESCAPES[c].encode()
        self.advance()

    def code_unit(self) -> int:
        self.advance()
        unit = 0
        for _ in range(4):
            c = self.peek()
            v = int(chr(c), 16) if not self.at_end() and chr(c) in "0123456789abcdefABCDEF" else -1
            if v < 0:
                raise self.expected("four hex digits after '\\u'")
            unit = unit * 16 + v
            self.advance()
        return unit

    def unicode_escape(self, out: bytearray, at: Tuple[int, int]) -> None:
        unit = self.code_unit()
        written = self.text[self.pos - 6:self.pos].decode("ascii")
        if 0xDC00 <= unit <= 0xDFFF:
            raise self.error(at, f"the low surrogate {written} must follow a high surrogate "
                                 "(\\uD800 to \\uDBFF)")
        if 0xD800 <= unit <= 0xDBFF:
            low_at = self.here()
            escaped = self.text[self.pos:self.pos + 2] == b"\\u"
            low = 0
            if escaped:
                self.advance()
                low = self.code_unit()
            if not 0xDC00 <= low <= 0xDFFF:
                raise self.error(low_at if escaped else at,
                                 f"the high surrogate {written} must be followed by a low "
                                 "surrogate (\\uDC00 to \\uDFFF)")
            unit = 0x10000 + ((unit - 0xD800) << 10) + (low - 0xDC00)
        out += chr(unit).encode("utf-8", "surrogatepass")

    def array(self, out: Value, depth: int) -> None:
        out.kind = ARRAY
        self.advance()
        self.skip_whitespace()
        if self.peek() == ord("]"):
            self.advance()
            return
        while True:
            out.items.append(self.value(depth))
            self.skip_whitespace()
            if self.peek() == ord("]"):
                self.advance()
                return
            if self.peek() != ord(",") or self.at_end():
                raise self.expected("',' or ']' after an array element")
            self.advance()
            self.skip_whitespace()

    def object(self, out: Value, depth: int) -> None:
        out.kind = OBJECT
        self.advance()
        self.skip_whitespace()
        if self.peek() == ord("}"):
            self.advance()
            return
        first_at = {}
        while True:
            if self.peek() != ord('"') or self.at_end():
                raise self.expected("a string key or '}'" if not out.members
                                    else "a string key after ','")
            at = self.here()
            key = self.string()
            if key in first_at:
                line, column = first_at[key]
                raise self.error(at, f'duplicate key "{printable(key)}" (first at {line}:{column})')
            first_at[key] = at
            self.skip_whitespace()
            if self.peek() != ord(":") or self.at_end():
                raise self.expected("':' after an object key")
            self.advance()
            self.skip_whitespace()
            out.members.append(Member(key, at, self.value(depth)))
            self.skip_whitespace()
            if self.peek() == ord("}"):
                self.advance()
                return
            if self.peek() != ord(",") or self.at_end():
                raise self.expected("',' or '}' after an object member")
            self.advance()
            self.skip_whitespace()


def _utf8_length(text: bytes, pos: int) -> int:
    """The length of the UTF-8 sequence at ``pos`` (RFC 3629), 0 if invalid."""
    def byte(i: int) -> int:
        return text[pos + i] if pos + i < len(text) else 0

    c = byte(0)
    lo, hi = 0x80, 0xBF
    if 0xC2 <= c <= 0xDF:
        n = 2
    elif 0xE0 <= c <= 0xEF:
        n = 3
        lo = 0xA0 if c == 0xE0 else lo
        hi = 0x9F if c == 0xED else hi
    elif 0xF0 <= c <= 0xF4:
        n = 4
        lo = 0x90 if c == 0xF0 else lo
        hi = 0x8F if c == 0xF4 else hi
    else:
        return 0
    if not lo <= byte(1) <= hi:
        return 0
    if any(byte(i) & 0xC0 != 0x80 for i in range(2, n)):
        return 0
    return n


def parse(text: bytes, source: str, *, keep_huge_numbers: bool = False) -> Value:
    """One JSON text, strictly: no comments, trailing commas, NaN, leading
    zeros, unescaped control characters, invalid UTF-8, lone surrogates or
    duplicate keys; a leading byte order mark is skipped. Raises
    :class:`JsonError` ("SOURCE:LINE:COL: expected ..., found ...")."""
    return _Parser(text, source, keep_huge_numbers).document()


class Writer:
    """The tool's compact JSON writer: ``{"key":value,...}`` on one line,
    numbers as :func:`number_text` (non-finite ones as null)."""

    def __init__(self) -> None:
        self._parts: List[str] = []
        self._has_items: List[bool] = []
        self._after_key = False

    def _separate(self) -> None:
        if self._after_key:
            self._after_key = False
            return
        if self._has_items:
            if self._has_items[-1]:
                self._parts.append(",")
            self._has_items[-1] = True

    def begin_object(self) -> "Writer":
        self._separate()
        self._parts.append("{")
        self._has_items.append(False)
        return self

    def end_object(self) -> "Writer":
        self._has_items.pop()
        self._parts.append("}")
        return self

    def key(self, name: str) -> "Writer":
        self.value(name)
        self._parts.append(":")
        self._after_key = True
        return self

    def value(self, v) -> "Writer":
        self._separate()
        if isinstance(v, bool):
            self._parts.append("true" if v else "false")
        elif isinstance(v, int):
            self._parts.append(str(v))
        elif isinstance(v, float):
            self._parts.append(number_text(v) if math.isfinite(v) else "null")
        else:
            self._parts.append(_quoted(str(v)))
        return self

    def field(self, name: str, v) -> "Writer":
        return self.key(name).value(v)

    def text(self) -> str:
        return "".join(self._parts)


def _quoted(text: str) -> str:
    out = ['"']
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)
