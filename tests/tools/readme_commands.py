#!/usr/bin/env python3
"""CI runs the README's commands exactly as the README writes them.

Reads the commands of the README's first ``sh`` block under "## Two
commands" (each line's text before its comment) and fails unless `.ci/run`
runs every one of them with no other argument and never with one. Before
checking the real `.ci/run` it checks itself on copies that CI must not pass
(a command given arguments, a command left out), so it cannot pass by
finding nothing.

usage: readme_commands.py README CI_SCRIPT
"""
import re
import shlex
import sys


def readme_commands(text):
    section = text.split("## Two commands", 1)
    if len(section) != 2:
        raise SystemExit("README: no '## Two commands' section")
    block = re.search(r"```sh\n(.*?)```", section[1], re.S)
    if not block:
        raise SystemExit("README: no ```sh block under '## Two commands'")
    commands = []
    for line in block.group(1).splitlines():
        command = line.split("#", 1)[0].strip()
        if command:
            commands.append(command)
    if not commands:
        raise SystemExit("README: the '## Two commands' block names no command")
    return commands


def ci_invocations(text, program):
    """The argument lists `program` is run with in the script's lines."""
    runs = []
    for line in text.splitlines():
        code = line.split("#", 1)[0]
        if not code.strip():
            continue
        words = shlex.split(code)
        for i, word in enumerate(words):
            if word != program:
                continue
            rest = []
            for w in words[i + 1:]:
                if w in (";", "&&", "||", "|", ")"):
                    break
                rest.append(w)
            runs.append(rest)
    return runs


def problems(commands, ci_text):
    found = []
    for command in commands:
        program, *args = shlex.split(command)
        runs = ci_invocations(ci_text, program)
        if not any(run == args for run in runs):
            found.append(f"'{command}' is not run as the README writes it")
        for run in runs:
            if run != args:
                found.append(f"'{' '.join([program] + run)}' is not the README's '{command}'")
    return found


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1]) as f:
        commands = readme_commands(f.read())
    with open(sys.argv[2]) as f:
        ci = f.read()
    # The check itself: a copy with an argument added to each command, and
    # one without the command, must both fail.
    for command in commands:
        program = shlex.split(command)[0]
        widened = re.sub(rf"(?m)^(.*\s){re.escape(program)}(\s*)$",
                         rf"\g<1>{program} release\g<2>", ci)
        dropped = "\n".join(line for line in ci.splitlines() if program not in line)
        for name, variant in (("an argument added", widened), ("the command removed", dropped)):
            if not problems([command], variant):
                raise SystemExit(f"self-check: .ci/run with {name} to '{command}' still passes")
    found = problems(commands, ci)
    if found:
        print(f"{sys.argv[2]} does not run the README's commands as written:", file=sys.stderr)
        for p in found:
            print("  " + p, file=sys.stderr)
        return 1
    print(f"{sys.argv[2]} runs the README's commands as written: {', '.join(commands)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
