#!/usr/bin/env python3
"""Hook files: solutions/ is the source of truth; assignments/ and the seeded mistakes derive from it.

A solution file marks its reference code like this:

        // BEGIN SOLUTION
        reference code                      (removed from the student's copy)
        // ELSE STUB
        // notImplemented("integrator()");  (uncommented in the student's copy)
        // END SOLUTION

Commands:
  hooks.py stub FILE                       print the student's version of one solution file
  hooks.py check                           exit 1, naming the files, when assignments/ has drifted
  hooks.py write [--backup DIR]            regenerate assignments/ (changed files are copied to DIR first)
  hooks.py mutants OUTDIR                  write every seeded mistake of tests/mutants/*.json as a
                                           hook directory OUTDIR/NAME and print NAME per line
  hooks.py files                           print the hook file names (cmake/hook_files.txt)
"""
import argparse
import json
import pathlib
import re
import shutil
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOLUTIONS = ROOT / "solutions"
ASSIGNMENTS = ROOT / "assignments"
MUTANTS = ROOT / "tests" / "mutants"
HOOK_LIST = ROOT / "cmake" / "hook_files.txt"

BEGIN, ELSE, END = "// BEGIN SOLUTION", "// ELSE STUB", "// END SOLUTION"


class HookError(Exception):
    pass


def hook_files():
    return [line.strip() for line in HOOK_LIST.read_text().splitlines() if line.strip() and not line.startswith("#")]


def stub(text, name="<text>"):
    """The student's version of a solution file."""
    out, state = [], "code"
    for number, line in enumerate(text.splitlines(keepends=True), 1):
        tag = line.strip()
        if tag == BEGIN:
            if state != "code":
                raise HookError(f"{name}:{number}: BEGIN SOLUTION inside another block")
            state = "solution"
        elif tag == ELSE:
            if state != "solution":
                raise HookError(f"{name}:{number}: ELSE STUB without BEGIN SOLUTION")
            state = "stub"
        elif tag == END:
            if state != "stub":
                raise HookError(f"{name}:{number}: END SOLUTION without ELSE STUB")
            state = "code"
        elif state == "code":
            out.append(line)
        elif state == "stub":
            match = re.match(r"^(\s*)// ?(.*)$", line.rstrip("\n"))
            if not match:
                raise HookError(f"{name}:{number}: stub lines must be commented out in the solution")
            out.append(match.group(1) + match.group(2) + "\n")
    if state != "code":
        raise HookError(f"{name}: a solution block is not closed")
    return "".join(out)


def expected_assignments():
    return {f: stub((SOLUTIONS / f).read_text(), f"solutions/{f}") for f in hook_files()}


def check():
    drifted = []
    for name, text in expected_assignments().items():
        path = ASSIGNMENTS / name
        if not path.exists() or path.read_text() != text:
            drifted.append(name)
    if drifted:
        print("assignments/ has drifted from solutions/: " + ", ".join(drifted))
        print("regenerate with: ./lab assignments --write")
        return 1
    print(f"assignments/ matches solutions/ ({len(hook_files())} hook files)")
    return 0


def write(backup):
    changed = []
    for name, text in expected_assignments().items():
        path = ASSIGNMENTS / name
        if path.exists() and path.read_text() != text:
            if backup is None:
                raise HookError("refusing to overwrite changed files without --backup")
            backup.mkdir(parents=True, exist_ok=True)
            shutil.copy2(path, backup / name)
            changed.append(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    if changed:
        print(f"backed up {', '.join(changed)} to {backup}")
    print(f"wrote {len(hook_files())} hook files to assignments/")
    return 0


def load_mutants():
    mutants = []
    for spec in sorted(MUTANTS.glob("*.json")):
        for m in json.loads(spec.read_text()):
            m["spec"] = spec.name
            mutants.append(m)
    names = [m["name"] for m in mutants]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise HookError(f"duplicate mutant names: {', '.join(sorted(dup))}")
    return mutants


def write_mutants(outdir):
    outdir = pathlib.Path(outdir)
    for m in load_mutants():
        target = outdir / m["name"]
        target.mkdir(parents=True, exist_ok=True)
        files = {f: (SOLUTIONS / f).read_text() for f in hook_files()}
        for change in m["changes"]:
            text = files[change["file"]]
            if text.count(change["from"]) != 1:
                raise HookError(
                    f"mutant {m['name']}: the text to replace occurs {text.count(change['from'])} times in "
                    f"solutions/{change['file']} (must be exactly once): {change['from']!r}")
            files[change["file"]] = text.replace(change["from"], change["to"])
        changed = {change["file"] for change in m["changes"]}
        for f, text in files.items():
            # The files the mistake changes lose their markers; the others stay the reference's text
            # byte for byte, so that the build reuses the reference's objects for them (Variants.cmake).
            text = _solution_only(text) if f in changed else text
            path = target / f
            if not path.exists() or path.read_text() != text:
                path.write_text(text)
        print(m["name"])
    return 0


def _solution_only(text):
    """A solution file with the markers and the commented stub removed (what the mutant compiles)."""
    out, state = [], "code"
    for line in text.splitlines(keepends=True):
        tag = line.strip()
        if tag == BEGIN:
            state = "solution"
        elif tag == ELSE:
            state = "stub"
        elif tag == END:
            state = "code"
        elif state != "stub":
            out.append(line)
    return "".join(out)


def existing_file(text):
    """argparse type: the path of a file that exists."""
    if not pathlib.Path(text).is_file():
        raise argparse.ArgumentTypeError(f"expects a file that exists, got '{text}'")
    return pathlib.Path(text)


class OneLineParser(argparse.ArgumentParser):
    """Command-line errors as one line naming the option and what it expects, exit status 2."""

    def error(self, message):
        print(f"error: {message} ({self.prog.split()[0]} -h for help)", file=sys.stderr)
        sys.exit(2)


def main(argv):
    parser = OneLineParser(prog="hooks.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="stub|check|write|mutants|files", required=True,
                                parser_class=OneLineParser)
    sub.add_parser("stub").add_argument("file", type=existing_file)
    sub.add_parser("check")
    sub.add_parser("write").add_argument("--backup", metavar="DIR", type=pathlib.Path)
    sub.add_parser("mutants").add_argument("outdir")
    sub.add_parser("files")
    args = parser.parse_args(argv)
    try:
        if args.command == "stub":
            sys.stdout.write(stub(args.file.read_text(), str(args.file)))
            return 0
        if args.command == "check":
            return check()
        if args.command == "write":
            return write(args.backup)
        if args.command == "mutants":
            return write_mutants(args.outdir)
        print("\n".join(hook_files()))
        return 0
    except (HookError, OSError, json.JSONDecodeError, KeyError) as e:
        print(f"hooks.py: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
