#!/usr/bin/env python3
"""Student releases and the Gradescope autograder, written from the instructor's tree.

  release.py release DIR [--reference-demo]
      the student release: framework, assignments (the stubs, generated from solutions/), public
      tests, worksheets without worksheets/instructor/, bench/ without bench/instructor/, lab,
      cmake/, the grader, and a README for students (docs/student-README.md). No solutions, no
      hidden tests, no seeded mistakes, no instructor notes; it builds on its own. --reference-demo
      adds the reference engine compiled here (reference/: object files and a library, no source),
      so that the release's viewer shows the reference ghost and ./lab run --reference the
      reference's numbers.
  release.py gradescope DIR [--hidden-visibility hidden|after_published]
      the Gradescope autograder: setup.sh, run_autograder and the sources they need (hidden tests
      included, no solutions: grading does not need them), and DIR.zip to upload.
  release.py leaks DIR
      exit 1, naming the files, when DIR holds solution code or hidden tests (the release checks
      itself this way before it is put in place).

DIR must not exist yet, or be an empty folder. Everything is written to a folder beside DIR first
and renamed into place when complete, so a failed run leaves nothing behind.
"""
import argparse
import json
import os
import pathlib
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import hooks  # noqa: E402
from hooks import OneLineParser  # noqa: E402

HIDDEN_SUFFIX = "_hidden_test.cpp"   # tests/autograder/*_hidden_test.cpp hold the hidden tests
HIDDEN_OPTION = "grading::hidden()"

# What a student release holds: these files and folders of the instructor's tree (folders whole,
# minus what EXCLUDED names). Anything new must be added here to reach students.
RELEASED = ["lab", "CMakeLists.txt", "CMakePresets.json", ".clang-format", ".gitignore",
            "cmake", "framework", "bench", "worksheets", "tests/CMakeLists.txt", "tests/framework", "tests/autograder",
            "tests/grading",
            "tools/grade.py", "tools/grading", "tools/headless.py", "tools/hooks.py", "tools/similarity.py"]
# The Gradescope autograder: what builds and grades a submission; worksheets are not needed.
GRADESCOPE = ["lab", "CMakeLists.txt", "CMakePresets.json", "cmake", "framework", "bench", "tests/CMakeLists.txt",
              "tests/framework", "tests/autograder", "tests/grading", "tools/grade.py", "tools/grading", "tools/hooks.py", "tools/similarity.py"]
# Folders inside released ones that are for instructors only.
INSTRUCTORS_ONLY = ("worksheets/instructor", "bench/instructor")
EXCLUDED = {*INSTRUCTORS_ONLY, "__pycache__"}
# The release's README.md: written for students, from this file (the instructors' README stays here).
STUDENT_README = "docs/student-README.md"
# Parts of it between these lines are kept only in a release written with --reference-demo; parts
# between the NO_ variants only in one without.
DEMO_BEGIN, DEMO_END = "<!-- reference-demo -->", "<!-- /reference-demo -->"
NO_DEMO_BEGIN, NO_DEMO_END = "<!-- no-reference-demo -->", "<!-- /no-reference-demo -->"


class ReleaseError(Exception):
    pass


# ---- What must not leak ---------------------------------------------------------------------------

def _solution_lines():
    """Lines of reference code (between BEGIN SOLUTION and ELSE STUB) that say something: longer than
    a brace and not also part of the public engine (framework/), which students have anyway."""
    public = "\n".join(p.read_text(errors="replace") for p in (ROOT / "framework").rglob("*") if p.is_file())
    public_lines = {line.strip() for line in public.splitlines()}
    secret = {}
    for name in hooks.hook_files():
        state = "code"
        for line in (ROOT / "solutions" / name).read_text().splitlines():
            tag = line.strip()
            if tag in (hooks.BEGIN, hooks.ELSE, hooks.END):
                state = {hooks.BEGIN: "solution", hooks.ELSE: "stub", hooks.END: "code"}[tag]
            elif state == "solution" and len(tag) >= 12 and not tag.startswith("//") and tag not in public_lines:
                secret[tag] = f"solutions/{name}"
    return secret


def _hidden_files():
    files = sorted((ROOT / "tests" / "autograder").glob("*" + HIDDEN_SUFFIX))
    for path in (ROOT / "tests" / "autograder").glob("*.cpp"):
        declares_hidden = HIDDEN_OPTION in path.read_text()
        if declares_hidden != (path in files):
            raise ReleaseError(f"tests/autograder/{path.name}: hidden tests (declared with {HIDDEN_OPTION}) go in "
                               f"files named *{HIDDEN_SUFFIX}, and only there")
    for path in files:
        text = path.read_text()
        if text.count("GRADED_TEST(") != text.count(HIDDEN_OPTION):
            raise ReleaseError(f"tests/autograder/{path.name}: every test in a *{HIDDEN_SUFFIX} file must be hidden")
    return files


def _hidden_text():
    """Names, hints and longer lines of the hidden tests: none may appear in a release."""
    hidden = _hidden_files()
    public = "\n".join(p.read_text() for p in (ROOT / "tests" / "autograder").glob("*") if p.is_file() and p not in hidden)
    public += "\n".join(f"{suite}.{name}" for suite, name in re.findall(r"GRADED_TEST\(\s*(\w+)\s*,\s*(\w+)", public))
    secret = {}
    for path in hidden:
        text = path.read_text()
        for suite, name in re.findall(r"GRADED_TEST\(\s*(\w+)\s*,\s*(\w+)", text):
            secret[name] = path.name
        for literal in re.findall(r'"([^"\n]{25,})"', text):
            secret[literal] = path.name
        for line in text.splitlines():
            if len(line.strip()) >= 40 and not line.strip().startswith("#include"):
                secret[line.strip()] = path.name
    return {s: origin for s, origin in secret.items() if s not in public}


def leaks(folder):
    """[(file in folder, what leaked, from where)] for solution code and hidden test text."""
    folder = pathlib.Path(folder)
    secrets = {**_solution_lines(), **_hidden_text()}
    found = []
    for path in sorted(folder.rglob("*")):
        if not path.is_file() or "build" in path.relative_to(folder).parts[:1]:
            continue
        text = path.read_text(errors="replace")
        for secret, origin in secrets.items():
            if secret in text:
                found.append((str(path.relative_to(folder)), secret, origin))
    for forbidden in ("solutions", "tests/mutants", "tests/grader", *INSTRUCTORS_ONLY):
        if (folder / forbidden).exists():
            found.append((forbidden, "the folder itself", forbidden))
    return found


# ---- Writing a tree -------------------------------------------------------------------------------

def _copy(entries, target, skip_hidden):
    hidden = set(_hidden_files()) if skip_hidden else set()
    for entry in entries:
        source = ROOT / entry
        if not source.exists():
            raise ReleaseError(f"{entry} is missing from {ROOT}")
        paths = [source] if source.is_file() else sorted(p for p in source.rglob("*") if p.is_file())
        for path in paths:
            rel = path.relative_to(ROOT)
            if any(str(rel) == e or str(rel).startswith(e + "/") or e in rel.parts for e in EXCLUDED):
                continue
            if path in hidden:
                continue
            (target / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(path, target / rel)


def _write_assignments(target):
    """The stubs, generated from solutions/ (never the instructor's possibly edited assignments/)."""
    for name, text in hooks.expected_assignments().items():
        (target / "assignments" / name).parent.mkdir(parents=True, exist_ok=True)
        (target / "assignments" / name).write_text(text)


def student_readme(demo):
    """The release's README.md: docs/student-README.md with the parts for this release."""
    out, keep = [], True
    for line in (ROOT / STUDENT_README).read_text().splitlines(True):
        tag = line.strip()
        if tag in (DEMO_BEGIN, NO_DEMO_BEGIN):
            keep = demo == (tag == DEMO_BEGIN)
        elif tag in (DEMO_END, NO_DEMO_END):
            keep = True
        elif keep:
            out.append(line)
    return "".join(out)


def _build_reference(tree):
    """--reference-demo: compiles the reference engine in build/reference-demo (kept, so the next
    release compiles only what changed) and puts into tree/reference/ the hook objects of solutions/
    (the variant "reference") and libgpl_reference.a (the viewer's ghost): binaries, no source."""
    build = ROOT / "build" / "reference-demo"
    build.mkdir(parents=True, exist_ok=True)
    log = build / "last-build.log"
    targets = ["gpl_reference"] + ["gpl_hookfile_solutions_" + re.sub(r"\W", "_", f) for f in hooks.hook_files()]
    print("building the reference engine for the demo (a minute or two the first time)", flush=True)
    with open(log, "w") as out:
        for cmd in (["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                     "-DGPL_BUILD_TESTS=OFF", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON"],
                    ["cmake", "--build", build, "--", "-j", str(os.cpu_count() or 1), *targets]):
            if subprocess.run([str(c) for c in cmd], stdout=out, stderr=subprocess.STDOUT).returncode != 0:
                raise ReleaseError(f"the reference engine did not build; the log is {log}")
    # Each hook file of solutions/ is an object library of its own (cmake/Variants.cmake): its object
    # file is the -o of its compile command.
    commands = json.loads((build / "compile_commands.json").read_text())
    outputs = [re.search(r" -o (\S+)", c["command"]) for c in commands]
    objects = sorted({pathlib.Path(c["directory"], o.group(1)) for c, o in zip(commands, outputs)
                      if o and "/gpl_hookfile_solutions_" in "/" + o.group(1)})
    if len(objects) != len(hooks.hook_files()):
        raise ReleaseError(f"expected {len(hooks.hook_files())} reference hook objects in {build}, found {len(objects)}")
    (tree / "reference" / "hooks").mkdir(parents=True)
    for obj in objects:
        shutil.copy2(obj, tree / "reference" / "hooks" / obj.name)
    shutil.copy2(build / "framework" / "viewer" / "libgpl_reference.a", tree / "reference" / "libgpl_reference.a")


def _packages():
    """The Debian packages of lab's PACKAGES list (one list for lab and the autograder)."""
    text = (ROOT / "lab").read_text()
    block = re.search(r"^PACKAGES=\((.*?)^\)", text, re.S | re.M)
    if not block:
        raise ReleaseError("cannot find the PACKAGES list in lab")
    return [w for line in block.group(1).splitlines() for w in line.split("#")[0].split()]


def _executable(path, text):
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)


SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image: it installs the Debian
# packages the lab needs (those missing) and builds the checker (the graded tests), the launcher and
# the engine's parts, so that grading a submission compiles only the submission's hook files (in
# the sandbox) and links its engine.
set -euo pipefail
cd "$(dirname "${{BASH_SOURCE[0]}}")"
packages=({packages})
missing=()
for p in "${{packages[@]}}"; do
  dpkg-query -W -f='${{Status}}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${{#missing[@]}} -gt 0 ]]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${{missing[@]}}"
fi
# Debian's python3, the one installed above, before any other on PATH (a pyenv shim costs seconds).
PYTHON=python3
[[ -x /usr/bin/python3 ]] && PYTHON=/usr/bin/python3
"$PYTHON" tools/grade.py prebuild --build-dir build/release
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Gradescope runs this for each submission: the student's files in $AUTOGRADER/submission (the hook
# files, at the top or in assignments/), the results in $AUTOGRADER/results/results.json.
# AUTOGRADER is /autograder unless GPL_AUTOGRADER_ROOT says otherwise (the lab's tests use a
# temporary folder). Hidden tests are shown to students: {visibility}.
set -uo pipefail
AUTOGRADER="${{GPL_AUTOGRADER_ROOT:-/autograder}}"
SOURCE="$AUTOGRADER/source"
RESULTS="$AUTOGRADER/results/results.json"
mkdir -p "$AUTOGRADER/results"
PYTHON=python3
[[ -x /usr/bin/python3 ]] && PYTHON=/usr/bin/python3
"$PYTHON" "$SOURCE/tools/grade.py" grade --build-dir "$SOURCE/build/release" --submission "$AUTOGRADER/submission" \\
  --json "$RESULTS" --hidden-visibility {visibility} 2>"$AUTOGRADER/results/errors.txt"
status=$?
cat "$AUTOGRADER/results/errors.txt" >&2
if [[ $status -eq 2 ]]; then
  # The grading could not run (no hook files in the submission, ...): zero, and the reason.
  "$PYTHON" "$SOURCE/tools/grade.py" failure --json "$RESULTS" --message "$(head -c 2000 "$AUTOGRADER/results/errors.txt")"
fi
exit 0
"""


def _in_place(target, fill):
    """Fills a fresh folder beside target, then renames it to target: all or nothing."""
    target = pathlib.Path(target).resolve()
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        raise ReleaseError(f"{target} already exists and is not an empty folder")
    if target == ROOT or ROOT in target.parents:
        raise ReleaseError(f"{target} is inside the lab ({ROOT}); write it elsewhere")
    if not target.parent.is_dir() or not os.access(target.parent, os.W_OK):
        raise ReleaseError(f"cannot write {target}: the folder {target.parent} does not exist or is not writable")
    staging = pathlib.Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        fill(staging)
        staging.chmod(0o755)
        if target.exists():
            target.rmdir()
        staging.rename(target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def release(target, demo=False):
    def fill(tree):
        _copy(RELEASED, tree, skip_hidden=True)
        _write_assignments(tree)
        (tree / "README.md").write_text(student_readme(demo))
        if demo:
            _build_reference(tree)
        found = leaks(tree)
        if found:
            where, what, origin = found[0]
            raise ReleaseError(f"the release would leak {origin} into {where}: {what!r}")
    _in_place(target, fill)
    print(f"wrote the student release to {target}: no solutions, no hidden tests, no seeded mistakes" +
          ("; the reference engine compiled, for the ghost and ./lab run --reference" if demo else ""))
    return 0


def gradescope(target, visibility):
    zip_path = pathlib.Path(str(pathlib.Path(target).resolve()) + ".zip")
    if zip_path.exists():
        raise ReleaseError(f"{zip_path} already exists")

    def fill(tree):
        _copy(GRADESCOPE, tree, skip_hidden=False)
        _write_assignments(tree)
        _executable(tree / "setup.sh", SETUP.format(packages=" ".join(_packages())))
        _executable(tree / "run_autograder", RUN_AUTOGRADER.format(visibility=visibility))
        solution = [(w, s) for w, s, _ in leaks(tree) if s in _solution_lines() or w == "solutions"]
        if solution:
            raise ReleaseError(f"the autograder would hold solution code in {solution[0][0]}")
        tmp_zip = zip_path.with_name(f".{zip_path.name}.partial")
        with zipfile.ZipFile(tmp_zip, "w", zipfile.ZIP_DEFLATED) as z:
            for path in sorted(tree.rglob("*")):
                if path.is_file():
                    info = zipfile.ZipInfo.from_file(path, str(path.relative_to(tree)))
                    with open(path, "rb") as f:
                        z.writestr(info, f.read(), zipfile.ZIP_DEFLATED)
        tmp_zip.rename(zip_path)

    try:
        _in_place(target, fill)
    except BaseException:
        zip_path.unlink(missing_ok=True)
        raise
    print(f"wrote the Gradescope autograder to {target} and {zip_path} (upload the zip); "
          f"hidden tests: {visibility}")
    return 0


def existing_folder(text):
    """argparse type: a folder that exists."""
    if not pathlib.Path(text).is_dir():
        raise argparse.ArgumentTypeError(f"expects a folder that exists, got '{text}'")
    return text


def main(argv):
    parser = OneLineParser(prog="release.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="release|gradescope|leaks", required=True,
                                parser_class=OneLineParser)
    r = sub.add_parser("release")
    r.add_argument("dir")
    r.add_argument("--reference-demo", action="store_true",
                   help="add the reference engine compiled (no source): the viewer's ghost and ./lab run --reference")
    g = sub.add_parser("gradescope")
    g.add_argument("dir")
    g.add_argument("--hidden-visibility", choices=("hidden", "after_published"), default="after_published",
                   help="when students see the hidden tests' results: never, or once grades are published")
    sub.add_parser("leaks").add_argument("dir", type=existing_folder)
    args = parser.parse_args(argv)
    try:
        if not (ROOT / "solutions").is_dir():
            raise ReleaseError("this is a student release: releases are written from the instructor's tree")
        if args.command == "release":
            return release(args.dir, args.reference_demo)
        if args.command == "gradescope":
            return gradescope(args.dir, args.hidden_visibility)
        found = leaks(args.dir)
        for where, what, origin in found:
            print(f"{where}: {what!r} (from {origin})")
        return 1 if found else 0
    except (ReleaseError, hooks.HookError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
