"""Running graded tests: one process per test, limits, and what a failure means (which hook, which limit)."""
import json
import os
import pathlib
import re
import shutil
import signal
import subprocess
import tempfile
import threading
import time

import hooks
from grading import GradeError, sandbox
from grading.sandbox import limits_of

DEFAULT_TIMEOUT = 5.0         # s per test; the reference solution needs a few hundredths
OUTPUT_CAP = 1 << 20          # bytes of output a test may print before it is stopped
TRACE_GRACE = 2.0             # s a stopped test gets to write its call stack before it is killed
GTEST_LINE = re.compile(r"^(Note: Google Test filter|\[[ =A-Z-]{10}\])")  # GoogleTest's own lines
ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


def run_limited(cmd, timeout, cap=OUTPUT_CAP, cwd=None, env=None, warn_signal=None, watch=None):
    """Runs cmd in its own process group. Returns (returncode, output, why) where why is None,
    'timeout', 'output' or what watch(pid) returned: watch is asked every few hundredths of a second
    and names a limit the running command broke (or None). At a limit the processes below cmd first
    get warn_signal (if given) and TRACE_GRACE seconds to report where they were, then every one of
    them is killed."""
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
            proc.wait(timeout=min(0.02, max(0.0, deadline - time.monotonic())))
        except subprocess.TimeoutExpired:
            pass
        if proc.poll() is not None:
            break
        if time.monotonic() >= deadline:
            stop("timeout")
        elif watch is not None:
            broken = watch(proc.pid)
            if broken:
                stop(broken)
    if stopped.is_set() and proc.poll() is None:
        if warn_signal is not None:
            for pid in sandbox.test_processes(proc.pid):
                try:
                    os.kill(pid, warn_signal)
                except ProcessLookupError:
                    pass
            try:
                proc.wait(timeout=TRACE_GRACE)
            except subprocess.TimeoutExpired:
                pass
    for pid in reversed(sandbox.descendants(proc.pid)):  # the test and anything it started
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    try:
        os.killpg(proc.pid, signal.SIGKILL)
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
        for key in ("time_limit", "memory_limit", "thread_limit", "file_limit"):
            t.setdefault(key, 0)
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


def run_one(binary, test, limits, guard=None, alone=False):
    """Runs one graded test (its name) in its own process, within its Limits, in the sandbox where
    there is one. Returns (passed, output, seconds). With a guard (the fallback without a sandbox), a
    test that writes into the lab's files fails; when other tests ran at the same time, the ones
    that may have written run again, one at a time, so that only the writer is blamed."""
    token = guard.start(alone) if guard else None
    try:
        sandbox.BUDGET.reserve(limits.memory_mib)
        try:
            passed, output, seconds = _run_one(binary, test, limits)
        finally:
            sandbox.BUDGET.release(limits.memory_mib)
    finally:
        tampered, suspect = guard.finish(token) if guard else ([], False)
    if suspect and not alone:
        return run_one(binary, test, limits, guard, alone=True)
    if tampered:
        passed = False
        output = (f"wrote into the lab's own files, which is not allowed (undone): {', '.join(tampered)}\n"
                  + output).strip()
    return passed, output, seconds


def _watch(limits):
    """What the grader watches while a test runs: its resident memory and its threads."""
    def watch(pid):
        memory, threads = sandbox.usage(pid)
        if memory > limits.memory_mib:
            return "memory"
        if threads > limits.threads:
            return "threads"
        return None
    return watch


SANITIZER_LINE = re.compile(r"^.*(?:: runtime error: |==[0-9]+==ERROR: [A-Za-z]+Sanitizer).*$", re.M)
SANITIZER_MARK = "sanitizer: "


def _run_one(binary, test, limits):
    with tempfile.TemporaryDirectory(prefix="gpl-grade-") as tmp:
        report_path = pathlib.Path(tmp) / "report.json"
        trace_path = pathlib.Path(tmp) / "trace.txt"
        args = [f"--gtest_filter={test}", f"--gtest_output=json:{report_path}"]
        env = {"GPL_GRADER_TRACE": str(trace_path), "GPL_GRADER_SANDBOX": "1"}
        cmd, env, cwd = sandbox.Sandbox.here().command(binary, args, tmp, limits, env)
        start = time.monotonic()
        rc, out, why = run_limited(cmd, limits.seconds, cwd=cwd, env=env, warn_signal=signal.SIGUSR1,
                                   watch=_watch(limits))
        seconds = time.monotonic() - start
        if sandbox.Sandbox.here().isolated and rc > 128:
            rc = 128 - rc  # bubblewrap exits with 128 + the signal that ended the test
        passed, output = _verdict(test, rc, out, why, limits, report_path, trace_path, binary)
        # In a sanitizer build (asan, asan-core), a finding comes first in the message: the
        # self-checks of the solutions and the stubs fail on it even where the test fails anyway.
        found = SANITIZER_LINE.search(out)
        if found:
            passed = False
            output = f"{SANITIZER_MARK}{found.group(0).strip()}\n{output}".strip()
        return passed, output, seconds


def _verdict(test, rc, out, why, limits, report_path, trace_path, binary):
    trace = trace_path.read_text(errors="replace") if trace_path.exists() else ""
    hook = hook_in_trace(trace, out)
    where = f" in {hook}" if hook else ""
    # The test's own last lines (a failed assert's message, say), without GoogleTest's banner.
    tail = "\n".join([l for l in out.strip().splitlines() if not GTEST_LINE.match(l)][-8:])
    if why == "timeout":
        return False, f"timed out after {limits.seconds:g} s{where} (an endless loop?)"
    if why == "output":
        own = [l for l in out.strip().splitlines() if not GTEST_LINE.match(l)]
        head = "\n".join(own[:6])
        return False, f"printed more than {OUTPUT_CAP // 1024} KiB of output{where} and was stopped; it began:\n{head}"
    if why == "memory":
        return False, (f"used more than {limits.memory_mib:g} MiB of memory{where} and was stopped "
                       "(a container that grows every step?)")
    if why == "threads":
        return False, f"ran more than {limits.threads} threads at once{where} and was stopped"
    if rc < 0:
        name = _signal_name(-rc)
        if name == "SIGSYS":
            if "forbidden system call: network" in trace:
                return False, f"tried to open a network connection{where}, which graded code may not do; it was stopped"
            return False, f"tried to start a process{where}, which graded code may not do; it was stopped"
        if name == "SIGXCPU":
            return False, (f"used more than {limits.cpu_seconds()} s of CPU time{where} and was "
                           "stopped (an endless loop in several threads?)")
        if name == "SIGXFSZ":
            return False, f"wrote more than {limits.file_mib:g} MiB to a file{where} and was stopped"
        what = {"SIGABRT": " (abort: a failed assert or an uncaught exception)",
                "SIGFPE": " (an arithmetic error such as an integer division by zero)"}.get(name, "")
        return False, f"crashed with {name}{what}{where}\n{tail}".strip()
    text = report_path.read_text(errors="replace") if report_path.exists() else ""
    if not text.strip():
        return False, f"the test exited with status {rc}{where} before reporting\n{out[-2000:]}".strip()
    try:
        report = json.loads(text)
    except json.JSONDecodeError:
        return False, f"the test's report is unreadable (exit status {rc}){where}\n{out[-2000:]}".strip()
    if report.get("tests", 0) != 1:
        return False, f"test {test} not found in {pathlib.Path(binary).name}"
    failures = _failure_messages(report)
    passed = rc == 0 and not failures
    if any("std::bad_alloc" in m for m in failures):
        failures.insert(0, f"ran out of memory{where}: an allocation failed (std::bad_alloc)")
    # The fixture's "hooks still not implemented" note says the most: show it first.
    failures.sort(key=lambda m: not m.startswith("hooks still not implemented"))
    return passed, "\n".join(failures)


def with_prerequisites(tests, name):
    """The name and, transitively, the prerequisites it has among `tests` (a set of names)."""
    by_name = {t["name"]: t for t in tests}
    found, todo = set(), [name]
    while todo:
        n = todo.pop()
        if n in found or n not in by_name:
            continue
        found.add(n)
        todo.extend(by_name[n]["depends_on"])
    return found


def select(tests, worksheet):
    picked = [t for t in tests if worksheet is None or t["worksheet"] == worksheet]
    if not picked:
        raise GradeError(f"no graded tests for worksheet {worksheet}")
    return picked


def grade_binary(binary, worksheet=None, defaults=DEFAULT_TIMEOUT, guard=None, only=None):
    """Grades every selected test (of the worksheet; of those named in `only` too, when given),
    prerequisites first. A test whose prerequisite lost its points is not run: it scores zero and
    says which prerequisite to fix first."""
    binary = pathlib.Path(binary).resolve()
    tests = select(manifest(binary), worksheet)
    if only is not None:
        tests = [t for t in tests if t["name"] in only]
    results = {}
    for t in tests:
        blocked = [d for d in t["depends_on"] if d in results and not results[d]["passed"]]
        if blocked:
            results[t["name"]] = {**t, "passed": False, "not_run": True, "score": 0.0, "seconds": 0.0,
                                  "output": f"not run: depends on {', '.join(blocked)}, which did not pass; fix that first"}
            continue
        passed, output, seconds = run_one(binary, t["name"], limits_of(t, defaults), guard)
        results[t["name"]] = {**t, "passed": passed, "not_run": False, "score": t["points"] if passed else 0.0,
                              "output": output, "seconds": seconds}
    return list(results.values())


def failed_results(tests, message):
    return [{**t, "passed": False, "not_run": False, "score": 0.0, "seconds": 0.0, "output": message}
            for t in tests]
