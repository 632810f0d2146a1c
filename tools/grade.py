#!/usr/bin/env python3
"""The grader: runs the graded GoogleTest tests of an autograder binary, one process per test, and
reports points, hints, Gradescope results.json and JUnit XML.

  grade.py grade --build-dir DIR [--worksheet N] [--solutions | --submission SUBDIR]
                 [--json FILE] [--junit FILE] [--timeout S]
      builds the variant (the student's assignments/ by default), grades it, prints the table.
      Exit status: 0 full marks, 1 points lost, 2 the grading itself could not run.
  grade.py report --binary AUTOGRADER [--worksheet N] [--json FILE] [--junit FILE]
      grades an autograder binary that is already built.
  grade.py selfcheck --binary AUTOGRADER (--expect full | --expect zero | --mutant NAME) [--worksheet N]
      the grader's own checks: the solutions score full marks, the stubs zero, and each seeded
      mistake (tests/mutants/*.json) loses points in the test named for it.
"""
import argparse
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import hooks  # noqa: E402

DEFAULT_TIMEOUT = 10.0        # s per test; the reference solution needs well under one
OUTPUT_CAP = 1 << 20          # bytes of output a test may print before it is stopped


class GradeError(Exception):
    """The grading itself cannot go on (bad arguments, missing binary, ...)."""


# ---- Running tests --------------------------------------------------------------------------------

def run_limited(cmd, timeout, cap=OUTPUT_CAP, cwd=None):
    """Runs cmd in its own process group. Returns (returncode, output, why) where why is None or
    'timeout' or 'output'; the process group is killed on either."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=cwd,
                            start_new_session=True)
    chunks, size, why = [], 0, [None]

    def kill(reason):
        if why[0] is None:
            why[0] = reason
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    def reader():
        nonlocal size
        while True:
            data = proc.stdout.read1(65536)
            if not data:
                return
            if size < cap:
                chunks.append(data[: cap - size])
            size += len(data)
            if size > cap:
                kill("output")
                return

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        kill("timeout")
        proc.wait()
    thread.join(timeout=5)
    proc.stdout.close()
    return proc.returncode, b"".join(chunks).decode("utf-8", "replace"), why[0]


def manifest(binary):
    binary = pathlib.Path(binary)
    if not binary.is_file():
        raise GradeError(f"autograder binary not found: {binary}")
    rc, out, why = run_limited([str(binary), "--grader-manifest"], timeout=30)
    if rc != 0 or why:
        raise GradeError(f"{binary} --grader-manifest failed (exit {rc}): {out[-500:]}")
    return json.loads(out)


def _failure_messages(report):
    messages = []
    for suite in report.get("testsuites", []):
        for case in suite.get("testsuite", []):
            for failure in case.get("failures", []):
                text = failure.get("failure", "")
                first, _, rest = text.partition("\n")
                # GoogleTest starts each failure with "file:line"; the student needs the message.
                text = rest if rest and ":" in first and first.split(":")[-1].isdigit() else text
                # ADD_FAILURE() and FAIL() add a bare "Failed" line before the message.
                messages.append(text[len("Failed\n"):] if text.startswith("Failed\n") else text)
    return messages


def run_one(binary, test, timeout):
    """Runs one graded test in its own process. Returns (passed, output)."""
    with tempfile.TemporaryDirectory(prefix="gpl-grade-") as tmp:
        report_path = pathlib.Path(tmp) / "report.json"
        cmd = [str(binary), f"--gtest_filter={test}", f"--gtest_output=json:{report_path}"]
        start = time.monotonic()
        rc, out, why = run_limited(cmd, timeout, cwd=tmp)
        seconds = time.monotonic() - start
        if why == "timeout":
            return False, f"timed out after {timeout:g} s (an endless loop?)", seconds
        if why == "output":
            return False, f"printed more than {OUTPUT_CAP // 1024} KiB of output and was stopped", seconds
        if rc < 0:
            name = signal.Signals(-rc).name if -rc in signal.Signals._value2member_map_ else f"signal {-rc}"
            tail = "\n".join(out.strip().splitlines()[-8:])
            return False, f"crashed with {name}\n{tail}".strip(), seconds
        if not report_path.exists():
            return False, f"the test binary exited with status {rc} before reporting\n{out[-2000:]}".strip(), seconds
        report = json.loads(report_path.read_text())
        if report.get("tests", 0) != 1:
            return False, f"test {test} not found in {binary}", seconds
        failures = _failure_messages(report)
        passed = rc == 0 and not failures
        # The fixture's "hooks still not implemented" note says the most: show it first.
        failures.sort(key=lambda m: not m.startswith("hooks still not implemented"))
        output = "\n".join(failures)
        return passed, output, seconds


def grade_binary(binary, worksheet=None, timeout=DEFAULT_TIMEOUT):
    binary = pathlib.Path(binary).resolve()
    tests = [t for t in manifest(binary) if worksheet is None or t["worksheet"] == worksheet]
    if not tests:
        raise GradeError(f"no graded tests for worksheet {worksheet}")
    results = []
    for t in tests:
        passed, output, seconds = run_one(binary, t["name"], timeout)
        results.append({**t, "passed": passed, "score": t["points"] if passed else 0.0,
                        "output": output, "seconds": seconds})
    return results


def failed_build_results(binary_tests, errors):
    return [{**t, "passed": False, "score": 0.0, "seconds": 0.0,
             "output": "the submission does not compile:\n" + errors} for t in binary_tests]


# ---- Reports --------------------------------------------------------------------------------------

def table(results, title):
    width = max(len(r["name"]) for r in results)
    lines = [title, f"{'test':<{width}}  {'points':>9}  result"]
    for r in results:
        status = "pass" if r["passed"] else "FAIL"
        lines.append(f"{r['name']:<{width}}  {r['score']:>4g} / {r['points']:<2g}  {status}")
        if not r["passed"]:
            lines.append(f"{'':<{width}}    hint: {r['hint']}")
            for line in r["output"].splitlines()[:6]:
                lines.append(f"{'':<{width}}    | {line}")
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    passed = sum(r["passed"] for r in results)
    lines.append(f"total: {total:g} / {maximum:g} points ({passed} of {len(results)} tests passed)")
    lines.append(f"{passed} passed, {len(results) - passed} failed")
    return "\n".join(lines)


def gradescope(results, seconds):
    tests = []
    for r in results:
        output = "passed" if r["passed"] else f"{r['output']}\nhint: {r['hint']}".strip()
        tests.append({"name": r["name"], "score": r["score"], "max_score": r["points"],
                      "status": "passed" if r["passed"] else "failed", "output": output,
                      "visibility": "visible"})
    return {"score": sum(r["score"] for r in results), "max_score": sum(r["points"] for r in results),
            "execution_time": round(seconds, 3), "visibility": "visible", "stdout_visibility": "visible",
            "tests": tests}


def junit(results, label):
    suites = ET.Element("testsuites", name=f"Game Physics Lab autograder ({label})")
    for ws in sorted({r["worksheet"] for r in results}):
        rs = [r for r in results if r["worksheet"] == ws]
        suite = ET.SubElement(suites, "testsuite", name=f"worksheet{ws}", tests=str(len(rs)),
                              failures=str(sum(not r["passed"] for r in rs)),
                              time=f"{sum(r['seconds'] for r in rs):.3f}")
        for r in rs:
            case = ET.SubElement(suite, "testcase", classname=r["name"].split(".")[0],
                                 name=r["name"].split(".", 1)[1], time=f"{r['seconds']:.3f}")
            ET.SubElement(case, "properties").append(
                ET.Element("property", name="points", value=f"{r['score']:g}/{r['points']:g}"))
            if not r["passed"]:
                failure = ET.SubElement(case, "failure", message=r["hint"])
                failure.text = r["output"]
    return ET.tostring(suites, encoding="unicode", xml_declaration=True)


def write_atomically(path, text):
    """Writes the whole file or nothing: a temporary file beside it, then a rename."""
    path = pathlib.Path(path)
    if not path.parent.is_dir():
        raise GradeError(f"cannot write {path}: the folder {path.parent} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        pathlib.Path(tmp).unlink(missing_ok=True)
        raise GradeError(f"cannot write {path}: {e.strerror}") from e


def check_writable(path):
    if path is None:
        return
    parent = pathlib.Path(path).resolve().parent
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise GradeError(f"cannot write {path}: the folder {parent} does not exist or is not writable")


def report(results, label, args, seconds):
    print(table(results, f"Game Physics Lab autograder: {label}"
                + (f", worksheet {args.worksheet}" if args.worksheet else "")))
    if args.json:
        write_atomically(args.json, json.dumps(gradescope(results, seconds), indent=2) + "\n")
        print(f"wrote {args.json}")
    if args.junit:
        write_atomically(args.junit, junit(results, label))
        print(f"wrote {args.junit}")
    full = all(r["passed"] for r in results)
    return 0 if full else 1


# ---- Building a variant ---------------------------------------------------------------------------

def cmake_build(build_dir, target):
    proc = subprocess.run(["cmake", "--build", str(build_dir), "--target", target],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return proc.returncode == 0, proc.stdout


def first_errors(log, limit=20):
    lines = [l for l in log.splitlines() if "error" in l.lower() or l.startswith(" ")]
    picked = [l for l in lines if "error:" in l][:limit] or lines[:limit]
    return "\n".join(picked)


def prepare_submission(source, hooks_dir):
    """Copies the hook files of a submission into hooks_dir. Files the submission lacks are taken
    from the untouched stubs; everything else in it is ignored. Returns (missing, ignored)."""
    source = pathlib.Path(source)
    if not source.is_dir():
        raise GradeError(f"submission folder not found: {source}")
    names = hooks.hook_files()
    present = [n for n in names if (source / n).is_file()]
    if not present:
        raise GradeError(f"submission folder {source} holds none of the hook files ({', '.join(names)})")
    hooks_dir.mkdir(parents=True, exist_ok=True)
    missing = []
    for n in names:
        src = source / n if (source / n).is_file() else ROOT / "assignments" / n
        if src.parent != source:
            missing.append(n)
        text = src.read_bytes()
        dst = hooks_dir / n
        if not dst.exists() or dst.read_bytes() != text:
            dst.write_bytes(text)  # a fresh modification time, so the build sees the change
    ignored = sorted(str(p.relative_to(source)) for p in source.rglob("*")
                     if p.is_file() and str(p.relative_to(source)) not in names)
    return missing, ignored


def configure_submission_build(build_dir, hooks_dir):
    if (build_dir / "CMakeCache.txt").exists():
        return
    proc = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                           f"-DGPL_SUBMISSION_DIR={hooks_dir}"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        raise GradeError("could not configure the submission build:\n" + proc.stdout[-3000:])


def cmd_grade(args):
    check_writable(args.json)
    check_writable(args.junit)
    build_dir = pathlib.Path(args.build_dir).resolve()
    start = time.monotonic()
    if args.submission:
        label = f"submission {args.submission}"
        sub_build = build_dir.parent / (build_dir.name + "-submission")
        hooks_dir = sub_build / "hooks"
        missing, ignored = prepare_submission(args.submission, hooks_dir)
        if missing:
            print(f"not in the submission, graded as the untouched stub: {', '.join(missing)}")
        if ignored:
            print(f"ignored (only hook files are graded): {', '.join(ignored[:20])}"
                  + (f" and {len(ignored) - 20} more" if len(ignored) > 20 else ""))
        configure_submission_build(sub_build, hooks_dir)
        target, build = "autograder_submission", sub_build
    else:
        variant = "solutions" if args.solutions else "assignments"
        label = variant
        target, build = f"autograder_{variant}", build_dir
    ok, log = cmake_build(build, target)
    if args.submission:
        log = log.replace(str(hooks_dir), str(pathlib.Path(args.submission)))
    if not ok:
        if args.submission is None and args.solutions:
            raise GradeError("the reference solutions do not build:\n" + first_errors(log))
        # The tests are the same in every variant: list them from the reference build.
        reference = build_dir / "tests" / "autograder_solutions"
        ok_ref, ref_log = cmake_build(build_dir, "autograder_solutions")
        if not ok_ref:
            raise GradeError("the build fails:\n" + first_errors(log))
        tests = [t for t in manifest(reference) if args.worksheet is None or t["worksheet"] == args.worksheet]
        print("the code does not compile; every test scores zero. First errors:\n" + first_errors(log))
        return report(failed_build_results(tests, first_errors(log)), label, args, time.monotonic() - start)
    binary = build / "tests" / target
    results = grade_binary(binary, args.worksheet, args.timeout)
    return report(results, label, args, time.monotonic() - start)


def cmd_report(args):
    check_writable(args.json)
    check_writable(args.junit)
    start = time.monotonic()
    results = grade_binary(args.binary, args.worksheet, args.timeout)
    return report(results, pathlib.Path(args.binary).name, args, time.monotonic() - start)


def cmd_selfcheck(args):
    results = grade_binary(args.binary, args.worksheet, args.timeout)
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    failed = [r["name"] for r in results if not r["passed"]]
    print(table(results, f"self-check of {pathlib.Path(args.binary).name}"))
    if args.expect == "full":
        ok = total == maximum and not failed
        print("OK: full marks" if ok else f"WRONG: the reference solutions lose points in {', '.join(failed)}")
    elif args.expect == "zero":
        ok = total == 0
        passed = [r["name"] for r in results if r["passed"]]
        print("OK: the untouched stubs score zero" if ok else
              f"WRONG: the untouched stubs earn points in {', '.join(passed)}: those tests cannot fail")
    else:
        specs = {m["name"]: m for m in hooks.load_mutants()}
        if args.mutant not in specs:
            raise GradeError(f"unknown seeded mistake '{args.mutant}'; known: {', '.join(sorted(specs))}")
        must_fail = specs[args.mutant]["must_fail"]
        if must_fail not in {r["name"] for r in results}:
            raise GradeError(f"seeded mistake '{args.mutant}' names the test {must_fail}, which does not exist")
        ok = must_fail in failed and total < maximum
        print(f"OK: '{specs[args.mutant]['mistake']}' is caught by {must_fail}" if ok else
              f"WRONG: '{specs[args.mutant]['mistake']}' is not caught by {must_fail}")
    return 0 if ok else 1


def main(argv):
    parser = argparse.ArgumentParser(prog="grade.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("--worksheet", type=int, help="grade only this worksheet's tests")
        p.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT, help="seconds per test")

    g = sub.add_parser("grade")
    common(g)
    g.add_argument("--build-dir", required=True)
    which = g.add_mutually_exclusive_group()
    which.add_argument("--solutions", action="store_true", help="grade the reference solutions")
    which.add_argument("--submission", metavar="DIR", help="grade a folder laid out like assignments/")
    g.add_argument("--json", metavar="FILE", help="write Gradescope results.json")
    g.add_argument("--junit", metavar="FILE", help="write JUnit XML")

    r = sub.add_parser("report")
    common(r)
    r.add_argument("--binary", required=True)
    r.add_argument("--json", metavar="FILE")
    r.add_argument("--junit", metavar="FILE")

    s = sub.add_parser("selfcheck")
    common(s)
    s.add_argument("--binary", required=True)
    exp = s.add_mutually_exclusive_group(required=True)
    exp.add_argument("--expect", choices=["full", "zero"])
    exp.add_argument("--mutant", metavar="NAME")

    args = parser.parse_args(argv)
    try:
        return {"grade": cmd_grade, "report": cmd_report, "selfcheck": cmd_selfcheck}[args.command](args)
    except (GradeError, hooks.HookError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
