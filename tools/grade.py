#!/usr/bin/env python3
"""The grader: runs the graded GoogleTest tests of an autograder binary, one process per test, and
reports points, hints, Gradescope results.json and JUnit XML.

  grade.py grade --build-dir DIR [--worksheet N] [--solutions | --submission SUBDIR]
                 [--json FILE] [--junit FILE] [--timeout S] [--hidden-visibility V]
      builds the variant (the student's assignments/ by default), grades it, prints the table.
  grade.py grade --build-dir DIR --batch DIR --out FILE.csv [--jobs N] [--worksheet N] [--timeout S]
                [--similarity]
      grades every submission folder in DIR, in parallel, and writes a gradebook (one row per
      submission, one column per test, the total) and FILE-results/NAME/results.json for each.
  grade.py report --binary AUTOGRADER [--worksheet N] [--json FILE] [--junit FILE]
      grades an autograder binary that is already built.
  grade.py prebuild --build-dir DIR
      builds the engine and the tests for grading submissions (Gradescope's setup.sh runs it).
  grade.py failure --json FILE --message TEXT
      writes a results.json with zero points that says why the grading could not run.
  grade.py selfcheck --binary AUTOGRADER (--expect full | --expect zero | --mutant NAME) [--worksheet N]
      the grader's own checks: the solutions score full marks, the stubs zero, and each seeded
      mistake (tests/mutants/*.json) loses points in the test named for it, which fails on its own
      (graded on that test's worksheet unless --worksheet says otherwise).

Exit status: 0 full marks, 1 points lost, 2 the grading itself could not run (a one-line error).

Each test runs in its own process, in a fresh folder, with a time limit (its own, declared with the
test, or --timeout) and an output cap: a crash, a timeout or endless output costs that test only.
A test whose prerequisite fails is "not run". Files of the lab that a test writes into are put
back and the test fails. A submission contributes only its hook files.
"""
import argparse
import concurrent.futures
import csv
import hashlib
import io
import json
import os
import pathlib
import re
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
import similarity  # noqa: E402

DEFAULT_TIMEOUT = 5.0         # s per test; the reference solution needs a few hundredths
OUTPUT_CAP = 1 << 20          # bytes of output a test may print before it is stopped
TRACE_GRACE = 2.0             # s a stopped test gets to write its call stack before it is killed
GTEST_LINE = re.compile(r"^(Note: Google Test filter|\[[ =A-Z-]{10}\])")  # GoogleTest's own lines


class GradeError(Exception):
    """The grading itself cannot go on (bad arguments, missing binary, ...)."""


# ---- Running tests --------------------------------------------------------------------------------

def run_limited(cmd, timeout, cap=OUTPUT_CAP, cwd=None, env=None, warn_signal=None):
    """Runs cmd in its own process group. Returns (returncode, output, why) where why is None or
    'timeout' or 'output'. At a limit the process first gets warn_signal (if given) and
    TRACE_GRACE seconds to report where it was, then the whole group is killed."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=cwd, env=env,
                            start_new_session=True)
    chunks, size, why = [], 0, [None]
    stopped = threading.Event()

    def stop(reason):
        if why[0] is None:
            why[0] = reason
        stopped.set()

    def reader():
        nonlocal size
        while True:
            data = proc.stdout.read1(65536)
            if not data:
                return
            if size < cap:
                chunks.append(data[: cap - size])
            size += len(data)
            if size > cap and not stopped.is_set():
                stop("output")

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    deadline = time.monotonic() + timeout
    while proc.poll() is None and not stopped.is_set():
        try:
            proc.wait(timeout=min(0.05, max(0.0, deadline - time.monotonic())))
        except subprocess.TimeoutExpired:
            pass
        if time.monotonic() >= deadline and proc.poll() is None:
            stop("timeout")
    if stopped.is_set() and proc.poll() is None:
        if warn_signal is not None:
            try:
                os.kill(proc.pid, warn_signal)
                proc.wait(timeout=TRACE_GRACE)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                pass
    try:
        os.killpg(proc.pid, signal.SIGKILL)  # the test and anything it started
    except ProcessLookupError:
        pass
    proc.wait()
    thread.join(timeout=5)
    proc.stdout.close()
    return proc.returncode, b"".join(chunks).decode("utf-8", "replace"), why[0]


def manifest(binary):
    """The graded tests of an autograder binary, checked: dependencies name graded tests, no cycles."""
    binary = pathlib.Path(binary)
    if not binary.is_file():
        raise GradeError(f"autograder binary not found: {binary}")
    rc, out, why = run_limited([str(binary), "--grader-manifest"], timeout=30)
    if rc != 0 or why:
        raise GradeError(f"{binary.name} --grader-manifest failed (exit {rc}): {out.strip()[-300:]}")
    tests = json.loads(out)
    for t in tests:
        t.setdefault("time_limit", 0)
        t.setdefault("depends_on", [])
        t.setdefault("hidden", False)
    return in_dependency_order(tests)


def in_dependency_order(tests):
    """The tests in their declared order, except that each comes after its prerequisites."""
    by_name = {t["name"]: t for t in tests}
    ordered, state = [], {}

    def visit(t, path):
        if state.get(t["name"]) == "done":
            return
        if state.get(t["name"]) == "visiting":
            raise GradeError("graded tests depend on each other in a circle: " + " -> ".join(path + [t["name"]]))
        state[t["name"]] = "visiting"
        for d in t["depends_on"]:
            if d not in by_name:
                raise GradeError(f"{t['name']} depends on {d}, which is not a graded test")
            visit(by_name[d], path + [t["name"]])
        state[t["name"]] = "done"
        ordered.append(t)

    for t in tests:
        visit(t, [])
    return ordered


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


# ---- Which hook was running -----------------------------------------------------------------------

def hook_names():
    """{"integrator": "integrator()", ...}: the hooks, as their stubs announce themselves."""
    names = {}
    for f in hooks.hook_files():
        path = ROOT / "assignments" / f
        if path.is_file():
            text = path.read_text(errors="replace")
            for function in re.findall(r"PhysicsEngine::(\w+)\(", text):
                names[function] = function + "()"
            for hook in re.findall(r'[nN]otImplemented\("([^"]+)"\)', text):
                names[hook.split("(")[0].split("::")[-1]] = hook
    return names


def _demangle(symbols):
    if not symbols or shutil.which("c++filt") is None:
        return symbols
    proc = subprocess.run(["c++filt"], input="\n".join(symbols) + "\n", capture_output=True, text=True)
    out = proc.stdout.splitlines()
    return out if proc.returncode == 0 and len(out) == len(symbols) else symbols


def hook_in_trace(trace, output=""):
    """The student hook whose assert failed, or else the innermost student hook in a call stack
    written by the autograder (graded.cpp); None when neither names one."""
    known = hook_names()
    # glibc's assert: "file:line: void gpl::PhysicsEngine::integrator(): Assertion `...' failed."
    # It names its function exactly, where an optimised call stack may have inlined it away.
    for line in reversed(output.splitlines()):
        m = re.search(r": ([^:]*(?:::[^:(]+)*)\([^)]*\): Assertion", line)
        if m:
            function = m.group(1).split("::")[-1].split()[-1]
            if function in known:
                return known[function]
    symbols = [m.group(1) for m in re.finditer(r"\(([^()+\s]+)\+0x[0-9a-f]+\)", trace)]
    for name in _demangle(symbols):
        function = name.split("(")[0].split("::")[-1]
        if function in known:
            return known[function]
    return None


def _signal_name(number):
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def run_one(binary, test, timeout, guard=None, alone=False):
    """Runs one graded test in its own process. Returns (passed, output, seconds). With a guard, a
    test that writes into the lab's files fails; when other tests ran at the same time, the ones
    that may have written run again, one at a time, so that only the writer is blamed."""
    token = guard.start(alone) if guard else None
    try:
        passed, output, seconds = _run_one(binary, test, timeout)
    finally:
        tampered, suspect = guard.finish(token) if guard else ([], False)
    if suspect and not alone:
        return run_one(binary, test, timeout, guard, alone=True)
    if tampered:
        passed = False
        output = (f"wrote into the lab's own files, which is not allowed (undone): {', '.join(tampered)}\n"
                  + output).strip()
    return passed, output, seconds


SANITIZER_LINE = re.compile(r"^.*(?:: runtime error: |==[0-9]+==ERROR: [A-Za-z]+Sanitizer).*$", re.M)
SANITIZER_MARK = "sanitizer: "


def _run_one(binary, test, timeout):
    with tempfile.TemporaryDirectory(prefix="gpl-grade-") as tmp:
        report_path = pathlib.Path(tmp) / "report.json"
        trace_path = pathlib.Path(tmp) / "trace.txt"
        cmd = [str(binary), f"--gtest_filter={test}", f"--gtest_output=json:{report_path}"]
        env = {**os.environ, "GPL_GRADER_TRACE": str(trace_path)}
        start = time.monotonic()
        rc, out, why = run_limited(cmd, timeout, cwd=tmp, env=env, warn_signal=signal.SIGUSR1)
        seconds = time.monotonic() - start
        passed, output = _verdict(test, rc, out, why, timeout, report_path, trace_path, binary)
        # In a sanitizer build (asan, asan-core), a finding comes first in the message: the
        # self-checks of the solutions and the stubs fail on it even where the test fails anyway.
        found = SANITIZER_LINE.search(out)
        if found:
            passed = False
            output = f"{SANITIZER_MARK}{found.group(0).strip()}\n{output}".strip()
        return passed, output, seconds


def _verdict(test, rc, out, why, timeout, report_path, trace_path, binary):
    trace = trace_path.read_text(errors="replace") if trace_path.exists() else ""
    hook = hook_in_trace(trace, out)
    where = f" in {hook}" if hook else ""
    # The test's own last lines (a failed assert's message, say), without GoogleTest's banner.
    tail = "\n".join([l for l in out.strip().splitlines() if not GTEST_LINE.match(l)][-8:])
    if why == "timeout":
        return False, f"timed out after {timeout:g} s{where} (an endless loop?)"
    if why == "output":
        own = [l for l in out.strip().splitlines() if not GTEST_LINE.match(l)]
        head = "\n".join(own[:6])
        return False, f"printed more than {OUTPUT_CAP // 1024} KiB of output{where} and was stopped; it began:\n{head}"
    if rc < 0:
        name = _signal_name(-rc)
        what = {"SIGABRT": " (abort: a failed assert or an uncaught exception)",
                "SIGFPE": " (an arithmetic error such as an integer division by zero)"}.get(name, "")
        return False, f"crashed with {name}{what}{where}\n{tail}".strip()
    if not report_path.exists():
        return False, f"the test exited with status {rc}{where} before reporting\n{out[-2000:]}".strip()
    report = json.loads(report_path.read_text())
    if report.get("tests", 0) != 1:
        return False, f"test {test} not found in {pathlib.Path(binary).name}"
    failures = _failure_messages(report)
    passed = rc == 0 and not failures
    # The fixture's "hooks still not implemented" note says the most: show it first.
    failures.sort(key=lambda m: not m.startswith("hooks still not implemented"))
    return passed, "\n".join(failures)


def select(tests, worksheet):
    picked = [t for t in tests if worksheet is None or t["worksheet"] == worksheet]
    if not picked:
        raise GradeError(f"no graded tests for worksheet {worksheet}")
    return picked


def grade_binary(binary, worksheet=None, timeout=DEFAULT_TIMEOUT, guard=None):
    """Grades every selected test, prerequisites first. A test whose prerequisite lost its points
    is not run: it scores zero and says which prerequisite to fix first."""
    binary = pathlib.Path(binary).resolve()
    tests = select(manifest(binary), worksheet)
    results = {}
    for t in tests:
        blocked = [d for d in t["depends_on"] if d in results and not results[d]["passed"]]
        if blocked:
            results[t["name"]] = {**t, "passed": False, "not_run": True, "score": 0.0, "seconds": 0.0,
                                  "output": f"not run: depends on {', '.join(blocked)}, which did not pass; fix that first"}
            continue
        limit = t["time_limit"] or timeout
        passed, output, seconds = run_one(binary, t["name"], limit, guard)
        results[t["name"]] = {**t, "passed": passed, "not_run": False, "score": t["points"] if passed else 0.0,
                              "output": output, "seconds": seconds}
    return list(results.values())


def failed_results(tests, message):
    return [{**t, "passed": False, "not_run": False, "score": 0.0, "seconds": 0.0, "output": message}
            for t in tests]


# ---- The lab's own files stay as they are ---------------------------------------------------------

class Guard:
    """Notices when a test writes into the lab's files (what builds and grades: the folders and files
    below), puts them back and keeps what was written in quarantine/ of the build folder. Build
    folders, worksheets and results are not guarded. Thread-safe: parallel graders share one guard."""

    FOLDERS = {"tests", "tools", "framework", "cmake", "assignments", "solutions"}
    FILES = {"CMakeLists.txt", "CMakePresets.json", "lab"}
    SKIP = {".git", "__pycache__"}

    def __init__(self, root, quarantine, skip=()):
        self.root, self.quarantine = pathlib.Path(root), pathlib.Path(quarantine)
        self.skip = [pathlib.Path(s).resolve() for s in skip]
        self.lock = threading.Lock()
        self.files = self._scan()
        self.contents = {p: p.read_bytes() for p in self.files}
        # Tests running now; those that were running when a change was found are suspects and run
        # again alone (no other test at the same time) to find out which one wrote.
        self.cond = threading.Condition()
        self.running, self.suspects, self.alone = set(), set(), None

    def start(self, alone=False):
        token = object()
        with self.cond:
            self.cond.wait_for(lambda: self.alone is None)
            if alone:
                self.alone = token
                self.cond.wait_for(lambda: not self.running)
            self.running.add(token)
        return token

    def finish(self, token):
        """Checks the files after a test. Returns (changed paths, suspect): suspect when the change
        may have come from another test that ran at the same time, so the test must run again alone."""
        with self.cond:
            changed = self.check()
            others = self.running - {token}
            if changed and others:
                self.suspects |= self.running
            suspect = token in self.suspects
            self.suspects.discard(token)
            self.running.discard(token)
            if self.alone is token:
                self.alone = None
            self.cond.notify_all()
        return changed, suspect

    def _skipped(self, path):
        if path.name in self.SKIP or path.name.startswith("build") or path.name.startswith("assignments.backup"):
            return True
        return any(path == s or s in path.parents for s in self.skip)

    def _scan(self):
        found = {}
        stack = [self.root]
        while stack:
            folder = stack.pop()
            try:
                entries = list(os.scandir(folder))
            except OSError:
                continue
            for e in entries:
                p = pathlib.Path(e.path)
                if self._skipped(p.resolve() if e.is_symlink() else p):
                    continue
                if e.is_dir(follow_symlinks=False):
                    if folder != self.root or e.name in self.FOLDERS:
                        stack.append(p)
                elif e.is_file(follow_symlinks=False) and (folder != self.root or e.name in self.FILES):
                    st = e.stat(follow_symlinks=False)
                    found[p] = (st.st_mtime_ns, st.st_size)
        return found

    def check(self):
        """Puts back what changed since the last check; returns the changed paths (relative)."""
        with self.lock:
            now = self._scan()
            changed = []
            stamp = self.quarantine / time.strftime("%Y%m%d-%H%M%S")
            for p in sorted(set(now) | set(self.files)):
                if self.files.get(p) == now.get(p):
                    continue
                if p in now and p in self.contents and p.read_bytes() == self.contents[p]:
                    continue  # touched, not changed
                rel = p.relative_to(self.root)
                if p in now:  # what was written is kept aside, never lost
                    (stamp / rel).parent.mkdir(parents=True, exist_ok=True)
                    shutil.move(str(p), str(stamp / rel))
                    del now[p]
                if p in self.contents:
                    p.parent.mkdir(parents=True, exist_ok=True)
                    p.write_bytes(self.contents[p])
                    st = p.stat()
                    now[p] = (st.st_mtime_ns, st.st_size)
                changed.append(str(rel))
            # The next check compares with this scan (and what was put back), never with a later
            # one: a test still running may write after the scan, and that must not go unseen.
            self.files = now
            return changed


# ---- Reports --------------------------------------------------------------------------------------

def status_word(r):
    return "pass" if r["passed"] else ("not run" if r.get("not_run") else "FAIL")


def table(results, title):
    width = max(len(r["name"]) for r in results)
    lines = [title, f"{'test':<{width}}  {'points':>9}  result"]
    for r in results:
        lines.append(f"{r['name']:<{width}}  {r['score']:>4g} / {r['points']:<2g}  {status_word(r)}")
        if r.get("not_run"):
            lines.append(f"{'':<{width}}    | {r['output']}")
        elif not r["passed"]:
            lines.append(f"{'':<{width}}    hint: {r['hint']}")
            for line in r["output"].splitlines()[:6]:
                lines.append(f"{'':<{width}}    | {line}")
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    passed = sum(r["passed"] for r in results)
    not_run = sum(bool(r.get("not_run")) for r in results)
    lines.append(f"total: {total:g} / {maximum:g} points ({passed} of {len(results)} tests passed)")
    lines.append(f"{passed} passed, {len(results) - passed} failed" + (f" ({not_run} not run)" if not_run else ""))
    return "\n".join(lines)


def gradescope(results, seconds, hidden_visibility="after_published", notes=""):
    tests = []
    for r in results:
        if r["passed"]:
            output = "passed"
        elif r.get("not_run"):
            output = r["output"]
        else:
            output = f"{r['output']}\nhint: {r['hint']}".strip()
        tests.append({"name": r["name"], "score": r["score"], "max_score": r["points"],
                      "status": "passed" if r["passed"] else "failed", "output": output,
                      "visibility": hidden_visibility if r.get("hidden") else "visible"})
    # The grader's own printout repeats hidden tests' names and messages: students never see it.
    stdout = "hidden" if any(r.get("hidden") for r in results) else "visible"
    data = {"score": sum(r["score"] for r in results), "max_score": sum(r["points"] for r in results),
            "execution_time": round(seconds, 3), "visibility": "visible", "stdout_visibility": stdout,
            "tests": tests}
    if notes:
        data["output"] = notes
    return data


def junit(results, label):
    suites = ET.Element("testsuites", name=f"Game Physics Lab autograder ({label})")
    for ws in sorted({r["worksheet"] for r in results}):
        rs = [r for r in results if r["worksheet"] == ws]
        suite = ET.SubElement(suites, "testsuite", name=f"worksheet{ws}", tests=str(len(rs)),
                              failures=str(sum(not r["passed"] and not r.get("not_run") for r in rs)),
                              skipped=str(sum(bool(r.get("not_run")) for r in rs)),
                              time=f"{sum(r['seconds'] for r in rs):.3f}")
        for r in rs:
            case = ET.SubElement(suite, "testcase", classname=r["name"].split(".")[0],
                                 name=r["name"].split(".", 1)[1], time=f"{r['seconds']:.3f}")
            ET.SubElement(case, "properties").append(
                ET.Element("property", name="points", value=f"{r['score']:g}/{r['points']:g}"))
            if r.get("not_run"):
                ET.SubElement(case, "skipped", message=r["output"])
            elif not r["passed"]:
                failure = ET.SubElement(case, "failure", message=r["hint"])
                failure.text = r["output"]
    return ET.tostring(suites, encoding="unicode", xml_declaration=True)


def write_atomically(path, text):
    """Writes the whole file or nothing: a temporary file beside it, then a rename."""
    path = pathlib.Path(path)
    if not path.parent.is_dir():
        raise GradeError(f"cannot write {path}: the folder {path.parent} does not exist")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    except OSError as e:
        raise GradeError(f"cannot write {path}: {e.strerror}") from e
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as e:
        pathlib.Path(tmp).unlink(missing_ok=True)
        raise GradeError(f"cannot write {path}: {e.strerror}") from e


def check_writable(path):
    if path is None:
        return
    path = pathlib.Path(path)
    if path.is_dir():
        raise GradeError(f"cannot write {path}: it is a folder")
    parent = path.resolve().parent
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise GradeError(f"cannot write {path}: the folder {parent} does not exist or is not writable")


def report(results, label, args, seconds, notes=""):
    print(table(results, f"Game Physics Lab autograder: {label}"
                + (f", worksheet {args.worksheet}" if args.worksheet else "")))
    if args.json:
        write_atomically(args.json, json.dumps(gradescope(results, seconds, args.hidden_visibility, notes), indent=2) + "\n")
        print(f"wrote {args.json}")
    if args.junit:
        write_atomically(args.junit, junit(results, label))
        print(f"wrote {args.junit}")
    full = all(r["passed"] for r in results)
    return 0 if full else 1


# ---- Building variants ----------------------------------------------------------------------------

def cmake_build(build_dir, targets, jobs=None, keep_going=False):
    cmd = ["cmake", "--build", str(build_dir)]
    for t in targets:
        cmd += ["--target", t]
    if jobs:
        cmd += ["-j", str(jobs)]
    if keep_going:
        cmd += ["--", "-k", "0"]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return proc.returncode == 0, proc.stdout


def first_errors(log, limit=20):
    lines = [l for l in log.splitlines() if "error" in l.lower() or l.startswith(" ")]
    picked = [l for l in lines if "error:" in l][:limit] or lines[:limit]
    return "\n".join(picked)


def prepare_submission(source, hooks_dir):
    """Copies the hook files of a submission into hooks_dir. Files the submission lacks are taken
    from the untouched stubs; everything else in it is ignored. Returns (missing, ignored)."""
    folder = source = pathlib.Path(source)
    if not source.is_dir():
        raise GradeError(f"submission folder not found: {source}")
    names = hooks.hook_files()
    present = [n for n in names if (source / n).is_file()]
    if not present and any((source / "assignments" / n).is_file() for n in names):
        source = source / "assignments"  # a whole copy of the lab: its assignments/ is the submission
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
    taken = {source / n for n in names}
    ignored = sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() and p not in taken)
    return missing, ignored


class Submission:
    """One submission folder: its hook files, the variant that builds them and its results."""

    def __init__(self, name, folder):
        self.name, self.folder = name, pathlib.Path(folder)
        self.error = None            # why it cannot be graded at all (no hook files, ...)
        self.build_errors = None     # the compiler's first errors
        self.missing, self.ignored = [], []
        self.variant = None
        self.results = None
        self.seconds = 0.0

    def notes(self):
        """What the student should know besides the tests: files not graded."""
        lines = []
        if self.missing:
            lines.append(f"not in the submission, graded as the untouched stub: {', '.join(self.missing)}")
        if self.ignored:
            lines.append(f"ignored (only hook files are graded): {', '.join(self.ignored[:20])}"
                         + (f" and {len(self.ignored) - 20} more" if len(self.ignored) > 20 else ""))
        return "\n".join(lines)


def stage_submissions(subs, sub_build):
    """Puts the hook files of each submission into SUB_BUILD/submissions/HASH (identical submissions
    share a folder, and so one build). Sets sub.variant; sub.error for folders without hook files."""
    root = sub_build / "submissions"
    root.mkdir(parents=True, exist_ok=True)
    for sub in subs:
        with tempfile.TemporaryDirectory(dir=sub_build) as tmp:
            try:
                sub.missing, sub.ignored = prepare_submission(sub.folder, pathlib.Path(tmp))
            except (GradeError, OSError) as e:
                sub.error = str(e)
                continue
            digest = hashlib.sha256()
            for n in hooks.hook_files():
                digest.update(n.encode() + b"\0" + (pathlib.Path(tmp) / n).read_bytes() + b"\0")
            sub.variant = digest.hexdigest()[:16]
            target = root / sub.variant
            if not target.exists():
                shutil.copytree(tmp, target)


def configure_submission_build(sub_build):
    cache = sub_build / "CMakeCache.txt"
    wanted = f"GPL_SUBMISSIONS_DIR:PATH={sub_build / 'submissions'}"
    if cache.exists() and wanted in cache.read_text(errors="replace"):
        return
    proc = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(sub_build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                           f"-DGPL_SUBMISSIONS_DIR={sub_build / 'submissions'}"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        raise GradeError("could not configure the submission build: " + first_errors(proc.stdout, 3))


def build_submissions(subs, sub_build, jobs):
    """Builds the autograder of every distinct variant in one build (the engine once, each variant's
    hook files once); a variant that does not compile gets its own first errors."""
    variants = sorted({s.variant for s in subs if s.variant})
    if not variants:
        return
    configure_submission_build(sub_build)
    targets = [f"autograder_submission_{v}" for v in variants]
    ok, _ = cmake_build(sub_build, targets, jobs, keep_going=True)
    errors = {}
    if not ok:
        for v, target in zip(variants, targets):
            ok_one, log = cmake_build(sub_build, [target])
            if not ok_one:
                errors[v] = log
        if not errors:
            raise GradeError("the submission build fails for a reason outside the submissions; see "
                             f"cmake --build {sub_build}")
    for s in subs:
        if s.variant in errors:
            log = errors[s.variant].replace(str(sub_build / "submissions" / s.variant), str(s.folder))
            s.build_errors = first_errors(log) or log.strip()[-2000:]


def reference_tests(build_dir, worksheet, avoid):
    """The graded tests as a variant that builds lists them (the list is the same in every variant):
    used when the code being graded does not compile."""
    candidates = [v for v in ("solutions", "assignments") if v != avoid]
    if not (ROOT / "solutions").is_dir() and "solutions" in candidates:
        candidates.remove("solutions")
    for v in candidates:
        ok, _ = cmake_build(build_dir, [f"autograder_{v}"])
        if ok:
            return select(manifest(build_dir / "tests" / f"autograder_{v}"), worksheet)
    raise GradeError("no variant of the autograder builds, so the tests cannot be listed")


def grade_submission(sub, args, sub_build, guard, reference):
    start = time.monotonic()
    if sub.error:
        sub.results = failed_results(reference(), sub.error)
    elif sub.build_errors is not None:
        sub.results = failed_results(reference(), "the submission does not compile:\n" + sub.build_errors)
    else:
        binary = sub_build / "tests" / f"autograder_submission_{sub.variant}"
        sub.results = grade_binary(binary, args.worksheet, args.timeout, guard)
    sub.seconds = time.monotonic() - start
    return sub


# ---- Commands -------------------------------------------------------------------------------------

def submission_build_dir(build_dir):
    return build_dir.parent / (build_dir.name + "-submission")


def cmd_grade(args):
    if args.batch:
        return cmd_batch(args)
    if args.similarity:
        raise GradeError("--similarity goes with --batch")
    if args.out:
        raise GradeError("--out goes with --batch")
    check_writable(args.json)
    check_writable(args.junit)
    build_dir = pathlib.Path(args.build_dir).resolve()
    start = time.monotonic()
    guard = Guard(ROOT, build_dir / "quarantine", skip=[p for p in (args.json, args.junit) if p])
    if args.submission:
        label = f"submission {args.submission}"
        sub_build = submission_build_dir(build_dir)
        sub = Submission(pathlib.Path(args.submission).name, args.submission)
        stage_submissions([sub], sub_build)
        if sub.error:
            raise GradeError(sub.error)
        if sub.notes():
            print(sub.notes())
        build_submissions([sub], sub_build, None)
        if sub.build_errors is not None:
            print("the code does not compile; every test scores zero. First errors:\n" + sub.build_errors)
        grade_submission(sub, args, sub_build, guard, lambda: reference_tests(sub_build, args.worksheet, None))
        return report(sub.results, label, args, time.monotonic() - start, sub.notes())
    if args.solutions and not (ROOT / "solutions").is_dir():
        raise GradeError("this is a student release: it has no solutions to grade")
    variant = "solutions" if args.solutions else "assignments"
    ok, log = cmake_build(build_dir, [f"autograder_{variant}"])
    if not ok:
        if args.solutions:
            raise GradeError("the reference solutions do not build: " + first_errors(log, 1))
        tests = reference_tests(build_dir, args.worksheet, variant)
        print("the code does not compile; every test scores zero. First errors:\n" + first_errors(log))
        results = failed_results(tests, "the code does not compile:\n" + first_errors(log))
        return report(results, variant, args, time.monotonic() - start)
    results = grade_binary(build_dir / "tests" / f"autograder_{variant}", args.worksheet, args.timeout, guard)
    return report(results, variant, args, time.monotonic() - start)


class Progress:
    """One line on the terminal ("grading: 12 of 50 submissions, 3 running"), or a line per
    finished submission when the output is not a terminal."""

    def __init__(self, total, stream=sys.stderr):
        self.total, self.stream, self.done, self.running = total, stream, 0, 0
        self.tty = stream.isatty()
        self.lock = threading.Lock()

    def say(self, text):
        with self.lock:
            if self.tty:
                self.stream.write(f"\r\033[K{text}")
            else:
                self.stream.write(text + "\n")
            self.stream.flush()

    def started(self):
        with self.lock:
            self.running += 1

    def finished(self, sub):
        with self.lock:
            self.done += 1
            self.running -= 1
            done, running = self.done, self.running
        total = sum(r["score"] for r in sub.results)
        maximum = sum(r["points"] for r in sub.results)
        self.say(f"grading: {done} of {self.total} submissions done, {running} running "
                 f"(last: {sub.name} {total:g}/{maximum:g})")

    def end(self):
        if self.tty:
            self.stream.write("\n")


def gradebook(subs):
    names = [r["name"] for r in subs[0].results]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["submission", *names, "total", "max_score", "note"])
    for s in subs:
        scores = {r["name"]: r["score"] for r in s.results}
        notes = [s.error or ("does not compile" if s.build_errors is not None else "")]
        if s.missing:
            notes.append("graded as the untouched stub: " + " ".join(s.missing))
        if s.ignored:
            notes.append("ignored: " + " ".join(s.ignored[:5]) + (" ..." if len(s.ignored) > 5 else ""))
        note = "; ".join(n for n in notes if n)
        w.writerow([s.name, *(f"{scores[n]:g}" for n in names), f"{sum(scores.values()):g}",
                    f"{sum(r['points'] for r in s.results):g}", note])
    return out.getvalue()


def cmd_batch(args):
    if args.submission or args.solutions or args.json or args.junit:
        raise GradeError("--batch grades folders of submissions: use --out FILE.csv, not --submission, "
                         "--solutions, --json or --junit")
    if not args.out:
        raise GradeError("--batch needs --out FILE.csv (the gradebook)")
    if args.similarity and shutil.which(similarity.SIM) is None:
        raise GradeError("--similarity needs sim_c from the Debian package similarity-tester "
                         "(./lab installs it; or: apt-get install similarity-tester)")
    batch = pathlib.Path(args.batch)
    if not batch.is_dir():
        raise GradeError(f"batch folder not found: {batch}")
    out = pathlib.Path(args.out)
    check_writable(out)
    results_dir = out.parent / (out.stem + "-results")
    if results_dir.exists() and not results_dir.is_dir():
        raise GradeError(f"cannot write the results folder {results_dir}: a file of that name exists")
    folders = sorted(p for p in batch.iterdir() if p.is_dir() and not p.name.startswith("."))
    skipped = sorted(p.name for p in batch.iterdir() if not p.is_dir())
    if not folders:
        raise GradeError(f"batch folder {batch} holds no submission folders")
    if skipped:
        print(f"not submission folders, skipped: {', '.join(skipped)}", file=sys.stderr)
    jobs = args.jobs or os.cpu_count() or 1
    build_dir = pathlib.Path(args.build_dir).resolve()
    sub_build = submission_build_dir(build_dir)
    start = time.monotonic()

    subs = [Submission(p.name, p) for p in folders]
    stage_submissions(subs, sub_build)
    distinct = len({s.variant for s in subs if s.variant})
    print(f"grading {len(subs)} submissions ({distinct} distinct) with {jobs} jobs", file=sys.stderr)
    build_submissions(subs, sub_build, os.cpu_count())  # compiling uses every core whatever --jobs says
    reference_cache, reference_lock = [], threading.Lock()

    def reference():
        with reference_lock:
            if not reference_cache:
                reference_cache.append(reference_tests(sub_build, args.worksheet, None))
        return reference_cache[0]

    if any(s.error or s.build_errors is not None for s in subs):
        reference()
    guard = Guard(ROOT, build_dir / "quarantine", skip=[out, results_dir, batch])
    results_dir.mkdir(exist_ok=True)
    progress = Progress(len(subs))

    def work(sub):
        progress.started()
        grade_submission(sub, args, sub_build, guard, reference)
        (results_dir / sub.name).mkdir(exist_ok=True)
        write_atomically(results_dir / sub.name / "results.json",
                         json.dumps(gradescope(sub.results, sub.seconds, args.hidden_visibility, sub.notes()),
                                    indent=2) + "\n")
        progress.finished(sub)
        return sub

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(work, subs))
    progress.end()
    write_atomically(out, gradebook(subs))
    if args.similarity:
        staged = {s.name: sub_build / "submissions" / s.variant for s in subs if s.variant}
        try:
            rows = similarity.compare(staged, hooks.hook_files(), ROOT / "assignments")
        except similarity.SimilarityError as e:
            raise GradeError(str(e)) from None
        similarity.write_csv(rows, out.parent / (out.stem + "-similarity.csv"))
        print(similarity.summary(rows))
    full = sum(all(r["passed"] for r in s.results) for s in subs)
    print(f"graded {len(subs)} submissions in {time.monotonic() - start:.1f} s: {full} with full marks; "
          f"wrote {out} and {results_dir}/NAME/results.json")
    return 0 if full == len(subs) else 1


def cmd_prebuild(args):
    """Builds what grading a submission needs besides the submission: the engine, the tests and the
    untouched stubs' autograder (it lists the tests when a submission does not compile)."""
    sub_build = submission_build_dir(pathlib.Path(args.build_dir).resolve())
    (sub_build / "submissions").mkdir(parents=True, exist_ok=True)
    configure_submission_build(sub_build)
    ok, log = cmake_build(sub_build, ["autograder_assignments"])
    if not ok:
        raise GradeError("the lab does not build: " + first_errors(log, 3))
    print(f"built the engine and the tests in {sub_build}")
    return 0


def cmd_failure(args):
    """A results.json that says why the grading could not run (Gradescope shows it to the student)."""
    data = {"score": 0, "output": "The submission could not be graded: " + args.message.strip(),
            "visibility": "visible", "stdout_visibility": "visible", "tests": []}
    write_atomically(args.json, json.dumps(data, indent=2) + "\n")
    return 0


def cmd_report(args):
    check_writable(args.json)
    check_writable(args.junit)
    start = time.monotonic()
    results = grade_binary(args.binary, args.worksheet, args.timeout)
    return report(results, pathlib.Path(args.binary).name, args, time.monotonic() - start)


def cmd_selfcheck(args):
    spec = None
    if args.mutant:
        specs = {m["name"]: m for m in hooks.load_mutants()}
        if args.mutant not in specs:
            raise GradeError(f"unknown seeded mistake '{args.mutant}'; known: {', '.join(sorted(specs))}")
        spec = specs[args.mutant]
        named = next((t for t in manifest(args.binary) if t["name"] == spec["must_fail"]), None)
        if named is None:
            raise GradeError(f"seeded mistake '{args.mutant}' names the test {spec['must_fail']}, which does not exist")
        if args.worksheet is None:
            args.worksheet = named["worksheet"]  # the other worksheets' tests would only take time
    results = grade_binary(args.binary, args.worksheet, args.timeout)
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    failed = [r["name"] for r in results if not r["passed"]]
    flagged = [r["name"] for r in results if r["output"].startswith(SANITIZER_MARK)]
    print(table(results, f"self-check of {pathlib.Path(args.binary).name}"))
    if flagged and args.expect in ("full", "zero"):
        print(f"WRONG: a sanitizer reported an error in {', '.join(flagged)}")
        return 1
    if args.expect == "full":
        ok = total == maximum and not failed
        print("OK: full marks" if ok else f"WRONG: the reference solutions lose points in {', '.join(failed)}")
    elif args.expect == "zero":
        ok = total == 0
        passed = [r["name"] for r in results if r["passed"]]
        print("OK: the untouched stubs score zero" if ok else
              f"WRONG: the untouched stubs earn points in {', '.join(passed)}: those tests cannot fail")
    else:
        named = next((r for r in results if r["name"] == spec["must_fail"]), None)
        if named is None:
            raise GradeError(f"--worksheet {args.worksheet} leaves out {spec['must_fail']}, the test named for "
                             f"seeded mistake '{args.mutant}'")
        # The named test must lose its points in the graded run (failed or not run) AND fail when run
        # on its own: a prerequisite catching the mistake must not hide a test that cannot.
        alone, output, _ = run_one(pathlib.Path(args.binary).resolve(), spec["must_fail"],
                                   named["time_limit"] or args.timeout)
        ok = not named["passed"] and named["score"] == 0 and total < maximum and not alone
        if ok:
            print(f"OK: '{spec['mistake']}' is caught by {spec['must_fail']}"
                  + (" (which is not run in grading: a prerequisite catches it first)" if named.get("not_run") else ""))
        elif named["passed"] or named["score"]:
            print(f"WRONG: '{spec['mistake']}' is not caught by {spec['must_fail']}")
        else:
            print(f"WRONG: '{spec['mistake']}' loses {spec['must_fail']} only through a prerequisite; "
                  "run on its own the test passes, so it cannot catch the mistake")
    return 0 if ok else 1


class OneLineParser(argparse.ArgumentParser):
    """Usage errors as one line ("error: ..."), exit status 2."""

    def error(self, message):
        print(f"error: {message} ({self.prog.split()[0]} -h for help)", file=sys.stderr)
        sys.exit(2)


def main(argv):
    parser = OneLineParser(prog="grade.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)

    def common(p):
        p.add_argument("--worksheet", type=int, help="grade only this worksheet's tests")
        p.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                       help=f"seconds per test unless the test declares its own (default {DEFAULT_TIMEOUT:g})")
        p.add_argument("--hidden-visibility", choices=("hidden", "after_published"), default="after_published",
                       help="Gradescope visibility of hidden tests (default after_published)")

    g = sub.add_parser("grade")
    common(g)
    g.add_argument("--build-dir", required=True)
    which = g.add_mutually_exclusive_group()
    which.add_argument("--solutions", action="store_true", help="grade the reference solutions")
    which.add_argument("--submission", metavar="DIR", help="grade a folder laid out like assignments/")
    which.add_argument("--batch", metavar="DIR", help="grade every submission folder in DIR")
    g.add_argument("--out", metavar="FILE.csv", help="the gradebook of --batch")
    g.add_argument("--jobs", type=int, help="submissions graded at once with --batch (default: one per core)")
    g.add_argument("--similarity", action="store_true",
                   help="with --batch: also compare the hook files across the batch (stub text left out) "
                        "and write FILE-similarity.csv")
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

    b = sub.add_parser("prebuild")
    b.add_argument("--build-dir", required=True)

    f = sub.add_parser("failure")
    f.add_argument("--json", metavar="FILE", required=True)
    f.add_argument("--message", required=True)

    args = parser.parse_args(argv)
    if getattr(args, "timeout", 1) <= 0:
        parser.error("--timeout must be a positive number of seconds")
    if getattr(args, "jobs", None) is not None and args.jobs < 1:
        parser.error("--jobs must be at least 1")
    try:
        return {"grade": cmd_grade, "report": cmd_report, "selfcheck": cmd_selfcheck, "prebuild": cmd_prebuild,
                "failure": cmd_failure}[args.command](args)
    except (GradeError, hooks.HookError) as e:
        print("error: " + "; ".join(line.strip() for line in str(e).splitlines() if line.strip()), file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
