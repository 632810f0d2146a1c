"""Command-line errors: every option of every ./lab command and program, given a bad value (or none,
or one that does not exist), exits with status 2 and prints one line on stderr that names the
option and says what it expects. Nothing is built or graded: each command stops at its arguments."""
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Runs a command on a virtual display of its own (tools/headless.py); the status is the command's.
HEADLESS = [sys.executable, str(ROOT / "tools" / "headless.py")]
RUN = os.environ.get("GPL_RUN_SOLUTIONS")
VIEWER = os.environ.get("GPL_VIEWER_SOLUTIONS")
BENCH = os.environ.get("GPL_BENCH_SOLUTIONS")
BENCH_CONTACTS = os.environ.get("GPL_BENCH_CONTACTS_SOLUTIONS")
# Libraries to preload into the viewer in a sanitizer build (tests/CMakeLists.txt says why).
PRELOAD = ["env", f"LD_PRELOAD={os.environ['GPL_VIEWER_PRELOAD']}"] if os.environ.get("GPL_VIEWER_PRELOAD") else []
UNWRITABLE = "/proc/gpl-no-folder-here"  # /proc refuses new folders, even to root

# (arguments, the option the line must name, what else it must say)
RUNNER_CASES = [
    (["--scene", "nowhere"], "--scene", "expects a scene name or key"),
    (["-s", "F13"], "--scene", "got 'F13'"),
    (["--steps", "abc"], "--steps", "expects a whole number of 0 or more, got 'abc'"),
    (["--steps", "-1"], "--steps", "got '-1'"),
    (["--steps", "2.5"], "--steps", "got '2.5'"),
    (["-n", "x"], "--steps", "got 'x'"),
    (["--steps"], "--steps", "required"),
    (["--dt", "abc"], "--dt", "expects a time in seconds above 0"),
    (["--dt", "0"], "--dt", "got '0'"),
    (["--dt", "-0.01"], "--dt", "got '-0.01'"),
    (["--dt", "nan"], "--dt", "got 'nan'"),
    (["--dt", "inf"], "--dt", "got 'inf'"),
    (["--integrator", "leapfrog"], "--integrator", "expects explicit-euler, semi-implicit-euler"),
    (["--csv", UNWRITABLE + "/out.csv"], "--csv", "cannot write"),
    (["--bogus"], "--bogus", "--help lists the options"),
]
VIEWER_CASES = [
    (["nowhere"], "scene", "expects a scene name or key"),
    (["--scene", "nowhere"], "--scene", "got 'nowhere'"),
    (["--frames", "abc"], "--frames", "expects a whole number"),
    (["--frames", "-3"], "--frames", "got '-3'"),
    (["projectile", "--frames", "2"], "--frames", "expects --out DIR"),  # ./lab viewer --headless without --out
    (["--out", UNWRITABLE], "--out", "expects a folder"),
    (["--record", UNWRITABLE], "--record", "expects a folder"),
    (["--steps", "many"], "--steps", "expects a whole number of 0 or more"),
    (["--dt", "0"], "--dt", "expects a time in seconds above 0"),
    (["--width", "10"], "--width", "expects a whole number from 64 to 8192, got '10'"),
    (["--height", "tall"], "--height", "got 'tall'"),
    (["--bogus"], "--bogus", "--help lists the options"),
]
BENCH_CASES = [
    (["--out", UNWRITABLE], "--out", "expects a folder"),
    (["--out"], "--out", "required"),
    (["--bogus"], "--bogus", "--help lists the options"),
]
# ./lab and the tools; none of these builds anything (each stops at its arguments).
LAB_CASES = [
    (["nowhere"], "nowhere", "./lab help"),
    (["bench", "speed"], "bench", "expects a study, accuracy, contacts, engine or stages, got 'speed'"),
    (["bench", "accuracy", "--out"], "--out", "expects a folder"),
    (["bench", "contacts", "--bogus"], "--bogus", "--out DIR"),
    (["bench", "engine", "--bogus"], "--bogus", "--sizes N..."),
    (["bench", "engine", "--threads"], "--threads", "needs 1 or 2"),
    (["bench", "engine", "--shape", "cone"], "--shape", "expects sphere or box, got 'cone'"),
    (["bench", "engine", "--shape"], "--shape", "needs sphere or box"),
    (["bench", "cloth", "--threads"], "--threads", "expects 1 or 2"),
    (["bench", "cloth", "--threads", "1", "3"], "--threads", "expects 1 or 2, got '3'"),
    (["assignments", "--bogus"], "--bogus", "--check or --write"),
    (["assignments", "--check", "--write"], "assignments", "expects one option"),
    (["release"], "dir", "required"),
    (["release", "/tmp/gpl-x", "--bogus"], "--bogus", "unrecognized"),
    (["gradescope", "/tmp/gpl-x", "--hidden-visibility", "sometimes"], "--hidden-visibility", "choose from"),
    (["grade", "--worksheet", "one"], "--worksheet", "invalid int value: 'one'"),
    (["grade", "--timeout", "soon"], "--timeout", "invalid float value: 'soon'"),
    (["grade", "--memory", "lots"], "--memory", "invalid float value: 'lots'"),
    (["test", "--preset", "fastest"], "--preset", "expects release, debug, asan, asan-core or clang, got 'fastest'"),
]
TOOL_CASES = [
    (["tools/release.py"], "release|gradescope|leaks", "required"),
    (["tools/release.py", "publish"], "release|gradescope|leaks", "invalid choice: 'publish'"),
    (["tools/release.py", "leaks", "/nonexistent-folder"], "dir", "expects a folder that exists"),
    (["tools/release.py", "release", "/tmp/gpl-x", "--reference-demo=yes"], "--reference-demo", "ignored explicit"),
    (["tools/hooks.py"], "stub|check|write|mutants|files", "required"),
    (["tools/hooks.py", "regenerate"], "stub|check|write|mutants|files", "invalid choice: 'regenerate'"),
    (["tools/hooks.py", "stub", "/nonexistent.cpp"], "file", "expects a file that exists"),
    (["tools/hooks.py", "write", "--backup"], "--backup", "expected one argument"),
    (["tools/hooks.py", "check", "--bogus"], "--bogus", "unrecognized"),
    (["tools/headless.py", "--size", "1x", "true"], "--size", "got '1x'"),
    (["tools/headless.py", "--size"], "--size", "expects WIDTHxHEIGHT"),
    (["tools/headless.py"], "COMMAND", "usage"),
]


class CommandLineErrors(unittest.TestCase):
    def check(self, cmd, option, says, env=None):
        with self.subTest(cmd=" ".join(map(str, cmd))):
            proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=120, cwd=ROOT,
                                  env={**os.environ, **(env or {})})
            lines = proc.stderr.strip().splitlines()
            self.assertEqual(proc.returncode, 2, proc.stdout[-1000:] + proc.stderr[-1000:])
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertIn(option, lines[0])
            self.assertIn(says, lines[0])

    @unittest.skipUnless(RUN, "GPL_RUN_SOLUTIONS names the runner")
    def test_runner(self):
        for args, option, says in RUNNER_CASES:
            self.check([RUN, *args], option, says)

    @unittest.skipUnless(VIEWER, "GPL_VIEWER_SOLUTIONS names the viewer")
    def test_viewer(self):
        # The options are checked before the window opens: no display is needed.
        for args, option, says in VIEWER_CASES:
            self.check([VIEWER, *args], option, says, env={"DISPLAY": ""})

    @unittest.skipUnless(VIEWER, "GPL_VIEWER_SOLUTIONS names the viewer")
    def test_viewer_script(self):
        cmd = [*HEADLESS, "--size", "320x240", *PRELOAD, VIEWER, "--width", "320", "--height", "240",
               "--script", "wait 1; jump"]
        self.check(cmd, "--script", "got 'jump'")

    @unittest.skipUnless(BENCH and BENCH_CONTACTS, "GPL_BENCH_SOLUTIONS and GPL_BENCH_CONTACTS_SOLUTIONS name the studies")
    def test_studies(self):
        for program in (BENCH, BENCH_CONTACTS):
            for args, option, says in BENCH_CASES:
                self.check([program, *args], option, says)

    def test_lab(self):
        for args, option, says in LAB_CASES:
            self.check([ROOT / "lab", *args], option, says)

    def test_lab_run_passes_the_runners_errors_on(self):
        # ./lab run builds the runner first (nothing to do after ./lab test), then the runner says it.
        self.check([ROOT / "lab", "run", "--steps", "abc"], "--steps", "expects a whole number of 0 or more, got 'abc'")

    def test_tools(self):
        for args, option, says in TOOL_CASES:
            self.check([sys.executable, *args], option, says)

    def test_headless_gives_the_commands_status_on_a_display_of_its_own(self):
        # Four at once, each on its own display; a status of the command's and not of the display's.
        runs = [subprocess.Popen([*HEADLESS, "sh", "-c", f'echo "$DISPLAY"; exit {status}'], text=True,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE) for status in (0, 2, 3, 5)]
        results = [(run.communicate(timeout=60), run.returncode) for run in runs]
        self.assertEqual([status for _, status in results], [0, 2, 3, 5], [err for (_, err), _ in results])
        displays = [out.strip() for (out, _), _ in results]
        self.assertEqual(len(set(displays)), 4, displays)
        self.assertTrue(all(d.startswith(":") and d[1:].isdigit() for d in displays), displays)
        killed = subprocess.run([*HEADLESS, "sh", "-c", "kill -TERM $$"], capture_output=True, timeout=60)
        self.assertEqual(killed.returncode, 128 + 15, "a command ended by SIGTERM")
        missing = subprocess.run([*HEADLESS, "/nonexistent-program"], capture_output=True, text=True, timeout=60)
        self.assertEqual((missing.returncode, len(missing.stderr.splitlines())), (127, 1), missing.stderr)

    def test_a_good_value_is_taken(self):
        # The checks let good values through: the same options with values that are right.
        if not RUN:
            self.skipTest("GPL_RUN_SOLUTIONS names the runner")
        with tempfile.TemporaryDirectory() as tmp:
            proc = subprocess.run([RUN, "--scene", "3", "--steps", "2", "--dt", "0.005", "--integrator", "rk4",
                                   "--csv", os.path.join(tmp, "run.csv")], capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            self.assertIn("h = 0.005 s", proc.stdout)
            self.assertIn("integrator: RK4", proc.stdout)


if __name__ == "__main__":
    unittest.main()
