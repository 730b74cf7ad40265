#!/usr/bin/python3
"""Builds the installable add-on: a zip of dualform_blender/ with a copy of
the dualform Python package in dualform_blender/vendor/ and, with
--library, libdualform in vendor/dualform/lib/ (then the add-on needs
nothing else but Embree, which the library links).

usage: samples/blender/package.py OUT.zip [--library build/release/sdk/libdualform.so]
"""

import argparse
import os
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
PACKAGE = HERE.parents[1] / "sdk" / "python" / "dualform"
SONAME = "libdualform.so.0.2"


def add_tree(archive: zipfile.ZipFile, folder: Path, prefix: str) -> None:
    for path in sorted(folder.rglob("*.py")):
        if "__pycache__" not in path.parts:
            archive.write(path, f"{prefix}/{path.relative_to(folder)}")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("out")
    parser.add_argument("--library", help="libdualform.so to bundle")
    args = parser.parse_args()
    with zipfile.ZipFile(args.out, "w", zipfile.ZIP_DEFLATED) as archive:
        add_tree(archive, HERE / "dualform_blender", "dualform_blender")
        add_tree(archive, PACKAGE, "dualform_blender/vendor/dualform")
        if args.library:
            archive.write(os.path.realpath(args.library),
                          f"dualform_blender/vendor/dualform/lib/{SONAME}")
    print(args.out)


if __name__ == "__main__":
    main()
