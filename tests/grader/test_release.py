"""The student release and the Gradescope autograder, built from scratch in temporary folders:
the release builds and passes its own tests, its stubs score zero, and neither solution code nor
hidden tests leaked into it; the autograder's setup.sh and run_autograder grade submissions in a
fake /autograder tree (GPL_AUTOGRADER_ROOT) into results.json files that Gradescope accepts."""
import functools
import json
import os
import pathlib
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Runs a command on a virtual display of its own (tools/headless.py); the status is the command's.
HEADLESS = [sys.executable, str(ROOT / "tools" / "headless.py")]
sys.path.insert(0, str(ROOT / "tools"))
from grading import running  # noqa: E402
import hooks  # noqa: E402
import release as release_tool  # noqa: E402

CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"


def run(cmd, cwd, env=None, timeout=400):
    return subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})})


@functools.lru_cache(maxsize=None)
def solution_code():
    """Each line of reference code between BEGIN SOLUTION and ELSE STUB (braces and comments aside),
    unless the public engine holds the same line."""
    public = {l.strip() for p in (ROOT / "framework").rglob("*") if p.is_file() for l in p.read_text().splitlines()}
    lines = set()
    for name in hooks.hook_files():
        inside = False
        for line in (ROOT / "solutions" / name).read_text().splitlines():
            if line.strip() == hooks.BEGIN:
                inside = True
            elif line.strip() in (hooks.ELSE, hooks.END):
                inside = False
            elif inside and len(line.strip()) > 3 and not line.strip().startswith("//") and line.strip() not in public:
                lines.add(line.strip())
    assert len(lines) >= 5, lines
    return lines


def hidden_tests():
    hidden = [t for t in running.checker_manifest(pathlib.Path(os.environ["GPL_TESTS_DIR"]) / "gpl-checker") if t["hidden"]]
    assert hidden, "there is at least one hidden test"
    return hidden


def readme_commands(text):
    """Every ./lab command the README shows: the lines of its sh blocks and its inline code."""
    commands, in_sh = [], False
    for line in text.splitlines():
        if line.strip().startswith("```"):
            in_sh = line.strip() == "```sh"
        elif in_sh and line.strip():
            commands.append(line.strip())
    commands += re.findall(r"`(\./lab [^`]*)`", text)
    return list(dict.fromkeys(commands))


# A window that fails to open, or a scene that fails in its first steps, ends the viewer within a
# second or two (the viewer is built beforehand): 8 s of it running show both went well.
WINDOW_SECONDS = 8


def is_window(command):
    """Whether a README command opens a viewer window."""
    args = shlex.split(command)
    return args[1] == "viewer" and not {"--headless", "--help"} & set(args)


def command_works(test, release, command):
    """Runs one command of the README in the release as a student would, without a display. Grading
    exits 1 while the stubs lose points: that is the command working."""
    args = shlex.split(command)
    test.assertEqual(args[0], "./lab", command)
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    proc = run(args, release, env=env)
    test.assertIn(proc.returncode, (0, 1) if args[1] == "grade" else (0,),
                  f"{command}:\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    if args[1] == "grade":
        test.assertIn("total:", proc.stdout, command)


def windows_work(test, release, commands):
    """Opens the README's viewer windows at once, each on a virtual display of its own, as a student
    would type them; each must still be open after WINDOW_SECONDS, with no error on its output."""
    if not commands:
        return
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for flags in {tuple(a for a in shlex.split(c)[2:] if a in ("--reference", "--debug")) for c in commands}:
        # Built first (./lab viewer --help builds the same viewer), so that the seconds are the window's.
        built = run(["./lab", "viewer", *flags, "--help"], release, env={"DISPLAY": ""}, timeout=400)
        test.assertEqual(built.returncode, 0, built.stdout[-2000:] + built.stderr[-2000:])
    opened = {command: subprocess.Popen([*HEADLESS, *shlex.split(command)], cwd=release, env=env, text=True,
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
              for command in commands}
    time.sleep(WINDOW_SECONDS)
    ended = {command: proc.poll() for command, proc in opened.items()}
    for command, proc in opened.items():
        if ended[command] is None:
            os.killpg(proc.pid, signal.SIGTERM)
        out, err = proc.communicate()
        with test.subTest(command=command):
            test.assertIsNone(ended[command], f"{command} ended within {WINDOW_SECONDS} s:\n{out[-2000:]}{err[-2000:]}")
            test.assertNotIn("error", err, command)


def ghost(test, release, *script):
    """The state the release's viewer dumps on the projectile with --ghost, after the script."""
    proc = run([release / "lab", "viewer", "--headless", "projectile", "--ghost", "--script",
                "; ".join([*script, "dump", "quit"])], release)
    test.assertEqual(proc.returncode, 0, proc.stdout[-2000:] + proc.stderr[-2000:])
    states = [json.loads(l[len("state "):]) for l in proc.stdout.splitlines() if l.startswith("state ")]
    test.assertEqual(len(states), 1, proc.stdout[-2000:])
    return states[0], proc.stdout


# Words of the instructors' README that a student's has no use for.
INSTRUCTORS_ONLY = ["--batch", "--solutions", "./lab release", "./lab gradescope", "seeded", "mutant", "selfcheck",
                    "solutions/", "--similarity", "instructor/"]


def all_text(folder):
    return {p: p.read_text(errors="replace") for p in folder.rglob("*")
            if p.is_file() and "build" not in p.relative_to(folder).parts}


class StudentRelease(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-release-"))
        cls.release = cls.tmp / "lab-release"
        cls.made = run([ROOT / "lab", "release", cls.release], ROOT)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_written(self):
        self.assertEqual(self.made.returncode, 0, self.made.stdout + self.made.stderr)
        for path in ("lab", "README.md", "framework/src/engine.cpp", "tests/autograder/worksheet1_test.cpp",
                     "tests/grading/launch.cpp", "worksheets/01-time-stepping.md", "tools/grade.py",
                     "cmake/hook_files.txt"):
            self.assertTrue((self.release / path).is_file(), path)
        self.assertEqual([p.name for p in self.tmp.iterdir() if p.name.startswith(".")], [], "no leftovers beside it")

    def test_nothing_for_instructors_only(self):
        for path in ("solutions", "tests/mutants", "tests/grader", "worksheets/instructor", "bench/instructor",
                     "tools/release.py", ".ci"):
            self.assertFalse((self.release / path).exists(), path)
        self.assertEqual(list((self.release / "tests" / "autograder").glob("*hidden*")), [])

    def test_assignments_are_the_stubs(self):
        for name, text in hooks.expected_assignments().items():
            self.assertEqual((self.release / "assignments" / name).read_text(), text)

    def test_no_solution_code_leaked(self):
        for path, text in all_text(self.release).items():
            for line in solution_code():
                self.assertNotIn(line, text, f"{path.relative_to(self.release)} holds solution code")

    def test_no_hidden_test_leaked(self):
        texts = all_text(self.release)
        for t in hidden_tests():
            suite, name = t["name"].split(".")
            for path, text in texts.items():
                self.assertNotIn(name, text, path)
                self.assertNotIn(t["hint"][:40], text, path)

    def test_the_leak_check_finds_a_leak(self):
        leaky = self.tmp / "leaky"
        shutil.copytree(self.release, leaky, ignore=shutil.ignore_patterns("build"))
        (leaky / "assignments" / "integrator.cpp").write_text((ROOT / "solutions" / "integrator.cpp").read_text())
        proc = run([sys.executable, ROOT / "tools" / "release.py", "leaks", leaky], ROOT)
        self.assertEqual(proc.returncode, 1, proc.stdout)
        self.assertIn("assignments/integrator.cpp", proc.stdout)
        shutil.rmtree(leaky)
        proc = run([sys.executable, ROOT / "tools" / "release.py", "leaks", self.release], ROOT)
        self.assertEqual(proc.returncode, 0, proc.stdout)

    @classmethod
    def lab_test(cls):
        """`./lab test` in the release, run once."""
        if not hasattr(cls, "tested"):
            cls.tested = run([cls.release / "lab", "test"], cls.release, timeout=800)
        return cls.tested

    def test_builds_on_its_own_passes_its_tests_and_the_stubs_score_zero(self):
        tested = self.lab_test()
        self.assertEqual(tested.returncode, 0, tested.stdout[-3000:] + tested.stderr[-3000:])
        self.assertIn("100% tests passed", tested.stdout)
        results = self.release / "results.json"
        graded = run([self.release / "lab", "grade", "--json", results], self.release)
        self.assertEqual(graded.returncode, 1, graded.stdout + graded.stderr)
        data = json.loads(results.read_text())
        self.assertEqual(data["score"], 0)
        public = [t for t in running.checker_manifest(pathlib.Path(os.environ["GPL_TESTS_DIR"]) / "gpl-checker")
                  if not t["hidden"]]
        self.assertEqual([t["name"] for t in data["tests"]], [t["name"] for t in public])
        self.assertEqual(data["max_score"], sum(t["points"] for t in public))
        ran = run([self.release / "lab", "run", "--steps", "3"], self.release)
        self.assertIn("hooks not implemented yet", ran.stdout)
        # Instructors' commands refuse, in one line.
        for cmd in (["release", self.tmp / "again"], ["grade", "--solutions"]):
            proc = run([self.release / "lab", *cmd], self.release)
            self.assertEqual(proc.returncode, 2, proc.stdout + proc.stderr)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)

    def test_a_compile_error_scores_zero_with_the_errors(self):
        # The release has no solutions: the list of tests comes from its own checker, the errors
        # from the compiler, with the student's own file name. Graded as a student has the release
        # after ./lab test (its build's stub objects spare the grading their compiling).
        self.lab_test()
        hook = self.release / "assignments" / "integrator.cpp"
        text = hook.read_text()
        results = self.tmp / "broken.json"
        try:
            hook.write_text(text + "\nthis is not C++\n")
            graded = run([self.release / "lab", "grade", "--worksheet", "1", "--json", results], self.release)
        finally:
            hook.write_text(text)
        self.assertEqual(graded.returncode, 1, graded.stdout + graded.stderr)
        self.assertIn("the code does not compile; every test scores zero. First errors:", graded.stdout)
        self.assertIn(f"{hook}:", graded.stdout)
        data = json.loads(results.read_text())
        self.assertEqual(data["score"], 0)
        public = [t["name"] for t in running.checker_manifest(pathlib.Path(os.environ["GPL_TESTS_DIR"]) / "gpl-checker")
                  if not t["hidden"] and t["worksheet"] == 1]
        self.assertEqual([t["name"] for t in data["tests"]], public)
        self.assertTrue(all("does not compile" in t["output"] for t in data["tests"]))

    def test_readme_is_for_students(self):
        text = (self.release / "README.md").read_text()
        self.assertEqual(text, release_tool.student_readme(demo=False))
        for words in INSTRUCTORS_ONLY:
            self.assertNotIn(words, text)
        for worksheet in sorted((ROOT / "worksheets").glob("0*.md")):
            self.assertIn(f"worksheets/{worksheet.name}", text)
        self.assertNotIn("--reference", text, "this release has no reference engine")
        self.assertNotIn("<!--", text)

    def test_readme_commands_work(self):
        commands = readme_commands((self.release / "README.md").read_text())
        self.assertGreaterEqual(len(commands), 10, commands)
        for command in commands:
            if is_window(command):
                continue
            with self.subTest(command=command):
                if command == "./lab test":  # the test above runs it, as typed, in this release
                    self.assertEqual(self.lab_test().returncode, 0)
                else:
                    command_works(self, self.release, command)
        windows = [c for c in commands if is_window(c)]
        self.assertGreaterEqual(len(windows), 2, commands)
        windows_work(self, self.release, windows)

    def test_no_ghost_and_no_reference(self):
        state, out = ghost(self, self.release, "key o", "wait 30")
        self.assertFalse(state["ghost"])
        self.assertIn("no reference ghost in this build", out)
        proc = run([self.release / "lab", "run", "--reference"], self.release)
        self.assertEqual(proc.returncode, 2, proc.stdout + proc.stderr)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("--reference-demo", proc.stderr)

    def test_refuses_an_existing_folder_or_one_inside_the_lab(self):
        occupied = self.tmp / "occupied"
        occupied.mkdir()
        (occupied / "mine.txt").write_text("keep me")
        for target, message in ((occupied, "already exists"), (ROOT / "build" / "rel", "inside the lab")):
            proc = run([ROOT / "lab", "release", target], ROOT)
            self.assertEqual(proc.returncode, 2)
            self.assertIn(message, proc.stderr)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertEqual([p.name for p in occupied.iterdir()], ["mine.txt"])
        self.assertFalse((ROOT / "build" / "rel").exists())


class ReferenceDemo(unittest.TestCase):
    """./lab release DIR --reference-demo: the reference engine compiled, without its source. The
    release's viewer draws the ghost (the reference's motion) and ./lab run --reference prints the
    reference's numbers."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-demo-"))
        cls.release = cls.tmp / "lab-release"
        cls.made = run([ROOT / "lab", "release", cls.release, "--reference-demo"], ROOT, timeout=500)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_written_with_binaries_only(self):
        self.assertEqual(self.made.returncode, 0, self.made.stdout + self.made.stderr)
        files = sorted(p.relative_to(self.release / "reference") for p in (self.release / "reference").rglob("*")
                       if p.is_file())
        self.assertEqual([str(f) for f in files],
                         sorted([f"hooks/{name}.o" for name in hooks.hook_files()] + ["libgpl_reference.a"]))
        for path in ("solutions", "tests/mutants", "tests/grader", "tools/release.py"):
            self.assertFalse((self.release / path).exists(), path)
        proc = run([sys.executable, ROOT / "tools" / "release.py", "leaks", self.release], ROOT)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        for path, text in all_text(self.release).items():
            for line in solution_code():
                self.assertNotIn(line, text, f"{path.relative_to(self.release)} holds solution code")

    def test_readme_shows_the_demo(self):
        text = (self.release / "README.md").read_text()
        self.assertIn("./lab run --reference", text)
        for words in INSTRUCTORS_ONLY:
            self.assertNotIn(words, text)
        plain = readme_commands(release_tool.student_readme(demo=False))
        demo_only = [c for c in readme_commands(text) if c not in plain]
        self.assertGreaterEqual(len(demo_only), 2, demo_only)
        for command in demo_only:
            if not is_window(command):
                with self.subTest(command=command):
                    command_works(self, self.release, command)
        windows_work(self, self.release, [c for c in demo_only if is_window(c)])

    def test_run_reference_prints_the_references_numbers(self):
        proc = run([self.release / "lab", "run", "--reference", "--scene", "projectile", "--steps", "200"], self.release)
        self.assertEqual(proc.returncode, 0, proc.stdout[-2000:] + proc.stderr[-2000:])
        self.assertNotIn("not implemented", proc.stdout)
        # Semi-implicit Euler in free fall changes the energy by exactly -m g^2 h^2 / 2 per step:
        # 0.5 kg, h = 0.01 s: -0.0024059025 J. The summary prints 6 significant digits (-0.0024059
        # here): equal to within half of the last (5e-8 J); rounding over 200 steps is far smaller.
        drift = float(re.search(r"([-+][0-9.e-]+) J per step", proc.stdout).group(1))
        self.assertAlmostEqual(drift, -0.5 * 9.81 ** 2 * 0.01 ** 2 / 2, delta=5e-8)
        stub = run([self.release / "lab", "run", "--scene", "projectile", "--steps", "200"], self.release)
        self.assertIn("hooks not implemented yet", stub.stdout)

    def test_viewer_shows_the_ghost(self):
        state, _ = ghost(self, self.release, "wait 29")
        self.assertTrue(state["ghost"])
        # The stubs leave the ball where it was thrown from; the ghost flies with 15 m/s at 45
        # degrees, so the largest difference is the reference's displacement after t: the closed
        # form of the throw (semi-implicit Euler is off by n h^2 g / 2 = 1.5 cm at 0.3 s: 2 %).
        t = state["time"]
        self.assertGreater(t, 0.25)
        v = 15 / 2 ** 0.5
        expected = ((v * t) ** 2 + (v * t - 9.81 * t * t / 2) ** 2) ** 0.5
        self.assertAlmostEqual(state["ghost_difference"], expected, delta=0.02 * expected)

    def test_the_study_with_the_reference(self):
        proc = run([self.release / "lab", "bench", "contacts", "--reference", "--out", self.tmp / "contacts"],
                   self.release, timeout=500)
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:] + proc.stderr[-3000:])
        self.assertIn("every hook it needs is written", proc.stdout)


class GradescopeAutograder(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-gradescope-"))
        cls.bundle = cls.tmp / "autograder"
        cls.made = run([ROOT / "lab", "gradescope", cls.bundle], ROOT)
        # The tree Gradescope builds: the zip unpacked to source/, setup.sh run once.
        cls.fake = cls.tmp / "fake-root"
        if cls.made.returncode == 0:
            shutil.unpack_archive(str(cls.bundle) + ".zip", cls.fake / "source", "zip")
            for script in ("setup.sh", "run_autograder", "lab"):
                (cls.fake / "source" / script).chmod(0o755)
            cls.setup = run([cls.fake / "source" / "setup.sh"], cls.fake / "source", timeout=500)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def grade(self, files):
        """Runs run_autograder on a submission {relative path: text}; returns results.json."""
        submission = self.fake / "submission"
        shutil.rmtree(submission, ignore_errors=True)
        shutil.rmtree(self.fake / "results", ignore_errors=True)
        submission.mkdir()
        for rel, text in files.items():
            (submission / rel).parent.mkdir(parents=True, exist_ok=True)
            (submission / rel).write_text(text)
        proc = run([self.fake / "source" / "run_autograder"], self.tmp, env={"GPL_AUTOGRADER_ROOT": str(self.fake)})
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        results = self.fake / "results" / "results.json"
        check = run([sys.executable, CHECK_GRADESCOPE, results], self.tmp)
        self.assertEqual(check.returncode, 0, check.stdout)
        return json.loads(results.read_text())

    def test_bundle_holds_hidden_tests_but_no_solutions(self):
        self.assertEqual(self.made.returncode, 0, self.made.stdout + self.made.stderr)
        for path in ("setup.sh", "run_autograder", "tools/grade.py", "assignments/integrator.cpp"):
            self.assertTrue((self.bundle / path).is_file(), path)
        self.assertTrue(list((self.bundle / "tests" / "autograder").glob("*_hidden_test.cpp")))
        for path in ("solutions", "tests/mutants", "tests/grader", "worksheets"):
            self.assertFalse((self.bundle / path).exists(), path)
        for path, text in all_text(self.bundle).items():
            for line in solution_code():
                self.assertNotIn(line, text, path)
        self.assertIn("--hidden-visibility after_published", (self.bundle / "run_autograder").read_text())
        self.assertIn("libgtest-dev", (self.bundle / "setup.sh").read_text())

    def test_setup_builds(self):
        self.assertEqual(self.setup.returncode, 0, self.setup.stdout[-3000:] + self.setup.stderr[-3000:])
        # The stubs' engine too: their objects seed every grading, so a file left as handed out
        # compiles nothing.
        self.assertTrue((self.fake / "source" / "build" / "release" / "tests" / "gpl-hooks-assignments").is_file())

    def full_marks(self):
        """The results of a submission that earns full marks: here the solutions."""
        return self.grade({n: (ROOT / "solutions" / n).read_text() for n in hooks.hook_files()})

    def test_full_marks_with_hidden_tests_after_publishing(self):
        data = self.full_marks()
        self.assertEqual(data["score"], data["max_score"])
        hidden = {t["name"] for t in hidden_tests()}
        self.assertEqual({t["name"] for t in data["tests"] if t["visibility"] == "after_published"}, hidden)
        self.assertTrue(all(t["visibility"] == "visible" for t in data["tests"] if t["name"] not in hidden))
        self.assertEqual(data["stdout_visibility"], "hidden", "the printout names hidden tests")
        self.assertEqual(data["max_score"], sum(t["points"] for t in running.checker_manifest(
            pathlib.Path(os.environ["GPL_TESTS_DIR"]) / "gpl-checker")))
        # The bundle grades with the lab's own grader, so in the same sandbox with the same limits.
        self.assertIn("sandbox: each test ran in bubblewrap", data["output"])

    def test_a_whole_repository_with_a_mistake(self):
        text = (ROOT / "solutions" / "integrator.cpp").read_text()
        update = "        b.velocity += h * b.acceleration;\n        b.position += h * b.velocity;\n"
        self.assertIn(update, text)
        files = {"assignments/integrator.cpp": text.replace(update, "".join(reversed(update.splitlines(True)))),
                 "assignments/simulation_timestep.cpp": (ROOT / "solutions" / "simulation_timestep.cpp").read_text(),
                 "README.md": "my repository", "tests/autograder/worksheet1_test.cpp": "// mine"}
        data = self.grade(files)
        tests = {t["name"]: t for t in data["tests"]}
        self.assertEqual(tests["Worksheet1.OneStepIsSemiImplicitEuler"]["status"], "failed")
        # Graded with assertions on, as everywhere: the energy assertion it keeps fires and is named,
        # in every test it stopped, and said once (its condition) in the results' output.
        self.assertIn("in integrator()", tests["Worksheet1.OneStepIsSemiImplicitEuler"]["output"])
        self.assertIn("stageActive(Stage::Springs)", data["output"])
        hidden = next(t["name"] for t in hidden_tests() if t["worksheet"] == 1)  # it needs the integrator
        self.assertTrue(tests[hidden]["output"].startswith("not run: depends on"), tests[hidden]["output"])
        self.assertIn("ignored (only hook files are graded): README.md, tests/autograder/worksheet1_test.cpp",
                      data["output"])

    def test_a_submission_without_hook_files_still_gets_results(self):
        data = self.grade({"report.pdf": "not code"})
        self.assertEqual(data["score"], 0)
        self.assertIn("none of the hook files", data["output"])


if __name__ == "__main__":
    unittest.main()
