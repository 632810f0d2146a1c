"""Tests of the grader's tools (tools/grade.py, tools/hooks.py) on their own, on small fake programs
(fakes.py: a probe of the launcher's filter, a fake engine and checker) and on the real checker and
engines, whose paths CTest passes in GPL_CHECKER, GPL_LAUNCH, GPL_HOOKS_SOLUTIONS and
GPL_HOOKS_ASSIGNMENTS."""
import contextlib
import io
import json
import re
import os
import pathlib
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from unittest import mock
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import fakes  # noqa: E402
import grade  # noqa: E402
from grading import building  # noqa: E402
from grading import cgroups  # noqa: E402
from grading.guard import Guard  # noqa: E402
from grading import reports  # noqa: E402
from grading import running  # noqa: E402
from grading import sandbox  # noqa: E402
import hooks  # noqa: E402
import similarity  # noqa: E402

CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"


def env_path(name):
    path = os.environ.get(name)
    if not path:
        raise RuntimeError(f"set {name} (CTest does)")
    return path


def programs(variant):
    """The real checker with the engine of solutions/ or assignments/."""
    return running.Programs(env_path("GPL_CHECKER"), env_path(f"GPL_HOOKS_{variant.upper()}"), env_path("GPL_LAUNCH"))


_GRADED = {}


def graded(variant, worksheet=1):
    """The real checker's results for a variant's engine on a worksheet, graded once per run."""
    if (variant, worksheet) not in _GRADED:
        _GRADED[variant, worksheet] = running.grade_binary(programs(variant), worksheet=worksheet)
    return _GRADED[variant, worksheet]


_FAKES = {}


def fake(name):
    """The fake programs of fakes.py, compiled once per run."""
    if not _FAKES:
        folder = tempfile.mkdtemp(prefix="gpl-fakes-")
        _FAKES.update(fakes.build(folder))
    return _FAKES[name]


def engines_left(engine):
    """The processes of program `engine` still running: those that run its very file, told apart by
    the file (a sandbox runs it as /grader/engine), not the engines of other graders that tests beside
    this one run."""
    named = subprocess.run(["pgrep", "-f", f"^({engine}|/grader/engine) --serve"], capture_output=True,
                           text=True).stdout.split()
    ours = os.stat(engine)
    left = []
    for pid in named:
        try:
            program = os.stat(f"/proc/{pid}/exe")
        except OSError:  # ended since, or not readable: not a process of this test's
            continue
        if (program.st_dev, program.st_ino) == (ours.st_dev, ours.st_ino):
            left.append(pid)
    return left


class RunLimited(unittest.TestCase):
    def test_a_loop_is_stopped_at_the_time_limit(self):
        rc, _, why = running.run_limited(["sh", "-c", "while :; do :; done"], timeout=0.5)
        self.assertEqual(why, "timeout")
        self.assertLess(rc, 0)

    def test_endless_output_is_stopped_at_the_cap(self):
        rc, out, why = running.run_limited(["yes"], timeout=20, cap=4096)
        self.assertEqual(why, "output")
        self.assertEqual(len(out), 4096)

    def test_a_normal_command_reports_its_exit_status(self):
        rc, out, why = running.run_limited(["sh", "-c", "echo hello; exit 3"], timeout=10)
        self.assertEqual((rc, out.strip(), why), (3, "hello", None))


FAKE_COMPILER = """#!/usr/bin/python3
# A compiler that answers as the source it is given asks: a located error, a g++ or Clang driver
# whose compiler proper was killed, or an object. Each start is one line in the log.
import pathlib, sys
args = sys.argv[1:]
with open(LOG, "a") as log:
    log.write(" ".join(args) + "\\n")
name = args[-1]
text = pathlib.Path(name).read_text() if name.endswith(".cpp") else ""
if "BROKEN" in text:
    print(name + ":3:5: error: expected ';' before '}' token")
    sys.exit(1)
if "KILLED_GCC" in text:
    print("g++: fatal error: Killed signal terminated program cc1plus")
    print("compilation terminated.")
    sys.exit(4)
if "KILLED_CLANG" in text:
    print("clang++: error: unable to execute command: Killed")
    print("clang++: error: clang frontend command failed due to signal (use -v to see invocation)")
    sys.exit(1)
out = args[args.index("-MF") + 1] if "-MF" in args else args[args.index("-o") + 1]
pathlib.Path(out).write_text("hook.o: " + name + "\\n" if "-M" in args else "\\t.text\\n")
"""


class CompileCache(unittest.TestCase):
    """compile_hook keeps a file's compile errors for its next grading only where the compiler said
    what is wrong at a line of it; a compiler ended by a signal (a limit of the moment) is asked
    again, whichever compiler's wording says so."""

    def setUp(self):
        self.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-compile-cache-"))
        self.addCleanup(lambda: subprocess.run(["rm", "-rf", str(self.tmp)]))
        self.log = self.tmp / "log"
        compiler = self.tmp / "fake-c++"
        compiler.write_text(FAKE_COMPILER.replace("LOG", repr(str(self.log)), 1))
        compiler.chmod(0o755)
        (self.tmp / "include").mkdir()
        self.trusted = mock.Mock(compiler=str(compiler), flags=[], include_dir=self.tmp / "include", pch=None)
        self.trusted.key.return_value = "fake"
        self.cache = self.tmp / "cache"
        self.cache.mkdir()
        for patched in (mock.patch.object(sandbox.Sandbox, "_probed", sandbox.Sandbox(None, "off for a test")),
                        mock.patch.object(cgroups.Cgroups, "_probed", cgroups.Cgroups(None, None, None, "off"))):
            patched.start()
            self.addCleanup(patched.stop)

    def compile_twice(self, text):
        """The errors of two gradings of a hook file, and how often the compiler started for each."""
        source = self.tmp / "src"
        source.mkdir(exist_ok=True)
        (source / "integrator.cpp").write_text(text)
        results = []
        for _ in range(2):
            before = len(self.log.read_text().splitlines()) if self.log.exists() else 0
            compiled = building.compile_hook(self.trusted, self.cache, source, "integrator.cpp", None)
            results.append((compiled.errors, len(self.log.read_text().splitlines()) - before))
        return results

    def test_a_located_error_is_kept_and_a_killed_compiler_is_asked_again(self):
        (first, starts), (second, again) = self.compile_twice("// BROKEN\n")
        self.assertRegex(first, r"^integrator\.cpp:3:5: error: expected")
        self.assertGreater(starts, 0)
        self.assertEqual((second, again), (first, 0), "the same file's errors come from the cache")
        for word in ("KILLED_GCC", "KILLED_CLANG"):
            with self.subTest(compiler=word):
                (first, starts), (second, again) = self.compile_twice(f"// {word}\n")
                self.assertIn("Killed", first)
                self.assertGreater(starts, 0)
                self.assertEqual(second, first)
                self.assertEqual(again, starts, "a compiler ended by a signal is asked again")

    def test_a_file_that_compiles_is_kept_as_its_object(self):
        (first, starts), (second, again) = self.compile_twice("// fine\n")
        self.assertEqual((first, second), (None, None))
        self.assertEqual((starts, again), (3, 0), "preprocess, compile and assemble once, then the cache")


class Launcher(unittest.TestCase):
    """gpl-launch: the filter is in force before the program's first instruction (a static
    initializer included); every refused call raises SIGSYS with its tag; threads work; no program
    can be executed after the first; descriptor 1000 is out of reach."""

    TAGS = {"process": 1, "network": 2, "namespace": 3, "memory": 4, "kernel": 5, "signal": 6, "limit": 7}
    REFUSED = {"fork": "process", "vfork": "process", "clone": "process", "clone_vm": "process",
               "clone_newuser": "namespace", "execve": "process", "execveat_abs": "process",
               "execveat_null": "process", "raise_nofile": "limit", "prlimit_nofile": "limit",
               "prlimit_other": "signal", "socket": "network", "unix": "network", "socketpair": "network",
               "unshare": "namespace", "setns": "namespace", "mount": "namespace", "chroot": "namespace",
               "memfd": "memory", "shmget": "memory", "io_uring": "kernel", "bpf": "kernel", "perf": "kernel",
               "userfaultfd": "kernel", "ptrace": "process", "vm_read": "process", "keyctl": "kernel",
               "personality": "kernel", "kill_other": "signal", "kill_group": "signal",
               "tgkill_other": "signal", "pidfd_other": "signal"}

    def launch(self, *args, env=None, options=()):
        return subprocess.run([env_path("GPL_LAUNCH"), *options, "--", str(fake("probe")), *args],
                              capture_output=True, text=True, timeout=20, env={**os.environ, **(env or {})})

    def test_every_forbidden_call_is_refused_with_its_tag(self):
        for what, tag in self.REFUSED.items():
            with self.subTest(call=what):
                proc = self.launch(what)
                self.assertEqual((proc.returncode, proc.stdout.strip()), (99, f"refused {self.TAGS[tag]}"), proc.stderr)

    def test_threads_signals_to_itself_and_limits_it_only_reads_work(self):
        self.assertEqual(self.launch("threads").stdout.strip(), "threads ok")
        self.assertEqual(self.launch("kill_self").stdout.strip(), "kill self 0")
        self.assertEqual(self.launch("raise").stdout.strip(), "raise 0")
        self.assertEqual(self.launch("clone3_thread").stdout.strip(), "clone3 -1 Function not implemented")
        self.assertIn("nofile 256 256", self.launch("getrlimit").stdout)

    def test_the_filter_is_there_before_main(self):
        proc = self.launch("hello", env={"PROBE_EARLY": "fork"})
        self.assertEqual(proc.stdout.strip(), "refused 1", "a static initializer's fork is refused")

    def test_descriptor_1000_is_closed_and_out_of_reach(self):
        self.assertRegex(self.launch("hello").stdout, r"fds1000=-1")
        self.assertEqual(self.launch("dup1000").stdout.strip(), "dup2 -> -1 Bad file descriptor")

    def test_the_leak_checkers_clone_only_in_a_sanitizer_build(self):
        self.assertRegex(self.launch("clone_vm", options=["--sanitizer"]).stdout, r"^allowed: clone_vm")
        self.assertRegex(self.launch("fork", options=["--sanitizer"]).stdout, r"^refused 1")

    def test_kernel_limits(self):
        with tempfile.TemporaryDirectory() as tmp:
            with open(pathlib.Path(tmp) / "f", "wb") as f:
                proc = subprocess.run([env_path("GPL_LAUNCH"), "--file-bytes", "1000000", "--", "/usr/bin/head",
                                       "-c", "3000000", "/dev/zero"], stdout=f, timeout=20)
            self.assertEqual(proc.returncode, -signal.SIGXFSZ)
            loop = "while True: pass"
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            proc = subprocess.run([env_path("GPL_LAUNCH"), "--cpu", "1", "--", "/usr/bin/python3", "-c", loop],
                                  capture_output=True, timeout=60)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            self.assertEqual(proc.returncode, -signal.SIGXCPU)
            # Stopped by its second of CPU time, whatever the wall clock did on a loaded machine: the
            # loop's own CPU time, between the limit and the limit plus the launch's (generous).
            used = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
            self.assertGreaterEqual(used, 0.9)
            self.assertLess(used, 3.0)

    def test_bad_usage_is_one_line(self):
        for args in (["--bogus"], ["--cpu", "x", "--", "/bin/true"], [], ["--", "/nonexistent"]):
            proc = subprocess.run([env_path("GPL_LAUNCH"), *args], capture_output=True, text=True, timeout=20)
            self.assertEqual(proc.returncode, 125, args)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)


class Pairs(unittest.TestCase):
    """run_one on the fake checker and engine, in the sandbox (and its fallbacks): each way an engine
    can end is named, with the hook the checker had in flight; no process outlives its test."""

    LIMITS = sandbox.Limits(2, 100, 8, 1)

    def run_fake(self, word, limits=None):
        p = running.Programs(fake("checker"), fake("engine"), env_path("GPL_LAUNCH"))
        passed, output, seconds = running.run_one(p, "Fake." + word.capitalize(), limits or self.LIMITS)
        self.assertEqual(engines_left(fake("engine")), [], f"{word}: processes of the engine outlived the test")
        return passed, output, seconds

    EXPECTED = {
        "ok": None,
        "survive": None,  # a thread left behind does not change the verdict, and is gone afterwards
        "eight": None,  # eight threads at once (the main thread and seven) are within the limit of 8
        "crash": r"^crashed with SIGSEGV in integrator\(\)$",
        "abort": r"^crashed with SIGABRT \(abort: a failed assert or an uncaught exception\) in integrator\(\)\n"
                 r"runner: x.cpp:3: .*Assertion",
        "loop": r"^timed out after 2 s in integrator\(\) \(an endless loop\?\)",
        "fork": r"^tried to start a process in integrator\(\), which graded code may not do",
        "socket": r"^tried to open a network connection in integrator\(\)",
        "memfd": r"^tried to allocate shared memory or a memory file in integrator\(\)",
        "print": r"^printed more than 1024 KiB of output in integrator\(\) and was stopped; it began:\ndebug: x = 1",
        "exit": r"^the engine did not answer in integrator\(\): the engine closed its pipe \(it exited with status 3\)",
        "nonsense": r"^the engine did not answer in integrator\(\): the answer is not one",
        "memory": r"^used more than 100 MiB of memory in integrator\(\) and was stopped",
        "threads": r"^ran more than 8 threads at once in integrator\(\) and was stopped",
        "file": r"^wrote more than 1 MiB to a file in integrator\(\) and was stopped",
        # The checker's call was the whole step, and it lists no stages: the step is named.
        "stack": r"^overflowed its stack in simulationTimestep\(\) \(an endless recursion\?\)",
        # The checker's call was integrator(): a stack naming another hook changes nothing.
        "fakestack": r"^crashed with SIGSEGV in integrator\(\)$",
    }

    def check_all(self, words):
        for word in words:
            with self.subTest(engine=word):
                passed, output, seconds = self.run_fake(word)
                pattern = self.EXPECTED[word]
                self.assertEqual(passed, pattern is None, output)
                if pattern:
                    self.assertRegex(output, pattern)
                # Within its limit of 2 s, stretched at most to this by a busy machine's waits for a core.
                self.assertLess(seconds, running.LOAD_ALLOWANCE * self.LIMITS.seconds)

    def test_in_the_sandbox(self):
        self.assertTrue(sandbox.Sandbox.here().isolated, sandbox.Sandbox.here().reason)
        self.check_all(self.EXPECTED)

    def test_a_busy_machine_leaves_a_test_its_time(self):
        """Two busy programs share the pair's one core: an engine that needs a second of CPU time
        passes within its limit of 2 s, which it outlasts on the wall clock, and an endless loop still
        times out, after 2 s of its own."""
        cores = os.sched_getaffinity(0)
        core = min(cores)
        # Each in a session of its own, as the pair is: where the kernel shares a core between
        # sessions first (autogroups), two programs of one session would take half of it, not two
        # thirds, and the engine would outlast 2 s on the wall clock only by a hair.
        hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"], start_new_session=True,
                                 preexec_fn=lambda: os.sched_setaffinity(0, {core})) for _ in range(2)]
        try:
            os.sched_setaffinity(0, {core})  # this thread, and so the checker and the engine it starts
            passed, output, seconds = self.run_fake("work")
            self.assertTrue(passed, output)
            self.assertGreater(seconds, 2, "the engine had its core to itself: the test shows nothing")
            passed, output, seconds = self.run_fake("loop")
            self.assertFalse(passed)
            self.assertRegex(output, self.EXPECTED["loop"])
        finally:
            os.sched_setaffinity(0, cores)
            for hog in hogs:
                hog.kill()
                hog.wait()

    def test_without_the_sandbox(self):
        with mock.patch.object(sandbox.Sandbox, "_probed", sandbox.Sandbox(None, "switched off for a test")):
            self.check_all(["ok", "crash", "fork", "socket", "memory", "threads", "file", "survive", "eight"])

    def test_without_cgroups(self):
        with mock.patch.object(cgroups.Cgroups, "_probed", cgroups.Cgroups(None, None, None, "off for a test")):
            self.check_all(["ok", "memory", "threads", "survive", "eight"])
        with mock.patch.object(cgroups.Cgroups, "_probed", cgroups.Cgroups(None, None, None, "off for a test")), \
                mock.patch.object(sandbox.Sandbox, "_probed", sandbox.Sandbox(None, "switched off for a test")):
            self.check_all(["ok", "memory", "threads"])

    def test_the_cgroups_here_are_used_and_removed(self):
        here = cgroups.Cgroups.here()
        if not here.available:
            self.skipTest(here.reason)
        self.assertIsNone(here.describe())
        def groups():
            return {p.name for p in here.memory_base.iterdir() if p.name.startswith("gpl-grade-")}

        before = groups()
        self.check_all(["ok", "memory"])
        # Other graders (tests running at the same time) make and remove groups of their own; the ones
        # made here must be gone, at once or (a process still being reaped on a loaded machine) soon.
        deadline = time.monotonic() + 30
        while groups() - before and time.monotonic() < deadline:
            time.sleep(0.1)
        self.assertEqual(groups() - before, set(), "every test's cgroup is removed")

    def test_each_breach_is_named(self):
        limits = sandbox.Limits(2, 100, 8, 64)
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            (tmp / "status.jsonl").write_text('{"event": "ended", "call": "integrator()", "detail": "eof"}\n')

            def verdict(rc, why=None, trace=""):
                pair = running.Pair()
                pair.runner_rc, pair.why, pair.trace, pair.checker_rc = rc, why, trace, 1
                return running.verdict("S.T", pair, limits, tmp, isolated=False)[1]

            self.assertRegex(verdict(-signal.SIGSYS, trace="grader: forbidden system call: network\n"),
                             "^tried to open a network connection in integrator")
            self.assertRegex(verdict(-signal.SIGSYS, trace="grader: forbidden system call: process\n"),
                             "^tried to start a process in integrator")
            self.assertRegex(verdict(-signal.SIGSYS, trace="grader: forbidden system call: namespace\n"),
                             "^tried to make a namespace")
            self.assertRegex(verdict(-signal.SIGXCPU), "^used more than 3 s of CPU time in integrator")
            self.assertRegex(verdict(-signal.SIGXFSZ), "^wrote more than 64 MiB to a file")
            self.assertRegex(verdict(-signal.SIGKILL, "memory"), "^used more than 100 MiB of memory")
            self.assertRegex(verdict(-signal.SIGKILL, "threads"), "^ran more than 8 threads at once")
            self.assertRegex(verdict(-signal.SIGKILL, "timeout"), "^timed out after 2 s")
            self.assertRegex(verdict(-signal.SIGSEGV, trace="grader: stack overflow\n"), "^overflowed its stack in integrator")

    def test_the_call_in_flight_at_a_limit_is_the_checkers_whatever_order_its_notes_came_in(self):
        limits = sandbox.Limits(2, 100, 8, 64)
        ended = '{"event": "ended", "call": "integrator()", "detail": "eof"}\n'
        noted_none = '{"event": "waiting", "call": null}\n'
        noted = '{"event": "waiting", "call": "sphereSphere()"}\n'
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)

            def message(notes):
                (tmp / "status.jsonl").write_text(notes)
                pair = running.Pair()
                pair.runner_rc, pair.why, pair.checker_rc = -signal.SIGKILL, "threads", 1
                return running.verdict("S.T", pair, limits, tmp, isolated=False)[1]

            # The engine ended within integrator() (a refused thread aborted it) and the checker saw
            # that before the grader's question, which then finds no call in flight: integrator().
            self.assertRegex(message(ended + noted_none), r"^ran more than 8 threads at once in integrator\(\)")
            # No call in flight at the limit, and one that ended after it: the limit was broken
            # between calls, and no hook is named.
            self.assertRegex(message(noted_none + ended), r"^ran more than 8 threads at once and was stopped")
            # A note that names its call is believed, whatever ended before it.
            self.assertRegex(message(ended + noted), r"^ran more than 8 threads at once in sphereSphere\(\)")
            self.assertRegex(message(noted), r"^ran more than 8 threads at once in sphereSphere\(\)")
            self.assertRegex(message(ended), r"^ran more than 8 threads at once in integrator\(\)")
            self.assertRegex(message(""), r"^ran more than 8 threads at once and was stopped")

    def test_a_hook_that_names_another_in_its_stack_is_not_believed(self):
        trace = "./gpl-hooks(_ZN3gpl13PhysicsEngine10integratorEv+0x2a)[0x56]\n"
        self.assertEqual(running.blamed_hook("sphereSphere()", trace, ""), "sphereSphere()")
        # Within a whole step, the engine's stack names a stage only among those the checker lists.
        self.assertEqual(running.blamed_hook("simulationTimestep()", trace, ""), "simulationTimestep()")
        self.assertEqual(running.blamed_hook("simulationTimestep()", trace, "", stages=["integrator()"]),
                         "integrator()")
        self.assertEqual(running.blamed_hook("simulationTimestep()", trace, "", stages=["sphereSphere()"]),
                         "simulationTimestep()")
        self.assertIsNone(running.blamed_hook(None, trace, ""))

    def test_tests_declare_their_own_limits(self):
        test = {"time_limit": 20, "memory_limit": 2048, "thread_limit": 0, "file_limit": 0}
        self.assertEqual(sandbox.limits_of(test, sandbox.default_limits(5, 512)),
                         sandbox.Limits(20, 2048, sandbox.DEFAULT_THREADS, sandbox.DEFAULT_FILE_MIB))
        self.assertEqual(sandbox.limits_of({}, 5).memory_mib, sandbox.DEFAULT_MEMORY_MIB)
        for t in programs("solutions").manifest():
            self.assertTrue(all(t[k] >= 0 for k in ("memory_limit", "thread_limit", "file_limit")), t)


# Programs as grade_binary() and test_limits() read them where run_one() is replaced: a release build.
RELEASE_BUILD = type("Release", (), {"sanitizer": False})


class SanitizerTimeLimits(unittest.TestCase):
    """A sanitizer build gives the heavy tests, those with a time limit of their own, that limit times
    SANITIZER_TIME_FACTOR; every other limit, and every limit of a release build, stays as it is."""

    def test_only_a_tests_own_limit_grows_and_only_under_a_sanitizer(self):
        heavy, light = {"name": "W.Heavy", "time_limit": 90}, {"name": "W.Light"}
        release, sanitizer = RELEASE_BUILD, type("Sanitizer", (), {"sanitizer": True})
        self.assertEqual(running.test_limits(release, heavy, 5.0).seconds, 90)
        self.assertEqual(running.test_limits(release, light, 5.0).seconds, 5.0)
        self.assertEqual(running.test_limits(sanitizer, heavy, 5.0).seconds, 90 * running.SANITIZER_TIME_FACTOR)
        self.assertGreater(running.SANITIZER_TIME_FACTOR, 1.0)
        self.assertEqual(running.test_limits(sanitizer, light, 5.0).seconds, 5.0)
        self.assertEqual(running.test_limits(sanitizer, heavy, 5.0).memory_mib,
                         running.test_limits(release, heavy, 5.0).memory_mib)


class TestsAtOnce(unittest.TestCase):
    TESTS = [{"name": n, "worksheet": 1, "points": 1.0, "depends_on": d, "timeout": 5.0}
             for n, d in [("A", []), ("B", ["A"]), ("C", []), ("D", ["C"]), ("E", ["D", "B"]), ("F", ["Z"]),
                          ("G", ["H"]), ("H", []), ("I", ["A"])]]

    def grade(self, jobs):
        """Grades TESTS with run_one() replaced: C fails, each test takes a few milliseconds; returns the
        results and, per test, when it started and ended."""
        times, lock = {}, threading.Lock()

        def run_one(programs, name, limits, guard=None):
            start = time.monotonic()
            time.sleep(0.02)
            with lock:
                times[name] = (start, time.monotonic())
            return name != "C", f"ran {name}", 0.02

        with mock.patch.object(running, "run_one", run_one), mock.patch.object(running, "limits_of",
                                                                            lambda t, d: None):
            return running.grade_binary(RELEASE_BUILD, tests=self.TESTS, jobs=jobs), times

    def test_the_results_are_those_of_one_at_a_time(self):
        alone, _ = self.grade(1)
        together, times = self.grade(3)
        self.assertEqual(together, alone)
        self.assertEqual([r["name"] for r in together], [t["name"] for t in self.TESTS])
        outcome = {r["name"]: (r["passed"], r["not_run"]) for r in together}
        # C fails: D is not run, and so E (D before it); G's prerequisite comes after it, F's is not graded.
        self.assertEqual(outcome, {"A": (True, False), "B": (True, False), "C": (False, False), "D": (False, True),
                                   "E": (False, True), "F": (True, False), "G": (True, False), "H": (True, False),
                                   "I": (True, False)})
        # No test starts before the prerequisites listed before it have ended; some ran at once.
        self.assertGreaterEqual(times["B"][0], times["A"][1])
        self.assertGreaterEqual(times["I"][0], times["A"][1])
        self.assertTrue(any(times[x][0] < times[y][1] and times[y][0] < times[x][1]
                            for x in times for y in times if x < y), times)

    def test_usable_cores_follow_the_cgroup_quota(self):
        here = len(os.sched_getaffinity(0))
        for files, cores in [({"cpu.max": "150000 100000"}, 1), ({"cpu.max": "max 100000"}, here),
                             ({"cpu.max": "50000 100000"}, 1), ({"cpu.max": f"{100000 * (here + 4)} 100000"}, here),
                             ({"cpu/cpu.cfs_quota_us": "100000", "cpu/cpu.cfs_period_us": "100000"}, 1),
                             ({"cpu/cpu.cfs_quota_us": "-1", "cpu/cpu.cfs_period_us": "100000"}, here), ({}, here)]:
            with self.subTest(files=files), tempfile.TemporaryDirectory() as tmp:
                for name, text in files.items():
                    (pathlib.Path(tmp) / name).parent.mkdir(parents=True, exist_ok=True)
                    (pathlib.Path(tmp) / name).write_text(text + "\n")
                self.assertEqual(sandbox.usable_cores(tmp), cores)


class Sandboxing(unittest.TestCase):
    def test_this_machine_allows_the_sandbox(self):
        here = sandbox.Sandbox.here()
        self.assertTrue(here.isolated, here.reason)

    def test_the_fallback_says_why(self):
        with mock.patch("shutil.which", return_value=None):
            self.assertIn("bubblewrap is not installed", sandbox.Sandbox._probe().describe())
        with mock.patch.dict(os.environ, {"GPL_GRADER_SANDBOX": "off"}):
            fallback = sandbox.Sandbox._probe()
        self.assertFalse(fallback.isolated)
        self.assertEqual(fallback.describe().count("\n"), 0, "one line")

    def probe(self, *args, env=None):
        with tempfile.TemporaryDirectory() as tmp, mock.patch.dict(os.environ, env or {}):
            cmd, env, _ = sandbox.Sandbox.here().runner_command(fake("probe"), list(args), tmp, sandbox.default_limits(5),
                                                                env_path("GPL_LAUNCH"))
            proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=20)
        return proc.stdout

    def test_the_sandbox_hides_the_lab_and_the_environment(self):
        if not sandbox.Sandbox.here().isolated:
            self.skipTest("no sandbox here")
        self.assertEqual(self.probe("exists", str(ROOT), "/work", "/root", "/tmp/gpl-lab", "/grader/trace.txt").split(),
                         ["False"] * 4 + ["True"])
        self.assertEqual(self.probe("getenv", "GPL_SECRET", env={"GPL_SECRET": "token"}).strip(), "(none)")

    def test_a_sanitizers_suppression_file_travels_without_showing_the_lab(self):
        # The asan preset names cmake/lsan.supp in LSAN_OPTIONS: the engine sees the file, not where it lies.
        if not sandbox.Sandbox.here().isolated:
            self.skipTest("no sandbox here")
        supp = ROOT / "cmake" / "lsan.supp"
        env = {"LSAN_OPTIONS": f"suppressions={supp}:print_suppressions=0"}
        self.assertEqual(self.probe("getenv", "LSAN_OPTIONS", env=env).strip(),
                         "suppressions=/grader/lsan_options.supp:print_suppressions=0")
        self.assertEqual(self.probe("cat", "/grader/lsan_options.supp", env=env), supp.read_text())

    def test_an_engine_process_is_read_once_and_a_gone_one_is_none(self):
        # A test being stopped can lose a process between two reads of /proc: one read decides.
        with mock.patch.object(sandbox, "_usage", side_effect=[(4096, 1, "gpl-engine"), None]):
            self.assertTrue(running.engine_process(12345))
        with mock.patch.object(sandbox, "_usage", return_value=(4096, 1, "bwrap")):
            self.assertFalse(running.engine_process(12345))
        child = subprocess.Popen(["sleep", "30"])
        try:
            self.assertTrue(running.engine_process(child.pid))
        finally:
            child.kill()
            child.wait()
        self.assertFalse(running.engine_process(child.pid))

    def test_a_batch_never_reserves_more_memory_than_there_is(self):
        budget = sandbox.MemoryBudget(total_mib=2600)  # 80 %: 2080 MiB, room for two tests of 1024
        self.assertEqual(budget.slots(1024), 2)
        budget.reserve(1024)
        budget.reserve(1024)
        third = threading.Thread(target=budget.reserve, args=(1024,))
        third.start()
        third.join(0.3)
        self.assertTrue(third.is_alive(), "a third test waits for memory")
        budget.release(1024)
        third.join(5)
        self.assertFalse(third.is_alive())
        self.assertEqual(budget.running, 2)


class NextStep(unittest.TestCase):
    def test_full_marks_say_what_comes_next(self):
        done = [{"worksheet": 2, "passed": True}]
        files = reports.worksheet_files(ROOT)
        self.assertGreaterEqual(len(files), 3)
        first, last = min(files), max(files)
        self.assertEqual(reports.next_step([{"worksheet": first, "passed": True}], first, ROOT),
                         f"full marks on worksheet {first}. Next: worksheet {first + 1}, {files[first + 1]}")
        self.assertEqual(reports.next_step([{"worksheet": last, "passed": True}], last, ROOT),
                         f"full marks on worksheet {last}: all worksheets done")
        self.assertEqual(reports.next_step(done + [{"worksheet": last, "passed": True}], None, ROOT),
                         "full marks: all worksheets done")
        self.assertIsNone(reports.next_step(done + [{"worksheet": 2, "passed": False}], 2, ROOT))


class Reports(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.solutions = graded("solutions")
        cls.stubs = graded("assignments")

    def test_every_graded_test_has_points_and_a_hint(self):
        for r in self.solutions:
            self.assertGreater(r["points"], 0, r["name"])
            self.assertGreater(len(r["hint"]), 30, r["name"])
            self.assertEqual(r["worksheet"], 1)

    def test_gradescope_results_are_valid(self):
        self.assertTrue(CHECK_GRADESCOPE.is_file(), f"{CHECK_GRADESCOPE} is missing")
        with tempfile.TemporaryDirectory() as tmp:
            for results, expected_score in ((self.solutions, None), (self.stubs, 0)):
                path = pathlib.Path(tmp) / "results.json"
                data = reports.gradescope(results, 1.5)
                reports.write_atomically(path, json.dumps(data))
                proc = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), str(path)], capture_output=True, text=True)
                self.assertEqual(proc.returncode, 0, proc.stdout)
                self.assertEqual(data["max_score"], sum(r["points"] for r in results))
                if expected_score is not None:
                    self.assertEqual(data["score"], expected_score)
                    self.assertTrue(all(t["status"] == "failed" for t in data["tests"]))
                    # The stubs fail only because their hooks are open: each test says so, no hint.
                    self.assertTrue(all(t["output"].startswith(("hooks still not implemented: ", "not run: depends on"))
                                        for t in data["tests"]), data["tests"])
                    self.assertFalse(any("hint:" in t["output"] for t in data["tests"]))
                else:
                    self.assertEqual(data["score"], data["max_score"])

    def test_junit_counts_failures(self):
        tree = ET.fromstring(reports.junit(self.stubs, "stubs"))
        suite = tree.find("testsuite")
        self.assertEqual(suite.get("name"), "worksheet1")
        not_run = sum(r["not_run"] for r in self.stubs)
        self.assertGreater(not_run, 0)
        self.assertEqual(int(suite.get("failures")), len(self.stubs) - not_run)
        self.assertEqual(int(suite.get("skipped")), not_run)
        self.assertEqual(len(suite.findall("testcase/failure")), len(self.stubs) - not_run)
        self.assertEqual(len(suite.findall("testcase/skipped")), not_run)
        tree = ET.fromstring(reports.junit(self.solutions, "solutions"))
        self.assertEqual(tree.find("testsuite").get("failures"), "0")

    def test_table_ends_with_the_count_line(self):
        text = reports.table(self.stubs, "stubs")
        not_run = sum(r["not_run"] for r in self.stubs)
        self.assertEqual(text.splitlines()[-1], f"0 of {len(self.stubs)} tests passed: "
                                                f"{len(self.stubs) - not_run} failed, {not_run} not run")
        self.assertEqual(reports.table(self.solutions, "solutions").splitlines()[-1],
                         f"{len(self.solutions)} of {len(self.solutions)} tests passed")

    def test_the_stubs_report_fits_a_screen(self):
        # Worksheet 1's stubs: one line for the open hooks, one for the tests that wait for them.
        text = reports.table(self.stubs, "stubs")
        self.assertLessEqual(len(text.splitlines()), 8, text)
        self.assertRegex(text, r"\nnot written yet: integrator\(\) simulationTimestep\(\) — \d+ tests, 0 / \d+ points "
                               r"\(Worksheet1\.GravityIndependentOfMass, ")
        self.assertIn("\nnot run until those pass — ", text)
        self.assertNotIn("hint:", text)
        # UsesEngineTimeStep builds engines of its own (no fixture note): the engine's report of
        # the stubs it ran groups it with the others.
        uses = next(r for r in self.stubs if r["name"] == "Worksheet1.UsesEngineTimeStep")
        self.assertTrue(uses["output"].startswith("hooks still not implemented: integrator()"), uses["output"])
        # JUnit keeps one entry per test, with the short message.
        tree = ET.fromstring(reports.junit(self.stubs, "stubs"))
        for failure in tree.iter("failure"):
            self.assertTrue(failure.get("message").startswith("hooks still not implemented: "), failure.get("message"))

    def test_stub_failures_say_which_hooks_are_open(self):
        open_hooks = [r for r in self.stubs if "hooks still not implemented" in r["output"]]
        self.assertGreater(len(open_hooks), len(self.stubs) // 2)
        self.assertTrue(all(r["output"].startswith("hooks still not implemented") for r in open_hooks))

    def test_unknown_test_name_is_a_failure_not_a_pass(self):
        passed, output, _ = running.run_one(programs("solutions"), "Worksheet1.NoSuchTest", running.limits_of({}, 10))
        self.assertFalse(passed)
        self.assertIn("not found", output)


def fake_result(name, output, passed=False, not_run=False, points=2, depends_on=()):
    return {"name": name, "worksheet": 1, "points": points, "hint": f"hint of {name}", "hidden": False,
            "depends_on": list(depends_on), "passed": passed, "not_run": not_run,
            "score": points if passed else 0.0, "seconds": 0.1, "output": output}


ENERGY_ABORT = ("crashed with SIGABRT (abort: a failed assert or an uncaught exception) in integrator()\n"
                "gpl-hooks-x: assignments/integrator.cpp:37: void gpl::PhysicsEngine::integrator(): Assertion "
                "`energyAfter <= energyBefore + 1e-12' failed.")


class Feedback(unittest.TestCase):
    """What the reports say: one cause once, hints only where the evidence points, no GoogleTest noise."""

    def results(self):
        return [fake_result("W.A", ENERGY_ABORT), fake_result("W.B", ENERGY_ABORT),
                fake_result("W.C", "velocity is (0, 0, 0), expected (0, -0.0981, 0) (off by 0.098100000000000007)"),
                fake_result("W.D", "timed out after 5 s in integrator() (an endless loop?)"),
                fake_result("W.E", "not run: depends on W.A, which did not pass; fix that first", not_run=True,
                            depends_on=["W.A"]),
                fake_result("W.F", "", passed=True),
                fake_result("W.G", ENERGY_ABORT.replace("37:", "38:").replace("energyAfter <= energyBefore + 1e-12",
                                                                               "x.isFinite()"))]

    def test_one_cause_is_said_once_first(self):
        text = reports.table(self.results(), "t")
        lines = text.splitlines()
        self.assertEqual(lines[1], "2 tests stopped on the same failed assertion, in integrator():")
        self.assertIn("assignments/integrator.cpp:37: assert(energyAfter <= energyBefore + 1e-12)", lines[2])
        self.assertIn("explicit Euler's signature: x += h v with the old velocity", lines[3])
        self.assertEqual(text.count("stopped on the same failed assertion (above)"), 2)
        self.assertEqual(text.count("energyAfter"), 1, text)
        # A different assert (W.G, alone) keeps its own message, without the hint of its test.
        self.assertIn("x.isFinite()", text)
        self.assertNotIn("hint of W.G", text)
        self.assertEqual(reports.meaning("a.isFinite()").split()[0], "a")
        self.assertEqual(reports.meaning("n > 0"), reports.GENERIC_MEANING)

    def test_the_step_an_assertion_ended_is_named(self):
        in_step = lambda n: ENERGY_ABORT.replace("in integrator()\n", f"in integrator() in step {n}\n")
        # The same step everywhere: said once, in the cause's first line.
        text = reports.table([fake_result("W.A", in_step(1)), fake_result("W.B", in_step(1))], "t")
        self.assertIn("2 tests stopped on the same failed assertion, in integrator(), in step 1:", text)
        self.assertEqual(text.count("in step"), 1, text)
        # Different steps: each test says its own.
        text = reports.table([fake_result("W.A", in_step(1)), fake_result("W.B", in_step(250))], "t")
        self.assertIn("2 tests stopped on the same failed assertion, in integrator():", text)
        self.assertRegex(text, r"W\.A .*\n +\| stopped on the same failed assertion \(above\), in step 1\n")
        self.assertRegex(text, r"W\.B .*\n +\| stopped on the same failed assertion \(above\), in step 250\n")
        tests = {t["name"]: t["output"] for t in reports.gradescope(
            [fake_result("W.A", in_step(1)), fake_result("W.B", in_step(250))], 1.0)["tests"]}
        self.assertTrue(tests["W.B"].startswith("crashed with SIGABRT (abort: a failed assert or an uncaught "
                                                "exception) in integrator() in step 250: stopped on the same"))

    def test_gradescope_says_the_cause_once_and_each_test_alone(self):
        data = reports.gradescope(self.results(), 1.0, notes="sandbox: bubblewrap")
        tests = {t["name"]: t["output"] for t in data["tests"]}
        self.assertIn("2 tests stopped on the same failed assertion", data["output"])
        self.assertIn("sandbox: bubblewrap", data["output"])
        self.assertIn("Assertion `energyAfter", tests["W.A"])          # the full message in the first
        self.assertIn("explicit Euler's signature", tests["W.A"])
        self.assertEqual(tests["W.B"], "crashed with SIGABRT (abort: a failed assert or an uncaught exception) "
                                       "in integrator(): stopped on the same failed assertion as W.A")
        self.assertNotIn("hint:", tests["W.A"] + tests["W.B"] + tests["W.D"] + tests["W.E"])
        self.assertIn("hint: hint of W.C", tests["W.C"])
        with tempfile.TemporaryDirectory() as tmp:
            path = pathlib.Path(tmp) / "results.json"
            reports.write_atomically(path, json.dumps(data))
            proc = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), str(path)], capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout)
        # A hidden test never carries the whole message that visible tests point at.
        results = self.results()
        results[0]["hidden"] = True
        tests = {t["name"]: t["output"] for t in reports.gradescope(results, 1.0)["tests"]}
        self.assertIn("Assertion `energyAfter", tests["W.B"])
        self.assertTrue(tests["W.A"].endswith("stopped on the same failed assertion as W.B"))

    def test_hints_only_for_a_tests_own_failure(self):
        text = reports.table(self.results(), "t")
        self.assertIn("hint: hint of W.C", text)
        for name in ("W.A", "W.B", "W.D", "W.E", "W.F"):
            self.assertNotIn(f"hint of {name}", text)
        self.assertIn("| timed out after 5 s in integrator()", text)

    def test_footer_and_numbers(self):
        text = reports.table(self.results(), "t")
        self.assertEqual(text.splitlines()[-2:], ["total: 2 / 14 points", "1 of 7 tests passed: 5 failed, 1 not run"])
        self.assertIn("(off by 0.0981)", text)

    def test_googletest_text_is_stripped(self):
        self.assertEqual(reports.clean("Expected: (b.velocity.y()) < (0.0), actual: 0 vs 0"),
                         "expected b.velocity.y() < 0.0, got 0 vs 0")
        self.assertEqual(reports.clean('unknown file: Failure\nC++ exception with description "bad thing" '
                                       "thrown in the test body."), "bad thing")
        self.assertEqual(reports.clean("h = 0.0050000000000000001 s, off by 0.098100000000000007, "
                                       "1.00199019, 0.100000 kg, 1e-12, 14323.9"),
                         "h = 0.005 s, off by 0.0981, 1.00199, 0.100000 kg, 1e-12, 14323.9")
        # Digits inside names and paths are left alone.
        for text in ("body_0.1234567890 at v1.23456789/x.cpp:12", "file2.123456789.cpp:4"):
            self.assertEqual(reports.clean(text), text)

    def test_open_hooks_are_grouped_one_line_each(self):
        results = [fake_result(f"W.O{i}", "hooks still not implemented: a() b()\nvelocity is 0") for i in range(4)]
        results += [fake_result("W.P", "hooks still not implemented: c()"),
                    fake_result("W.N", "not run: depends on W.O1", not_run=True, depends_on=["W.O1"]),
                    fake_result("W.Q", "off by 1")]
        lines = reports.table(results, "t").splitlines()
        self.assertIn("not written yet: a() b() — 4 tests, 0 / 8 points (W.O0, W.O1, ...)", lines)
        self.assertIn("not written yet: c() — 1 test, 0 / 2 points (W.P)", lines)
        self.assertIn("not run until those pass — 1 test, 0 / 2 points (W.N)", lines)
        self.assertEqual(sum(l.startswith("W.") for l in lines), 1)  # W.Q alone keeps its row
        data = reports.gradescope(results, 1.0)
        self.assertEqual(len(data["tests"]), len(results))
        self.assertEqual(data["tests"][0]["output"], "hooks still not implemented: a() b()")

    def graded_mutant(self, name):
        """The report of worksheet 1 for a seeded mistake's engine (the test is skipped if it is not built)."""
        engine = pathlib.Path(env_path("GPL_CHECKER")).parent / f"gpl-hooks-mutant_{name}"
        if not engine.is_file():
            self.skipTest(f"{engine} is not built")
        results = running.grade_binary(running.Programs(env_path("GPL_CHECKER"), engine, env_path("GPL_LAUNCH")), 1)
        return reports.table(results, name)

    def test_explicit_euler_says_its_assertion_once(self):
        text = self.graded_mutant("explicit_euler")
        # Explicit Euler's energy grows in the first step of every run.
        self.assertRegex(text, r"\n\d+ tests stopped on the same failed assertion, in integrator\(\), in step 1:\n"
                               r"  \S*integrator\.cpp:\d+: assert\(stageActive[^\n]*energyAfter <= energyBefore")
        self.assertIn("explicit Euler's signature", text)
        self.assertEqual(text.count("Assertion `"), 0)
        self.assertNotIn("hint:", text)
        self.assertRegex(text, r"OneStepIsSemiImplicitEuler +0 / \d+ +FAIL\n +\| stopped on the same failed assertion \(above\)")

    def test_a_body_no_longer_finite_is_said_once_as_the_student_readme_says(self):
        text = self.graded_mutant("static_bodies_force_over_mass")
        self.assertRegex(text, r"\n\d+ tests stopped early: body 'floor' is no longer finite after step 1 "
                               r"\(t = 0\.01 s\): check integrator\(\)\n  what it usually means: ")
        self.assertNotIn("hint:", text)
        self.assertNotIn("unknown file", text)
        self.assertNotIn("Expected:", text)
        # The student README's table quotes the grader's words ("…" stands for what varies).
        readme = (ROOT / "docs" / "student-README.md").read_text()
        row = re.search(r"^\| `(stopped early: body '…' is no longer finite)` \| (.*) \|$", readme, re.M)
        self.assertIsNotNone(row, "the student README has no row for a body no longer finite")
        self.assertRegex(text, re.escape(row.group(1)).replace("…", "[^']+"))
        self.assertIn(reports.meaning("isFinite(x)"), text)
        self.assertIn(row.group(2), reports.meaning("isFinite(x)"))


class Declarations(unittest.TestCase):
    def test_prerequisites_come_first_and_circles_are_refused(self):
        tests = [{"name": "S.C", "depends_on": ["S.B"]}, {"name": "S.A", "depends_on": []},
                 {"name": "S.B", "depends_on": ["S.A"]}]
        self.assertEqual([t["name"] for t in running.in_dependency_order(tests)], ["S.A", "S.B", "S.C"])
        tests[1]["depends_on"] = ["S.C"]
        with self.assertRaisesRegex(grade.GradeError, "circle: S.C -> S.B -> S.A -> S.C"):
            running.in_dependency_order(tests)
        with self.assertRaisesRegex(grade.GradeError, "S.A depends on S.X, which is not a graded test"):
            running.in_dependency_order([{"name": "S.A", "depends_on": ["S.X"]}])

    def test_manifest_declares_limits_prerequisites_and_hidden_tests(self):
        tests = {t["name"]: t for t in programs("solutions").manifest()}
        self.assertIn("Worksheet1.GravityPointsDown", tests["Worksheet1.EnergyNeverIncreases"]["depends_on"])
        self.assertTrue(any(t["hidden"] for t in tests.values()))
        self.assertTrue(all(t["time_limit"] >= 0 for t in tests.values()))

    def test_stubs_report_not_run_with_the_prerequisite(self):
        stubs = {r["name"]: r for r in graded("assignments")}
        energy = stubs["Worksheet1.EnergyNeverIncreases"]
        self.assertTrue(energy["not_run"])
        self.assertEqual(energy["score"], 0)
        self.assertTrue(energy["output"].startswith("not run: depends on Worksheet1.GravityPointsDown"))

    def test_hidden_tests_visibility_is_configurable(self):
        # What Gradescope's file says of hidden tests depends on the list, not on a run: every test
        # of the checker, as if passed.
        results = [{**t, "passed": True, "not_run": False, "score": t["points"], "seconds": 0.0, "output": ""}
                   for t in programs("solutions").manifest()]
        for visibility in ("hidden", "after_published"):
            data = reports.gradescope(results, 1.0, visibility)
            hidden = [t for t, r in zip(data["tests"], results) if r["hidden"]]
            self.assertTrue(hidden)
            self.assertTrue(all(t["visibility"] == visibility for t in hidden))
            self.assertEqual(data["stdout_visibility"], "hidden")

    def test_a_seeded_mistake_must_be_caught_by_its_own_test(self):
        # The reference passes the named test: the self-check must say WRONG, not OK.
        with contextlib.redirect_stdout(io.StringIO()) as out:
            status = grade.main(["selfcheck", "--checker", env_path("GPL_CHECKER"), "--hooks",
                                 env_path("GPL_HOOKS_SOLUTIONS"), "--mutant", "explicit_euler"])
        self.assertEqual(status, 1)
        self.assertIn("WRONG: 'position updated with the old velocity (explicit Euler)' is not caught", out.getvalue())
        # Graded on the named test's worksheet only.
        self.assertIn("Worksheet1.OneStepIsSemiImplicitEuler", out.getvalue())
        self.assertNotIn("Worksheet2.", out.getvalue())


class HooksInTraces(unittest.TestCase):
    def test_the_innermost_hook_of_a_call_stack(self):
        trace = ("./autograder(+0x1234)[0x55]\n"
                 "/lib/x86_64-linux-gnu/libc.so.6(+0x3c050)[0x7f]\n"
                 "./autograder(_ZN3gpl13PhysicsEngine10integratorEv+0x2a)[0x56]\n"
                 "./autograder(_ZN3gpl13PhysicsEngine18simulationTimestepEv+0x10)[0x57]\n"
                 "./autograder(_ZN3gpl13PhysicsEngine4stepEv+0x10)[0x58]\n")
        self.assertEqual(running.hook_in_trace(trace), "integrator()")
        self.assertIsNone(running.hook_in_trace("./autograder(_ZN3gpl13PhysicsEngine4stepEv+0x10)[0x58]\n"))

    def test_a_failed_assert_names_its_function(self):
        output = ("autograder: /x/integrator.cpp:25: void gpl::PhysicsEngine::integrator(): "
                  "Assertion `isFinite(b.position)' failed.")
        self.assertEqual(running.hook_in_trace("", output), "integrator()")


class GuardTest(unittest.TestCase):
    def test_changes_are_undone_and_kept_aside(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = pathlib.Path(tmp) / "lab"
            (root / "tests").mkdir(parents=True)
            (root / "worksheets").mkdir()
            (root / "tests" / "a_test.cpp").write_text("original")
            guard = Guard(root, pathlib.Path(tmp) / "quarantine")
            self.assertEqual(guard.check(), [])
            (root / "tests" / "a_test.cpp").write_text("weakened")
            (root / "tests" / "new.cpp").write_text("injected")
            (root / "worksheets" / "notes.md").write_text("not guarded")
            (root / "README.md").write_text("not guarded either")
            (root / "lab").write_text("guarded")
            self.assertEqual(guard.check(), ["lab", "tests/a_test.cpp", "tests/new.cpp"])
            self.assertFalse((root / "lab").exists())
            self.assertEqual((root / "tests" / "a_test.cpp").read_text(), "original")
            self.assertFalse((root / "tests" / "new.cpp").exists())
            kept = sorted(p.name for p in (pathlib.Path(tmp) / "quarantine").rglob("*") if p.is_file())
            self.assertEqual(kept, ["a_test.cpp", "lab", "new.cpp"])
            (root / "tests" / "a_test.cpp").unlink()
            self.assertEqual(guard.check(), ["tests/a_test.cpp"])
            self.assertEqual((root / "tests" / "a_test.cpp").read_text(), "original")


class Similarity(unittest.TestCase):
    """The batch's similarity report: copies found however renamed, the stubs' text never counted."""

    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.tmp = pathlib.Path(tmp.name)

    def submission(self, name, files):
        folder = self.tmp / name
        folder.mkdir()
        for file, text in files.items():
            (folder / file).write_text(text)
        return folder

    def test_copies_pair_up_and_stubs_do_not(self):
        solution = (ROOT / "solutions" / "collision_impulse.cpp").read_text()
        # A copy with every name changed and the layout squeezed: the same tokens apart from names.
        renamed = solution.replace("vn", "vrel").replace("const double w ", "const double wsum ")
        renamed = renamed.replace("(w == 0.0", "(wsum == 0.0").replace("/ w;", "/ wsum;").replace("    ", "  ")
        # Another way to the same impulse: reduced mass and a velocity difference of its own.
        other = (ROOT / "assignments" / "collision_impulse.cpp").read_text().replace(
            '    kernelNotImplemented("applyCollisionImpulse()");\n',
            "    const Vec3 dv = b.velocity - a.velocity;\n"
            "    const double vn = dv.dot(contact.normal);\n"
            "    if (vn >= 0.0 || a.isStatic() && b.isStatic()) return;\n"
            "    const double mu = 1.0 / (a.invMass + b.invMass);\n"
            "    const Vec3 impulse = -(1.0 + contact.restitution) * mu * vn * contact.normal;\n"
            "    a.velocity = a.velocity - a.invMass * impulse;\n"
            "    b.velocity = b.velocity + b.invMass * impulse;\n")
        stub = (ROOT / "assignments" / "collision_impulse.cpp").read_text()
        subs = {"ann": self.submission("ann", {"collision_impulse.cpp": solution}),
                "bob": self.submission("bob", {"collision_impulse.cpp": renamed}),
                "cat": self.submission("cat", {"collision_impulse.cpp": other}),
                "dan": self.submission("dan", {"collision_impulse.cpp": stub}),
                "eve": self.submission("eve", {"collision_impulse.cpp": stub})}
        rows = similarity.compare(subs, ["collision_impulse.cpp", "integrator.cpp"], ROOT / "assignments")
        pairs = {(a, b): percent for percent, a, b, _ in rows}
        self.assertGreaterEqual(pairs.get(("ann", "bob"), 0), 90, rows)
        self.assertGreaterEqual(pairs.get(("bob", "ann"), 0), 90, rows)
        self.assertEqual(rows[0][1:3] in {("ann", "bob"), ("bob", "ann")}, True, rows)
        # Two untouched stubs share the whole stub, which is left out: they never pair.
        self.assertFalse([r for r in rows if "dan" in r[1:3] or "eve" in r[1:3]], rows)
        self.assertTrue(all(percent >= 20 for percent, *_ in rows))
        self.assertIn("ann in bob", similarity.summary(rows))

    def test_nothing_to_compare(self):
        subs = {"only": self.submission("only", {"integrator.cpp": "int x;\n"})}
        self.assertEqual(similarity.compare(subs, ["integrator.cpp"], ROOT / "assignments"), [])
        self.assertIn("no pair", similarity.summary([]))


class CommandLine(unittest.TestCase):
    def grade_py(self, *args):
        return subprocess.run([sys.executable, str(ROOT / "tools" / "grade.py"), *map(str, args)],
                              capture_output=True, text=True)

    def test_bad_options_are_one_line_errors(self):
        for args, message in [(["grade", "--build-dir", "b", "--bogus"], "unrecognized arguments: --bogus"),
                              (["grade"], "required: --build-dir"),
                              (["grade", "--build-dir", "b", "--timeout", "0"], "--timeout must be a positive"),
                              (["grade", "--build-dir", "b", "--memory", "-5"], "--memory must be a positive"),
                              (["report", "--checker", env_path("GPL_CHECKER"), "--hooks",
                                env_path("GPL_HOOKS_SOLUTIONS"), "--worksheet", "10"],
                               "no graded tests for worksheet 10; the worksheets with graded tests: 1, 2"),
                              (["report", "--checker", "c", "--hooks", "h", "--worksheet", "x"],
                               "invalid int value: 'x' (./lab grade --help for help)"),
                              (["report", "--checker", "/nonexistent", "--hooks", env_path("GPL_HOOKS_SOLUTIONS")],
                               "checker not found"),
                              (["nonsense"], "invalid choice")]:
            with self.subTest(args=args):
                proc = self.grade_py(*args)
                self.assertEqual(proc.returncode, 2)
                self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
                self.assertIn(message, proc.stderr)


class Files(unittest.TestCase):
    def test_write_atomically_refuses_a_missing_folder_and_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(grade.GradeError):
                reports.write_atomically(pathlib.Path(tmp) / "nope" / "results.json", "{}")
            self.assertEqual(list(pathlib.Path(tmp).iterdir()), [])

    def test_submission_folder_checks(self):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            with self.assertRaisesRegex(grade.GradeError, "not found"):
                building.prepare_submission(tmp / "missing", tmp / "hooks")
            (tmp / "empty").mkdir()
            with self.assertRaisesRegex(grade.GradeError, "none of the hook files"):
                building.prepare_submission(tmp / "empty", tmp / "hooks")
            sub = tmp / "sub"
            sub.mkdir()
            (sub / "integrator.cpp").write_text("// mine\n")
            (sub / "report.pdf").write_text("not code")
            missing, ignored, _ = building.prepare_submission(sub, tmp / "hooks")
            self.assertEqual((tmp / "hooks" / "integrator.cpp").read_text(), "// mine\n")
            self.assertIn("simulation_timestep.cpp", missing)
            self.assertEqual(ignored, ["report.pdf"])
            self.assertEqual((tmp / "hooks" / "simulation_timestep.cpp").read_text(),
                             (ROOT / "assignments" / "simulation_timestep.cpp").read_text())


    def test_symbolic_links_are_not_followed(self):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            sub = tmp / "sub"
            sub.mkdir()
            (sub / "integrator.cpp").symlink_to(ROOT / "solutions" / "integrator.cpp")
            (sub / "sphere_plane.cpp").write_text("// mine\n")
            (sub / "everything").symlink_to("/")
            missing, ignored, _ = building.prepare_submission(sub, tmp / "hooks")
            self.assertIn("integrator.cpp", missing, "a hook file that is a link is graded as the stub")
            self.assertEqual((tmp / "hooks" / "integrator.cpp").read_text(),
                             (ROOT / "assignments" / "integrator.cpp").read_text())
            self.assertEqual(ignored, ["everything", "integrator.cpp"])
            (tmp / "link").symlink_to(ROOT / "solutions")
            with self.assertRaisesRegex(grade.GradeError, "is a symbolic link"):
                building.prepare_submission(tmp / "link", tmp / "hooks2")
            whole = tmp / "lab"
            whole.mkdir()
            (whole / "assignments").symlink_to(ROOT / "solutions")
            with self.assertRaisesRegex(grade.GradeError, "none of the hook files"):
                building.prepare_submission(whole, tmp / "hooks3")


class Hooks(unittest.TestCase):
    def test_stub_replaces_the_solution_block(self):
        text = "a\n    // BEGIN SOLUTION\n    secret();\n    // ELSE STUB\n    // notImplemented(\"x\");\n    // END SOLUTION\nb\n"
        self.assertEqual(hooks.stub(text), "a\n    notImplemented(\"x\");\nb\n")

    def test_malformed_markers_are_errors(self):
        for text in ("// BEGIN SOLUTION\nx\n", "// ELSE STUB\n", "// BEGIN SOLUTION\n// ELSE STUB\nnot commented\n// END SOLUTION\n",
                     "// END SOLUTION\n"):
            with self.assertRaises(hooks.HookError, msg=text):
                hooks.stub(text)

    def test_no_solution_code_reaches_the_assignments(self):
        for name in hooks.hook_files():
            solution = (ROOT / "solutions" / name).read_text()
            student = (ROOT / "assignments" / name).read_text()
            self.assertNotIn(hooks.BEGIN, student)
            if hooks.BEGIN in solution:
                self.assertNotIn("b.position += h * b.velocity", student)

    def test_mutants_keep_the_files_they_leave_alone_byte_for_byte(self):
        # The build compiles only the files that differ from the reference's (cmake/Variants.cmake).
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
            hooks.write_mutants(tmp)
            for m in hooks.load_mutants():
                changed = {c["file"] for c in m["changes"]}
                for name in hooks.hook_files():
                    same = (pathlib.Path(tmp) / m["name"] / name).read_text() == (ROOT / "solutions" / name).read_text()
                    self.assertEqual(same, name not in changed, f"{m['name']}: {name}")

    def test_every_mutant_changes_the_code_and_names_a_test(self):
        for m in hooks.load_mutants():
            self.assertTrue(m["changes"], m["name"])
            self.assertTrue(m["must_fail"].startswith("Worksheet"), m["name"])
            for change in m["changes"]:
                self.assertNotEqual(change["from"], change["to"], m["name"])

    def test_alternatives_replace_their_files_with_code_of_their_own_in_rounds(self):
        # Compared without comments and spacing: a reworded or reindented copy of the reference is no
        # alternative.
        def bare(code):
            return "".join(line.split("//")[0].replace(" ", "") for line in code.splitlines())

        alternatives = hooks.load_alternatives()
        self.assertTrue(alternatives)
        by_name = {alt["name"]: alt for alt in alternatives}
        for alt in alternatives:
            self.assertIn(alt["file"], hooks.hook_files(), alt["name"])
            self.assertTrue(alt["why"].strip(), alt["name"])
            reference = hooks.solution_blocks((ROOT / "solutions" / alt["file"]).read_text())
            self.assertEqual(len(alt["blocks"]), len(reference), alt["name"])
            for mine, theirs in zip(alt["blocks"], reference):
                self.assertNotEqual(bare(mine), bare(theirs), f"{alt['name']}: the reference's code")
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()) as printed:
            hooks.write_alternatives(tmp)
            self.check_rounds(tmp, printed.getvalue(), alternatives, by_name)

    def check_rounds(self, tmp, printed, alternatives, by_name):
        lines = [line.split(" ") for line in printed.splitlines()]
        rounds = {name: members.split(",") for name, _, members in lines}
        # Every alternative in exactly one round, as many rounds as the most alternatives of one file.
        self.assertEqual(sorted(n for members in rounds.values() for n in members), sorted(by_name))
        most = max(sum(a["file"] == alt["file"] for a in alternatives) for alt in alternatives)
        self.assertEqual(list(rounds), [f"round{k}" for k in range(1, most + 1)])
        for name, worksheet, members in lines:
            chosen = {by_name[n]["file"]: by_name[n] for n in members.split(",")}
            self.assertEqual(len(chosen), len(members.split(",")), f"{name}: two alternatives of one file")
            self.assertEqual(int(worksheet), min(hooks.hook_worksheet(f) for f in chosen), name)
            # The round's files carry their alternatives' code, every other file the reference's.
            for file in hooks.hook_files():
                text = (pathlib.Path(tmp) / name / file).read_text()
                reference = (ROOT / "solutions" / file).read_text()
                if file in chosen:
                    self.assertEqual(text, hooks.with_blocks(reference, chosen[file]["blocks"]), f"{name}: {file}")
                    self.assertNotIn(hooks.BEGIN, text, f"{name}: {file}")
                else:
                    self.assertEqual(text, reference, f"{name}: {file}")

    def test_a_malformed_alternative_is_a_one_line_error(self):
        good = {"name": "x", "why": "another way", "file": "integrator.cpp", "code": "    return;\n"}
        for entries, says in [("[", "worksheet9.json: not valid JSON"),
                              ({"name": "x"}, "expects a list of alternatives"),
                              ([{**good, "name": ""}], "alternative 1 has no name"),
                              ([good, good], "duplicate alternative names: x"),
                              ([{**good, "file": "nowhere.cpp"}], "'nowhere.cpp' is not a hook file"),
                              ([{k: v for k, v in good.items() if k != "why"}], "'why' must be a non-empty string"),
                              ([{**good, "code": 3}], "'code' must be a non-empty string"),
                              ([{**good, "code": ["a", ""]}], "'code' must be a non-empty string"),
                              ([{**good, "file": "box_box.cpp"}], "has 2 solution block(s), the alternative gives 1"),
                              ([{**good, "file": "student_scenes.cpp"}], "has 0 solution block(s)")]:
            with self.subTest(says=says), tempfile.TemporaryDirectory() as tmp:
                folder = pathlib.Path(tmp) / "alternatives"
                folder.mkdir()
                (folder / "worksheet9.json").write_text(entries if isinstance(entries, str) else json.dumps(entries))
                err = io.StringIO()
                with mock.patch.object(hooks, "ALTERNATIVES", folder), contextlib.redirect_stderr(err), \
                        contextlib.redirect_stdout(io.StringIO()):
                    self.assertEqual(hooks.main(["alternatives", str(pathlib.Path(tmp) / "out")]), 1)
                self.assertEqual(len(err.getvalue().strip().splitlines()), 1, err.getvalue())
                self.assertIn(says, err.getvalue())
                self.assertFalse((pathlib.Path(tmp) / "out").exists(), "nothing written for a malformed set")

    def test_selfcheck_from_a_worksheet_on_says_what_it_cannot_do_in_one_line(self):
        # What grader.alternatives.* runs: the tests of the round's earliest worksheet and the later ones.
        for extra, says in [(["--expect", "full", "--worksheet", "5"], "--from-worksheet goes with --expect"),
                            (["--mutant", "x"], "--from-worksheet goes with --expect"),
                            (["--expect", "full"], "no graded tests for worksheet 10 or later; the worksheets with "
                                                   "graded tests: 1, 2")]:
            with self.subTest(extra=extra):
                proc = subprocess.run([sys.executable, str(ROOT / "tools" / "grade.py"), "selfcheck", "--checker",
                                       env_path("GPL_CHECKER"), "--hooks", env_path("GPL_HOOKS_SOLUTIONS"),
                                       "--from-worksheet", "10", *extra], capture_output=True, text=True)
                self.assertEqual(proc.returncode, 2, proc.stdout[-500:])
                self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
                self.assertIn(says, proc.stderr)


    def test_selfcheck_leaves_out_the_tests_named(self):
        # What the asan-core preset's self-check of the solutions runs: every test but those named.
        left_out = ["Worksheet1.StaysFinite", "Worksheet1.GravityPointsDown"]
        with contextlib.redirect_stdout(io.StringIO()) as out:
            status = grade.main(["selfcheck", "--checker", env_path("GPL_CHECKER"), "--hooks",
                                 env_path("GPL_HOOKS_SOLUTIONS"), "--expect", "full", "--worksheet", "1",
                                 "--leave-out", ",".join(left_out)])
        self.assertEqual(status, 0, out.getvalue())
        self.assertIn("OK: full marks", out.getvalue())
        graded = [t["name"] for t in programs("solutions").manifest() if t["worksheet"] == 1]
        for name in graded:
            if name in left_out:
                self.assertNotIn(name, out.getvalue())
            else:
                self.assertIn(name, out.getvalue())
        # A name that is no graded test, or --leave-out beside a seeded mistake: one line, status 2.
        for extra, says in [(["--expect", "full", "--leave-out", "Worksheet1.StaysFinit"],
                             "--leave-out: no graded test is named Worksheet1.StaysFinit"),
                            (["--mutant", "explicit_euler", "--leave-out", "Worksheet1.StaysFinite"],
                             "--leave-out goes with --expect, not with --mutant")]:
            with self.subTest(extra=extra):
                proc = subprocess.run([sys.executable, str(ROOT / "tools" / "grade.py"), "selfcheck", "--checker",
                                       env_path("GPL_CHECKER"), "--hooks", env_path("GPL_HOOKS_SOLUTIONS"), *extra],
                                      capture_output=True, text=True)
                self.assertEqual(proc.returncode, 2, proc.stdout[-500:])
                self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
                self.assertIn(says, proc.stderr)

if __name__ == "__main__":
    unittest.main()
