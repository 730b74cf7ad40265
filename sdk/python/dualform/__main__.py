"""``python -m dualform deform SCENARIO --out MESH [--report JSON]
[--strict] [--hard-handles] [--method fitted_rotations|paper]``: the
``dualform`` tool's deform command, through this package."""

from __future__ import annotations

import argparse
import json
import sys
from typing import List, Optional

from .errors import DualformError
from .scenario import ScenarioError, run_deform
from .types import Method

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dualform")
    commands = parser.add_subparsers(dest="command", required=True)
    deform = commands.add_parser("deform", help="solve a scenario and write the deformed mesh")
    deform.add_argument("scenario")
    deform.add_argument("--out", required=True, help="the deformed mesh (.off, .obj, .ply)")
    deform.add_argument("--report", help="also write the report JSON here")
    deform.add_argument("--strict", action="store_true", help="fail when the solve did not converge")
    deform.add_argument("--hard-handles", action="store_true")
    deform.add_argument("--method", choices=["fitted_rotations", "paper"])
    args = parser.parse_args(argv)
    method = None if args.method is None else (
        Method.PAPER if args.method == "paper" else Method.FITTED_ROTATIONS)
    try:
        report = run_deform(args.scenario, args.out, hard_handles=args.hard_handles, method=method)
    except (ScenarioError, DualformError, OSError, KeyError, TypeError) as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_BAD_INPUT
    text = json.dumps(report)
    print(text)
    if args.report:
        with open(args.report, "w") as f:
            f.write(text + "\n")
    if args.strict and not report["converged"]:
        print(f"error: did not converge in {report['iterations']} iterations", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
