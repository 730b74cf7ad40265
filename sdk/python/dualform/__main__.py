"""``python -m dualform deform SCENARIO --out MESH [--report JSON]
[--roi-out TXT] [--strict] [--hard-handles] [--method fitted_rotations|paper]
[--morph-target NAME]``: the ``dualform`` tool's deform command through
this package, with the tool's report, messages and exit codes (0 success,
1 the work failed, 2 bad input)."""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from .scenario import (ScenarioError, SolveError, WorkError, report_json, run_deform,
                       write_text_file)
from .types import Method

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2


def _error(message: str) -> None:
    print(f"error: {message}", file=sys.stderr)


def _warning(message: str) -> None:
    print(f"warning: {message}", file=sys.stderr)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dualform")
    commands = parser.add_subparsers(dest="command", required=True)
    deform = commands.add_parser("deform", help="solve a scenario and write the deformed mesh")
    deform.add_argument("scenario")
    deform.add_argument("--out", required=True,
                        help="the deformed mesh (.off, .obj, .ply, .gltf, .glb, .fbx)")
    deform.add_argument("--report", help="also write the report JSON here")
    deform.add_argument("--roi-out", help="write the ROI's vertices here, one a line")
    deform.add_argument("--strict", action="store_true", help="fail when the solve did not converge")
    deform.add_argument("--hard-handles", action="store_true")
    deform.add_argument("--method", choices=["fitted_rotations", "paper"])
    deform.add_argument("--morph-target", metavar="NAME",
                        help="for a glTF or FBX mesh: keep the asset's positions and add the "
                             "edit as a morph target (FBX: blend shape channel) of this name")
    args = parser.parse_args(argv)
    if args.morph_target == "":
        _error("--morph-target needs a name")
        return EXIT_BAD_INPUT
    method = None if args.method is None else (
        Method.PAPER if args.method == "paper" else Method.FITTED_ROTATIONS)
    try:
        report = run_deform(args.scenario, args.out, hard_handles=args.hard_handles,
                            method=method, morph_target=args.morph_target, roi_out=args.roi_out,
                            warn=_warning)
    except WorkError as error:
        _error(str(error))
        return EXIT_BAD_INPUT if error.bad_input else EXIT_FAILED
    except ScenarioError as error:
        _error(str(error))
        return EXIT_BAD_INPUT
    except SolveError as error:
        _error(str(error))
        return EXIT_FAILED
    text = report_json(report)
    print(text)
    if args.report:
        try:
            write_text_file(args.report, text)
        except WorkError as error:
            _error(str(error))
            return EXIT_BAD_INPUT if error.bad_input else EXIT_FAILED
    if args.strict and not report["converged"]:
        _error(f"did not converge in {report['iterations']} iterations (last update "
               f"{report['last_update']:g} of the diagonal)")
        return EXIT_FAILED
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
