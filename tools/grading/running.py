"""Running graded tests: for each, the trusted checker and the submission's engine in the sandbox,
wired by pipes; limits; and what a failure means (which hook, which limit)."""
import concurrent.futures
import dataclasses
import fcntl
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
from grading.cgroups import Cgroups
from grading.sandbox import limits_of

DEFAULT_TIMEOUT = 5.0         # s per test; the reference solution needs a few hundredths
# A sanitizer build (the asan presets' self-checks) runs the heavy tests, those that set their own
# time limit, several times slower than the release build the limit is set for: there they get this
# many times their limit. The grader's own setting, never the submission's.
SANITIZER_TIME_FACTOR = 3.0
OUTPUT_CAP = 1 << 20          # bytes of output a test may print before it is stopped
TRACE_GRACE = 2.0             # s a stopped test gets to write its call stack before it is killed
# A test's time limit counts the time it could run: from the start of the engine's own process, less
# the time the test's processes waited for a core that other programs held (the kernel's run-queue
# wait), so that a test graded on a busy machine gets the seconds a quiet one gives it; on the wall
# clock, never more than this many times its limit.
LOAD_ALLOWANCE = 10.0
GTEST_LINE = re.compile(r"^(Note: Google Test filter|\[[ =A-Z-]{10}\])")  # GoogleTest's own lines
ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


def run_limited(cmd, timeout, cap=OUTPUT_CAP, cwd=None, env=None, warn_signal=None, watch=None):
    """Runs cmd in its own process group. Returns (returncode, output, why) where why is None,
    'timeout', 'output' or what watch(pid) returned: watch is asked every few hundredths of a second
    and names a limit the running command broke (or None). At a limit the processes below cmd first
    get warn_signal (if given) and TRACE_GRACE seconds to report where they were, then every one of
    them is killed."""
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=cwd,
                            env=env, start_new_session=True)
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


def checker_manifest(checker):
    """The graded tests as the trusted checker lists them, checked: every field there and of its
    type, dependencies naming graded tests, no cycles. Nothing of a submission runs here."""
    checker = pathlib.Path(checker)
    if not checker.is_file():
        raise GradeError(f"checker not found: {checker}")
    rc, out, why = run_limited([str(checker), "--grader-manifest"], timeout=30)
    if rc != 0 or why:
        raise GradeError(f"{checker.name} --grader-manifest failed (exit {rc}): {out.strip()[-300:]}")
    try:
        tests = json.loads(out)
    except json.JSONDecodeError as e:
        raise GradeError(f"{checker.name} --grader-manifest printed no test list ({e})") from None
    if not isinstance(tests, list):
        raise GradeError(f"{checker.name} --grader-manifest printed no test list")
    fields = {"name": str, "worksheet": int, "points": (int, float), "hint": str}
    checked = []
    for t in tests:
        if not isinstance(t, dict) or any(not isinstance(t.get(k), kind) for k, kind in fields.items()):
            raise GradeError(f"{checker.name} --grader-manifest: a test without its name, worksheet, points or hint: {t!r:.200}")
        t = dict(t)
        for key in ("time_limit", "memory_limit", "thread_limit", "file_limit"):
            value = t.get(key) or 0
            t[key] = value if isinstance(value, (int, float)) and value >= 0 else 0
        t["depends_on"] = [d for d in t.get("depends_on") or [] if isinstance(d, str)]
        t["hidden"] = bool(t.get("hidden", False))
        checked.append(t)
    if len({t["name"] for t in checked}) != len(checked):
        raise GradeError(f"{checker.name} --grader-manifest lists a test twice")
    return in_dependency_order(checked)


manifest = checker_manifest


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


def hook_worksheets():
    """{"integrator()": 1, "sphereSphere()": 3, ...}: the worksheet of each hook (its file's head)."""
    found = {}
    for f in hooks.hook_files():
        path = ROOT / "assignments" / f
        if not path.is_file():
            continue
        text = path.read_text(errors="replace")
        m = re.search(r"Worksheet (\d+)", text)
        if not m:
            continue
        for function in re.findall(r"PhysicsEngine::(\w+)\(", text):
            found[function + "()"] = int(m.group(1))
        for hook in re.findall(r'[nN]otImplemented\("([^"]+)"\)', text):
            found[hook] = int(m.group(1))
    return found


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


# ---- One graded test: the checker (trusted) and the submission's engine (in the sandbox) ----------

class Programs:
    """What grades one variant: the trusted checker (the graded tests, no submission code), the
    variant's engine that answers it (gpl-hooks-VARIANT, untrusted) and the launcher (trusted)."""

    def __init__(self, checker, hooks, launcher=None, sanitizer=None):
        self.checker = pathlib.Path(checker).resolve()
        self.hooks = pathlib.Path(hooks).resolve()
        self.launcher = pathlib.Path(launcher or os.environ.get("GPL_LAUNCH") or self.checker.parent / "gpl-launch").resolve()
        # The leak checker's clone and ptrace are allowed only when the trusted configuration says
        # the build has sanitizers (CTest sets GPL_GRADER_SANITIZER for the asan presets).
        self.sanitizer = (os.environ.get("GPL_GRADER_SANITIZER", "") not in ("", "0")) if sanitizer is None else sanitizer
        for what, path in (("checker", self.checker), ("engine", self.hooks), ("launcher", self.launcher)):
            if not path.is_file():
                raise GradeError(f"{what} not found: {path}")

    def manifest(self):
        return checker_manifest(self.checker)


def _high_fd(fd):
    """fd moved above 9 (close-on-exec), so that placing the pipes at 0-4 in a child never clobbers one."""
    if fd > 9:
        return fd
    new = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
    os.close(fd)
    return new


def _spawn(argv, env, fds, output_path=None):
    """Starts argv in a session of its own with fds {target: source} placed (stdin /dev/null; stdout
    and stderr to fds[1] or to output_path). Thread-safe (posix_spawn). Returns the pid."""
    actions = [(os.POSIX_SPAWN_OPEN, 0, "/dev/null", os.O_RDONLY, 0)]
    if output_path is not None:
        actions += [(os.POSIX_SPAWN_OPEN, 1, str(output_path), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600),
                    (os.POSIX_SPAWN_DUP2, 1, 2)]
    for target, source in sorted(fds.items()):
        actions.append((os.POSIX_SPAWN_DUP2, source, target))
        if target == 1 and output_path is None:
            actions.append((os.POSIX_SPAWN_DUP2, source, 2))
    return os.posix_spawn(argv[0], argv, env, file_actions=actions, setsid=True)


def _status(pid, block=False):
    """The returncode (negative: a signal) of a child, or None while it runs."""
    try:
        got, status = os.waitpid(pid, 0 if block else os.WNOHANG)
    except ChildProcessError:
        return -signal.SIGKILL
    if got == 0:
        return None
    return os.waitstatus_to_exitcode(status)


def _kill_tree(pid):
    for p in reversed(sandbox.descendants(pid)):
        try:
            os.kill(p, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


class Pair:
    """What happened when the checker and the engine ran one test."""
    checker_rc = None       # the checker's returncode (None: killed by the grader)
    runner_rc = None        # the engine's (bubblewrap's) returncode
    why = None              # None, "timeout", "output", "memory" or "threads": a limit the grader or kernel kept
    output = ""             # what the engine printed (capped)
    trace = ""              # the call stack the engine wrote (untrusted: it only refines a message)
    killed = False          # the grader ended the engine (its status says nothing of its own)
    seconds = 0.0


def engine_process(pid):
    """Whether pid is one of the engine's own processes, not bubblewrap's or the launcher's; False
    once it has ended. Read once: a process of a test being stopped can end between two reads."""
    usage = sandbox._usage(pid)
    return usage is not None and usage[2] not in ("bwrap", "gpl-launch")


def run_pair(programs, test, limits, folder, sandbox_here=None, cgroups=None):
    """Runs one graded test: the engine first (in the sandbox, within its limits), then the checker,
    wired by two pipes; the time limit applies to the pair (LOAD_ALLOWANCE: from the engine's start,
    less the pair's waits for a core). At a limit the checker is asked which call was in flight
    (SIGUSR2) and the engine to write its call stack (SIGUSR1); when the checker ends, every process
    of the engine is killed."""
    sandbox_here = sandbox_here or sandbox.Sandbox.here()
    cgroups = cgroups or Cgroups.here()
    folder = pathlib.Path(folder)
    group = None
    if cgroups.available:
        try:
            # bubblewrap's own two processes (its parent and the sandbox's init) besides the engine's threads
            group = cgroups.make(limits, extra_processes=2 if sandbox_here.isolated else 0)
        except OSError:  # the machine's cgroups are full or gone: the grader watches instead
            group = None
    result = Pair()
    pipes = []
    try:
        cmd, env, trace = sandbox_here.runner_command(programs.hooks, ["--serve"], folder, limits, programs.launcher,
                                                     group, programs.sanitizer)
        a_read, a_write = map(_high_fd, os.pipe())   # checker -> engine
        b_read, b_write = map(_high_fd, os.pipe())   # engine -> checker
        out_read, out_write = map(_high_fd, os.pipe())
        pipes = [a_read, a_write, b_read, b_write, out_read, out_write]
        runner = _spawn(cmd, env, {1: out_write, 3: a_read, 4: b_write})
        for fd in (a_read, b_write, out_write):
            os.close(fd)
            pipes.remove(fd)
        checker_env = {**os.environ, "GPL_CHECKER_STATUS": str(folder / "status.jsonl")}
        checker_cmd = [str(programs.checker), f"--gtest_filter={test}",
                       f"--gtest_output=json:{folder / 'report.json'}"]
        start = time.monotonic()
        try:
            checker = _spawn(checker_cmd, checker_env, {3: b_read, 4: a_write}, output_path=folder / "checker.txt")
        except OSError:
            _kill_tree(runner)
            _status(runner, block=True)
            raise
        for fd in (b_read, a_write):
            os.close(fd)
            pipes.remove(fd)

        chunks, size, stopped = [], 0, threading.Event()

        def reader():
            nonlocal size
            while True:
                try:
                    data = os.read(out_read, 65536)
                except OSError:
                    return
                if not data:
                    return
                if size < OUTPUT_CAP:
                    chunks.append(data[: OUTPUT_CAP - size])
                size += len(data)
                if size > OUTPUT_CAP:
                    stopped.set()

        thread = threading.Thread(target=reader, daemon=True)
        thread.start()
        watch = None if group else _watch(limits)
        deadline = start + limits.seconds
        latest = start + LOAD_ALLOWANCE * limits.seconds
        while True:
            if result.checker_rc is None:
                result.checker_rc = _status(checker)
                if result.checker_rc is not None:
                    break
            if result.runner_rc is None:
                result.runner_rc = _status(runner)
            if stopped.is_set():
                result.why = "output"
                break
            if time.monotonic() >= deadline:
                now = time.monotonic()
                ages = [a for a in map(age, sandbox.test_processes(runner)) if a is not None]
                begun = max(start, now - max(ages)) if ages else start
                deadline = min(begun + limits.seconds + queued_seconds([checker, *sandbox.descendants(runner)]), latest)
                if now >= deadline:
                    result.why = "timeout"
                    break
            if watch is not None and result.runner_rc is None:
                result.why = watch(runner)
                if result.why:
                    break
            if group is not None and result.runner_rc is None:
                # Stopped just before the kernel would kill it (memory), or once the kernel refused
                # it a thread, so that it can say where it was.
                result.why = "memory" if group.near_memory_limit() else "threads" if group.threads_refused() else None
                if result.why:
                    break
            # Often enough to stop a growing engine before the kernel's memory limit (no call stack then).
            time.sleep(0.005 if group is not None or time.monotonic() - start < 0.2 else 0.02)
        if result.why is not None:
            # Which call was in flight (the checker's word, trusted), and the engine's call stack.
            try:
                os.kill(checker, signal.SIGUSR2)
            except ProcessLookupError:
                pass
            if result.runner_rc is None:
                for pid in (group.processes() if group else sandbox.test_processes(runner)):
                    if engine_process(pid):
                        try:
                            os.kill(pid, signal.SIGUSR1)
                        except (ProcessLookupError, PermissionError):
                            pass
                grace = time.monotonic() + TRACE_GRACE
                while result.runner_rc is None and time.monotonic() < grace:
                    time.sleep(0.01)
                    result.runner_rc = _status(runner)
        # The engine's processes go, all of them, whatever the checker did. An engine that ended
        # (at the end of its requests, or by a signal bubblewrap has still to pass on) is given a
        # moment to say so: its status must not be mistaken for the grader's kill.
        if result.runner_rc is None:
            # (In a sanitizer build the leak checker runs at that end, and its report counts.)
            settle = time.monotonic() + (0.0 if result.why else 10.0 if programs.sanitizer else 0.5)
            result.runner_rc = _status(runner)
            while result.runner_rc is None and time.monotonic() < settle:
                time.sleep(0.005)
                result.runner_rc = _status(runner)
            result.killed = result.runner_rc is None
        if result.runner_rc is None:
            # The engine's own processes first, so that bubblewrap ends and reaps them itself.
            for pid in (group.processes() if group else sandbox.descendants(runner)):
                if engine_process(pid):
                    try:
                        os.kill(pid, signal.SIGKILL)
                    except (ProcessLookupError, PermissionError):
                        pass
            settle = time.monotonic() + 0.5
            while result.runner_rc is None and time.monotonic() < settle:
                time.sleep(0.005)
                result.runner_rc = _status(runner)
        if group:
            group.kill()
        if result.runner_rc is None:
            _kill_tree(runner)
            result.runner_rc = _status(runner, block=True)
        if result.checker_rc is None:
            # The engine is gone: a checker waiting for it reads the end of its pipe and finishes. At
            # a limit it is ended, once it has noted the call in flight (SIGUSR2 above; a busy
            # machine may not have run it yet) or half a second has passed.
            finish = time.monotonic() + (0.5 if result.why else 2.0)
            while result.checker_rc is None and time.monotonic() < finish:
                if result.why and any(e[0] == "waiting" for e in _checker_status(folder)):
                    break
                time.sleep(0.01)
                result.checker_rc = _status(checker)
            if result.checker_rc is None:
                _kill_tree(checker)
                _status(checker, block=True)
        else:
            _kill_tree(checker)  # anything the checker left (it starts none)
        thread.join(timeout=5)
        result.output = b"".join(chunks).decode("utf-8", "replace")
        if group:
            # The kernel's word on memory and threads comes before the wall clock's: a thread that
            # could not start may leave the engine waiting until the time is up.
            result.why = group.broken() or result.why
        result.trace = ""
        if trace.exists():
            with open(trace, "rb") as f:  # the engine wrote it: no more than its first MiB is read
                result.trace = f.read(1 << 20).decode("utf-8", "replace")
        result.seconds = time.monotonic() - start
        return result
    finally:
        for fd in pipes:
            try:
                os.close(fd)
            except OSError:
                pass
        if group:
            group.remove()


def age(pid):
    """Seconds since process pid began (None when it is gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
        ticks = int(stat[stat.rindex(")") + 2:].split()[19])
    except (OSError, ValueError, IndexError):
        return None
    return time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")


def queued_seconds(pids):
    """Seconds the main threads of pids have waited on the kernel's run queues for a core, from
    /proc/PID/schedstat (0 for a process gone, or where the kernel does not say)."""
    total = 0
    for pid in pids:
        try:
            with open(f"/proc/{pid}/schedstat") as f:
                total += int(f.read().split()[1])
        except (OSError, ValueError, IndexError):
            continue
    return total / 1e9


def _checker_status(folder):
    """The checker's own notes (trusted): [(event, call, detail)]."""
    events = []
    path = pathlib.Path(folder) / "status.jsonl"
    if path.exists():
        for line in path.read_text(errors="replace").splitlines():
            try:
                e = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(e, dict):
                stages = e.get("hooks")
                events.append((e.get("event"), e.get("call") if isinstance(e.get("call"), str) else None,
                               e.get("detail") if isinstance(e.get("detail"), str) else "",
                               [h for h in stages if isinstance(h, str)] if isinstance(stages, list) else None))
    return events


def call_in_flight(events):
    """The call the checker had in flight when the test stopped, from its notes (trusted): the call
    its last "waiting" note names (the grader asks at a limit). A note that names none, written once
    the engine had already ended within a call ("ended" before it: a limit that ended the engine
    reaches the checker first on a busy machine), names that call; one written before any call
    ended, none (a limit broken between calls). Without a "waiting" note, the call the engine ended
    within, or None."""
    noted = [k for k, (event, _, _, _) in enumerate(events) if event == "waiting"]
    if not noted:
        return next((call for event, call, _, _ in events if event == "ended"), None)
    last = noted[-1]
    if events[last][1]:
        return events[last][1]
    return next((call for event, call, _, _ in events[:last] if event == "ended"), None)


# The one hook that calls the others (the step's stages): a call stack of the engine may name which
# of them was running. Any other call is the hook itself, whatever the engine's stack says.
WHOLE_STEP = "simulationTimestep()"


def blamed_hook(call, trace, output, test=None, stages=None):
    """The hook named in a message: the call the checker had in flight (trusted). Within a whole
    step, the engine's own call stack or failed assert may name the stage that was running, but only
    among the stages the checker lists for that step (`stages`): a hook that writes a stack of its
    own never gets another hook blamed. None when the checker had no call in flight."""
    if not call:
        return None
    if call != WHOLE_STEP or not stages:
        return call
    named = hook_in_trace(trace, output)
    return named if named in stages else call


FORBIDDEN = {
    "network": "tried to open a network connection{where}, which graded code may not do; it was stopped",
    "process": "tried to start a process{where}, which graded code may not do; it was stopped",
    "namespace": "tried to make a namespace or mount something{where}, which graded code may not do; it was stopped",
    "memory": "tried to allocate shared memory or a memory file{where}, which graded code may not do; it was stopped",
    "kernel": "tried to use a kernel interface that graded code may not use{where}; it was stopped",
    "signal": "tried to send a signal to another process{where}, which graded code may not do; it was stopped",
    "limit": "tried to raise its limit of open files{where}, which graded code may not do; it was stopped",
}


def run_one(programs, test, limits, guard=None, alone=False):
    """Runs one graded test (its name) within its Limits. Returns (passed, output, seconds). With a
    guard (the fallback without a sandbox), a test that writes into the lab's files fails; when
    other tests ran at the same time, the ones that may have written run again, one at a time, so
    that only the writer is blamed."""
    token = guard.start(alone) if guard else None
    try:
        sandbox.BUDGET.reserve(limits.memory_mib)
        try:
            passed, output, seconds = _run_one(programs, test, limits)
        finally:
            sandbox.BUDGET.release(limits.memory_mib)
    finally:
        tampered, suspect = guard.finish(token) if guard else ([], False)
    if suspect and not alone:
        return run_one(programs, test, limits, guard, alone=True)
    if tampered:
        passed = False
        output = (f"wrote into the lab's own files, which is not allowed (undone): {', '.join(tampered)}\n"
                  + output).strip()
    return passed, output, seconds


def _watch(limits):
    """What the grader watches where no cgroup counts for it: resident memory and threads."""
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


def _run_one(programs, test, limits):
    with tempfile.TemporaryDirectory(prefix="gpl-grade-") as tmp:
        pair = run_pair(programs, test, limits, tmp)
        passed, output = verdict(test, pair, limits, pathlib.Path(tmp))
        # In a sanitizer build (asan, asan-core), a finding comes first in the message: the
        # self-checks of the solutions and the stubs fail on it even where the test fails anyway.
        found = SANITIZER_LINE.search(pair.output)
        if found:
            passed = False
            output = f"{SANITIZER_MARK}{found.group(0).strip()}\n{output}".strip()
        return passed, output, pair.seconds


def _runner_signal(pair, isolated):
    """The signal that ended the engine, or None (bubblewrap exits with 128 + the signal)."""
    rc = pair.runner_rc
    if rc is None:
        return None
    if rc < 0:
        return -rc
    if isolated and rc > 128:
        return rc - 128
    return None


# How a message begins when the test did not fail on its own assertions: the engine crashed, broke
# a limit or did not answer (the reports show no hint for these: the message says what happened).
ENGINE_FAILURES = ("stopped early:", "timed out after", "printed more than", "used more than", "ran more than", "tried to ",
                   "wrote more than", "overflowed its stack", "crashed with", "the engine did not answer",
                   "the engine exited", "the checker ended", "the checker failed", "wrote into the lab's",
                   "ran out of memory", "could not be graded", SANITIZER_MARK)


OPEN_HOOKS = "hooks still not implemented:"
STOPPED_EARLY = "stopped early:"
# The engine's sentence when a step leaves a body with a NaN or an infinity (engine.cpp, rotation.cpp).
NONFINITE = re.compile(r"(body '[^'\n]{1,100}'[^\n\"]{0,60}? is no longer finite (?:after|in) step \d+[^\n\"]{0,80})")


def verdict(test, pair, limits, folder, isolated=None):
    """(passed, message): the checker's report decides; the engine's fate and the limits say why a
    test failed, naming the hook the checker had in flight."""
    isolated = sandbox.Sandbox.here().isolated if isolated is None else isolated
    events = _checker_status(folder)
    ended = [(call, detail) for event, call, detail, _ in events if event == "ended"]
    stages = next((st for event, call, _, st in reversed(events) if st is not None), None)
    call = call_in_flight(events)
    hook = blamed_hook(call, pair.trace, pair.output, test, stages)
    where = f" in {hook}" if hook else ""
    out = pair.output
    tail = "\n".join([l for l in out.strip().splitlines() if not GTEST_LINE.match(l)][-8:])
    if pair.why == "timeout":
        return False, f"timed out after {limits.seconds:g} s{where} (an endless loop?)"
    if pair.why == "output":
        head = "\n".join(out.strip().splitlines()[:6])
        return False, f"printed more than {OUTPUT_CAP // 1024} KiB of output{where} and was stopped; it began:\n{head}"
    if pair.why == "memory":
        return False, (f"used more than {limits.memory_mib:g} MiB of memory{where} and was stopped "
                       "(a container that grows every step?)")
    if pair.why == "threads":
        return False, f"ran more than {limits.threads} threads at once{where} and was stopped"
    report_path = folder / "report.json"
    text = report_path.read_text(errors="replace") if report_path.exists() else ""
    try:
        report = json.loads(text) if text.strip() else None
    except json.JSONDecodeError:
        report = None
    cases = [c for s in (report or {}).get("testsuites", []) for c in s.get("testsuite", [])]
    ran = [c for c in cases if c.get("status", "RUN") == "RUN"]
    names = [f"{c.get('classname', '')}.{c.get('name', '')}" for c in ran]
    if report is not None and (report.get("tests", 0) == 0 or not ran):
        return False, f"test {test} not found in the checker"
    failures = _failure_messages(report) if report else []
    passed = (report is not None and pair.checker_rc == 0 and names == [test] and not failures and
              all(c.get("result", "COMPLETED") == "COMPLETED" for c in ran))
    if passed:
        return True, ""
    signal_number = None if pair.killed else _runner_signal(pair, isolated)
    if signal_number and (ended or report is None):
        # The engine was ended by a signal during a call: what ended it says more than the checker.
        name = _signal_name(signal_number)
        if name == "SIGSYS":
            m = re.search(r"forbidden system call: (\w+)", pair.trace)
            kind = m.group(1) if m and m.group(1) in FORBIDDEN else "process"
            return False, FORBIDDEN[kind].format(where=where)
        if name == "SIGXCPU":
            return False, (f"used more than {limits.cpu_seconds()} s of CPU time{where} and was "
                           "stopped (an endless loop in several threads?)")
        if name == "SIGXFSZ":
            return False, f"wrote more than {limits.file_mib:g} MiB to a file{where} and was stopped"
        if name == "SIGSEGV" and "grader: stack overflow" in pair.trace:
            return False, f"overflowed its stack{where} (an endless recursion?)\n{tail}".strip()
        what = {"SIGABRT": " (abort: a failed assert or an uncaught exception)",
                "SIGFPE": " (an arithmetic error such as an integer division by zero)"}.get(name, "")
        # The step the engine was taking (its own word: it only words a failure already decided).
        step = re.search(r"^grader: in step (\d{1,12})$", pair.trace, re.M)
        during = f" in step {int(step.group(1))}" if step else ""
        return False, f"crashed with {name}{what}{where}{during}\n{tail}".strip()
    if ended:
        # The engine left the call (exited) or answered something that is no answer: the checker says which.
        _, detail = ended[0]
        # The checker's own words name the call already ("... stopped answering during X: why").
        detail = re.sub(r"^the submission's code (stopped answering|answered nonsense) during [\w:]+\(\):?\s*",
                        lambda m: "it " + m.group(1) + (": " if m.group(1) == "answered nonsense" else ""),
                        detail or "it stopped").rstrip(": ")
        rc = pair.runner_rc
        status = f" (it exited with status {rc})" if rc and not pair.killed and rc > 0 and (not isolated or rc < 128) else ""
        return False, f"the engine did not answer{where}: {detail}{status}\n{tail}".strip()
    if report is None:
        own = (folder / "checker.txt").read_text(errors="replace").strip().splitlines()[-5:] \
            if (folder / "checker.txt").exists() else []
        return False, "\n".join([f"the checker ended (status {pair.checker_rc}) without a report{where}", *own, tail]).strip()
    # A body that is no longer finite ends the run wherever the test was: the engine's own sentence,
    # once, in the words of ./lab run and the student README ("stopped early: body ...").
    nonfinite = next((m.group(1) for m in map(NONFINITE.search, failures) if m), None)
    if nonfinite:
        return False, f"{STOPPED_EARLY} {nonfinite}"
    if any("std::bad_alloc" in m for m in failures):
        failures.insert(0, f"ran out of memory{where}: an allocation failed (std::bad_alloc)")
    # A test of its own engines has no fixture note: the engine's own report of the stubs it ran
    # ("not implemented: X()", untrusted: hooks only, and it only words a failure) says the same.
    if not any(m.startswith(OPEN_HOOKS) for m in failures):
        known = set(hook_names().values())
        reported = sorted({m.group(1) for m in re.finditer(r"^not implemented: (\S+\(\))$", pair.output, re.M)} & known)
        if reported:
            failures.insert(0, f"{OPEN_HOOKS} {' '.join(reported)}")
    # The fixture's "hooks still not implemented" note says the most: show it first.
    failures.sort(key=lambda m: not m.startswith("hooks still not implemented"))
    return False, "\n".join(failures) or f"the checker failed (status {pair.checker_rc}){where}"



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
        known = sorted({t["worksheet"] for t in tests})
        raise GradeError(f"no graded tests for worksheet {worksheet}; the worksheets with graded tests: "
                         + ", ".join(map(str, known)))
    return picked


def test_limits(programs, test, defaults=DEFAULT_TIMEOUT):
    """The limits a graded test runs under with these programs: limits_of() its manifest entry, its
    own time limit SANITIZER_TIME_FACTOR times longer in a sanitizer build."""
    limits = limits_of(test, defaults)
    if programs.sanitizer and test.get("time_limit"):
        limits = dataclasses.replace(limits, seconds=limits.seconds * SANITIZER_TIME_FACTOR)
    return limits


def grade_binary(programs, worksheet=None, defaults=DEFAULT_TIMEOUT, guard=None, only=None, tests=None, jobs=1):
    """Grades every selected test (of the worksheet; of those named in `only` too, when given),
    prerequisites first, the list from the trusted checker. A test whose prerequisite lost its
    points is not run: it scores zero and says which prerequisite to fix first. Up to `jobs` tests
    run at once, each in its own sandbox, a test only once the prerequisites listed before it are
    decided: the results are those of one test at a time, in the list's order."""
    tests = select(tests if tests is not None else programs.manifest(), worksheet)
    if only is not None:
        tests = [t for t in tests if t["name"] in only]
    position = {t["name"]: i for i, t in enumerate(tests)}
    before = {t["name"]: [d for d in t["depends_on"] if position.get(d, len(tests)) < position[t["name"]]]
              for t in tests}

    def graded(t):
        passed, output, seconds = run_one(programs, t["name"], test_limits(programs, t, defaults), guard)
        return {**t, "passed": passed, "not_run": False, "score": t["points"] if passed else 0.0,
                "output": output, "seconds": seconds}

    results, waiting, running = {}, list(tests), {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        while waiting or running:
            started = True
            while started:  # a test found not run may decide the next one's prerequisites
                started = False
                for t in list(waiting):
                    if any(d not in results for d in before[t["name"]]):
                        continue
                    blocked = [d for d in before[t["name"]] if not results[d]["passed"]]
                    if blocked:
                        results[t["name"]] = {
                            **t, "passed": False, "not_run": True, "score": 0.0, "seconds": 0.0,
                            "output": f"not run: depends on {', '.join(blocked)}, which did not pass; fix that first"}
                    elif len(running) < max(1, jobs):
                        running[pool.submit(graded, t)] = t
                    else:
                        continue
                    waiting.remove(t)
                    started = True
            if running:
                done, _ = concurrent.futures.wait(running, return_when=concurrent.futures.FIRST_COMPLETED)
                for future in done:
                    results[running.pop(future)["name"]] = future.result()
    return [results[t["name"]] for t in tests]




def failed_results(tests, message):
    return [{**t, "passed": False, "not_run": False, "score": 0.0, "seconds": 0.0, "output": message}
            for t in tests]
