"""The Python package's ctypes structs (dualform._native) against dualform.h.

Three views of every struct must agree: the fields the header declares (read
from its text), the layout the C compiler gives them (sizes, alignments and
offsets printed by struct_layout.c, built with the header) and the package's
``_fields_``. A field added to the header and missed by the package, a type
that changed width, or a struct the package mirrors that the layout program
does not list, all fail here.
"""

from __future__ import annotations

import ctypes
import os
import re
import subprocess
from pathlib import Path

import pytest

from dualform import _native

HEADER = Path(__file__).resolve().parents[2] / "sdk" / "include" / "dualform" / "dualform.h"


def compiled_layout() -> tuple[dict, dict]:
    """{python name: (C name, size, alignment)} and {python name: {field: (offset, size)}}."""
    program = os.environ.get("DUALFORM_STRUCT_LAYOUT")
    if not program:
        pytest.fail("DUALFORM_STRUCT_LAYOUT must name the built struct_layout program "
                    "(CTest sets it)")
    text = subprocess.run([program], check=True, capture_output=True, text=True).stdout
    structs: dict = {}
    fields: dict = {}
    for line in text.splitlines():
        kind, owner, *rest = line.split()
        if kind == "struct":
            structs[owner] = (rest[0], int(rest[1]), int(rest[2]))
            fields[owner] = {}
        else:
            fields[owner][rest[0]] = (int(rest[1]), int(rest[2]))
    return structs, fields


def header_fields() -> dict:
    """{C struct name: [field names in order]}, from the header's text."""
    text = re.sub(r"/\*.*?\*/", "", HEADER.read_text(), flags=re.S)
    out = {}
    for struct in re.finditer(r"struct (dfm_\w+) \{(.*?)\}", text, flags=re.S):
        names = []
        for declaration in struct.group(2).split(";"):
            declaration = declaration.strip()
            if not declaration:
                continue
            pointer = re.search(r"\(\*\s*(\w+)\)", declaration)  # a function pointer
            name = pointer or re.search(r"(\w+)\s*(\[[^\]]*\])?$", declaration)
            names.append(name.group(1))
        out[struct.group(1)] = names
    return out


def package_structs() -> dict:
    return {name: value for name, value in vars(_native).items()
            if isinstance(value, type) and issubclass(value, ctypes.Structure)
            and value.__module__ == _native.__name__}


STRUCTS, FIELDS = compiled_layout()
HEADER_FIELDS = header_fields()
PACKAGE = package_structs()


def test_the_package_mirrors_exactly_the_structs_the_layout_program_lists():
    assert sorted(PACKAGE) == sorted(STRUCTS)


@pytest.mark.parametrize("name", sorted(PACKAGE))
def test_a_struct_matches_the_header_field_by_field(name):
    cls = PACKAGE[name]
    c_name, size, alignment = STRUCTS[name]
    package_fields = [field[0] for field in cls._fields_]
    assert package_fields == HEADER_FIELDS[c_name], f"{name} against {c_name}'s declaration"
    assert list(FIELDS[name]) == HEADER_FIELDS[c_name], f"struct_layout.c lists {c_name} so"
    for field in package_fields:
        offset, field_size = FIELDS[name][field]
        assert getattr(cls, field).offset == offset, f"{c_name}.{field}'s offset"
        assert getattr(cls, field).size == field_size, f"{c_name}.{field}'s size"
    assert ctypes.sizeof(cls) == size, f"sizeof({c_name})"
    assert ctypes.alignment(cls) == alignment, f"alignof({c_name})"
