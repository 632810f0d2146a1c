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
  hooks.py alternatives OUTDIR             write the correct alternatives of tests/alternatives/*.json in rounds
                                           (round k: the k-th alternative of each hook file, its code in
                                           place of the file's solution blocks) as hook directories
                                           OUTDIR/roundK, and print per line the round, the earliest
                                           worksheet of its files and its alternatives' names
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
ALTERNATIVES = ROOT / "tests" / "alternatives"
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


def _load_specs(folder, kind):
    """The entries of every folder/*.json, each with "spec" set to its file's name; names unique."""
    entries = []
    for spec in sorted(folder.glob("*.json")):
        try:
            listed = json.loads(spec.read_text())
        except json.JSONDecodeError as e:
            raise HookError(f"{spec.name}: not valid JSON: {e}") from None
        if not isinstance(listed, list):
            raise HookError(f"{spec.name}: expects a list of {kind}s")
        for number, entry in enumerate(listed, 1):
            if not isinstance(entry, dict) or not isinstance(entry.get("name"), str) or not entry["name"]:
                raise HookError(f"{spec.name}: {kind} {number} has no name")
            entries.append({**entry, "spec": spec.name})
    names = [e["name"] for e in entries]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise HookError(f"duplicate {kind} names: {', '.join(sorted(dup))}")
    return entries


def load_mutants():
    return _load_specs(MUTANTS, "mutant")


def load_alternatives():
    """The correct alternatives: each replaces the solution blocks of one hook file with its own code
    ("code": a string, or for a file with several blocks a list of strings, one per block in order)."""
    alternatives = _load_specs(ALTERNATIVES, "alternative")
    files = hook_files()
    for alt in alternatives:
        where = f"{alt['spec']}: alternative {alt['name']}"
        for key in ("why", "file"):
            if not isinstance(alt.get(key), str) or not alt[key].strip():
                raise HookError(f"{where}: '{key}' must be a non-empty string")
        if alt["file"] not in files:
            raise HookError(f"{where}: '{alt['file']}' is not a hook file (cmake/hook_files.txt)")
        code = alt.get("code")
        if isinstance(code, str):
            code = [code]
        if not isinstance(code, list) or not code or not all(isinstance(c, str) and c.strip() for c in code):
            raise HookError(f"{where}: 'code' must be a non-empty string, or a list of them (one per solution block)")
        alt["blocks"] = code
    return alternatives


def write_mutants(outdir):
    for m in load_mutants():
        files = {f: (SOLUTIONS / f).read_text() for f in hook_files()}
        for change in m["changes"]:
            text = files[change["file"]]
            if text.count(change["from"]) != 1:
                raise HookError(
                    f"mutant {m['name']}: the text to replace occurs {text.count(change['from'])} times in "
                    f"solutions/{change['file']} (must be exactly once): {change['from']!r}")
            files[change["file"]] = text.replace(change["from"], change["to"])
        changed = {change["file"] for change in m["changes"]}
        _write_variant(pathlib.Path(outdir) / m["name"], {f: _solution_only(files[f]) for f in changed})
        print(m["name"])
    return 0


def alternative_rounds(alternatives):
    """The alternatives in rounds: round k holds the k-th alternative of each hook file (in the order
    of the specs), so that no round has two of one file. A round is one hook directory with all its
    alternatives in place: each must score full marks beside the others as beside the reference."""
    rounds = []
    for alt in alternatives:
        k = sum(1 for other in alternatives[:alternatives.index(alt)] if other["file"] == alt["file"])
        if k == len(rounds):
            rounds.append([])
        rounds[k].append(alt)
    return rounds


def write_alternatives(outdir):
    alternatives = load_alternatives()
    for alt in alternatives:  # every entry checked before any is written
        alt["text"] = with_blocks((SOLUTIONS / alt["file"]).read_text(), alt["blocks"],
                                  f"alternative {alt['name']} of solutions/{alt['file']}")
        alt["worksheet"] = hook_worksheet(alt["file"])
    # One line per round: its name, the earliest worksheet of its hook files, its alternatives.
    for number, members in enumerate(alternative_rounds(alternatives), 1):
        _write_variant(pathlib.Path(outdir) / f"round{number}", {alt["file"]: alt["text"] for alt in members})
        print(f"round{number}", min(alt["worksheet"] for alt in members), ",".join(alt["name"] for alt in members))
    return 0


def hook_worksheet(file):
    """The worksheet that assigns a hook file, from its first line ("// Worksheet N, assignment ...")."""
    match = re.match(r"// Worksheet (\d+),", (SOLUTIONS / file).read_text())
    if not match:
        raise HookError(f"solutions/{file} does not begin with '// Worksheet N,': no worksheet assigns it")
    return int(match.group(1))


def _write_variant(target, changed):
    """A hook directory: the files in `changed` (name: text) as given; the others stay the reference's
    text byte for byte, so that the build reuses the reference's objects for them (Variants.cmake).
    Files already as they should be are not written again (their objects stay up to date)."""
    target.mkdir(parents=True, exist_ok=True)
    for f in hook_files():
        text = changed[f] if f in changed else (SOLUTIONS / f).read_text()
        path = target / f
        if not path.exists() or path.read_text() != text:
            path.write_text(text)


def with_blocks(text, blocks, name="<text>"):
    """A solution file with the code of each solution block (BEGIN SOLUTION to ELSE STUB) replaced by
    the next of `blocks`, and the markers and the commented stubs removed."""
    count = sum(line.strip() == BEGIN for line in text.splitlines())
    if count != len(blocks):
        raise HookError(f"{name}: the file has {count} solution block(s), the alternative gives {len(blocks)}")
    out, state, blocks = [], "code", iter(blocks)
    for line in text.splitlines(keepends=True):
        tag = line.strip()
        if tag == BEGIN:
            code = next(blocks)
            out.append(code if not code or code.endswith("\n") else code + "\n")
            state = "solution"
        elif tag == ELSE:
            state = "stub"
        elif tag == END:
            state = "code"
        elif state == "code":
            out.append(line)
    return "".join(out)


def solution_blocks(text):
    """The code of each solution block of a solution file (BEGIN SOLUTION to ELSE STUB), in order."""
    blocks, state = [], "code"
    for line in text.splitlines(keepends=True):
        tag = line.strip()
        if tag == BEGIN:
            blocks.append("")
            state = "solution"
        elif tag in (ELSE, END):
            state = "code"
        elif state == "solution":
            blocks[-1] += line
    return blocks


def _solution_only(text):
    """A solution file with the markers and the commented stub removed (what the mutant compiles)."""
    return with_blocks(text, solution_blocks(text))


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
    sub = parser.add_subparsers(dest="command", metavar="stub|check|write|mutants|files|alternatives", required=True,
                                parser_class=OneLineParser)
    sub.add_parser("stub").add_argument("file", type=existing_file)
    sub.add_parser("check")
    sub.add_parser("write").add_argument("--backup", metavar="DIR", type=pathlib.Path)
    sub.add_parser("mutants").add_argument("outdir")
    sub.add_parser("alternatives").add_argument("outdir")
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
        if args.command == "alternatives":
            return write_alternatives(args.outdir)
        print("\n".join(hook_files()))
        return 0
    except (HookError, OSError, json.JSONDecodeError, KeyError) as e:
        print(f"hooks.py: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
