"""The add-on installed as docs/blender.md says: the page's Python block,
run as written inside Blender, whose working directory (set by the tests)
is the folder that holds dualform_blender.zip."""

import re
from pathlib import Path

PAGE = Path(__file__).resolve().parents[2] / "docs" / "blender.md"


def install_block() -> str:
    page = PAGE.read_text()
    return re.search(r"```python\n(import os\nimport bpy\n.*?)```", page, re.S).group(1)


def install_as_documented() -> None:
    exec(compile(install_block(), str(PAGE), "exec"), {})
