"""End to end: ./lab grade --submission DIR on a student's folder, as an instructor runs it."""
import hashlib
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"


def tree_digest(folder):
    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        if p.is_file():
            h.update(str(p.relative_to(folder)).encode() + p.read_bytes())
    return h.hexdigest()


def lab_grade(*args):
    return subprocess.run([str(ROOT / "lab"), "grade", *map(str, args)], capture_output=True, text=True, cwd=ROOT)


class Submission(unittest.TestCase):
    def setUp(self):
        self.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-submission-"))
        self.before = tree_digest(ROOT / "assignments"), tree_digest(ROOT / "solutions")

    def tearDown(self):
        self.assertEqual((tree_digest(ROOT / "assignments"), tree_digest(ROOT / "solutions")), self.before,
                         "grading a submission changed the working tree")
        shutil.rmtree(self.tmp)

    def submission(self, integrator_from, to=None):
        sub = self.tmp / "student"
        sub.mkdir()
        for name in ("simulation_timestep.cpp", "student_scenes.cpp"):
            shutil.copy(ROOT / "solutions" / name, sub / name)
        text = (ROOT / "solutions" / "integrator.cpp").read_text()
        if to is not None:
            self.assertIn(integrator_from, text)
            text = text.replace(integrator_from, to)
        (sub / "integrator.cpp").write_text(text)
        (sub / "README.txt").write_text("my notes")
        return sub

    def test_explicit_euler_submission_loses_the_named_test(self):
        # A folder staged by an older lab, before a worksheet added hook files, must not stop the
        # grading (it holds only some of today's hook files).
        stale = ROOT / "build" / "release-submission" / "submissions" / "staged-by-an-older-lab"
        stale.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / "solutions" / "integrator.cpp", stale / "integrator.cpp")
        sub = self.submission("        b.velocity += h * b.acceleration;\n        b.position += h * b.velocity;\n",
                              "        b.position += h * b.velocity;\n        b.velocity += h * b.acceleration;\n")
        results = self.tmp / "results.json"
        proc = lab_grade("--submission", sub, "--json", results)
        self.assertEqual(proc.returncode, 1, proc.stdout + proc.stderr)
        self.assertIn("ignored (only hook files are graded): README.txt", proc.stdout)
        # Hook files are graded with assertions on: the reference's energy assertion, which this
        # submission keeps, fires in every test that steps, and the grader says it once, first,
        # naming its hook (the function that asserts), its file:line and what it usually means.
        line = next(i for i, l in enumerate((sub / "integrator.cpp").read_text().splitlines(), 1)
                    if "assert(stageActive" in l)
        # Explicit Euler's energy grows in the first step of every run: the step is said once too.
        self.assertRegex(proc.stdout, r"\d+ tests stopped on the same failed assertion, in integrator\(\), in step 1:\n"
                                      rf"  \S*integrator\.cpp:{line}: assert\(stageActive[^\n]*\n"
                                      r"  what it usually means: the total energy grew in a step")
        self.assertEqual(proc.stdout.count("assert(stageActive"), 1, proc.stdout)
        self.assertIn("stopped on the same failed assertion (above)", proc.stdout)
        data = json.loads(results.read_text())
        # Each test alone (Gradescope): the first with the whole message, the others in one line;
        # the hook named there is the checker's call in flight (the integrator, or the whole step).
        outputs = [t["output"] for t in data["tests"] if t["status"] == "failed" and t["output"].startswith("crashed")]
        self.assertRegex(outputs[0], r"^crashed with SIGABRT \(abort: a failed assert or an uncaught exception\) "
                                     r"in (integrator|simulationTimestep)\(\)")
        self.assertIn(f"integrator.cpp:{line}: void gpl::PhysicsEngine::integrator(): Assertion `stageActive", outputs[0])
        self.assertTrue(all("stopped on the same failed assertion as" in o for o in outputs[1:]), outputs)
        self.assertIn("stopped on the same failed assertion", data["output"])
        failed = {t["name"] for t in data["tests"] if t["status"] == "failed"}
        self.assertIn("Worksheet1.OneStepIsSemiImplicitEuler", failed)
        self.assertLess(data["score"], data["max_score"])
        check = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), str(results)], capture_output=True, text=True)
        self.assertEqual(check.returncode, 0, check.stdout)

    def test_a_submission_that_does_not_compile_scores_zero_with_the_error(self):
        sub = self.submission("b.position += h * b.velocity;", "b.position += h * b.velocity")
        results = self.tmp / "results.json"
        proc = lab_grade("--submission", sub, "--json", results)
        self.assertEqual(proc.returncode, 1, proc.stdout + proc.stderr)
        data = json.loads(results.read_text())
        self.assertEqual(data["score"], 0)
        self.assertTrue(all("does not compile" in t["output"] and "integrator.cpp" in t["output"] for t in data["tests"]))
        self.assertIn(str(sub), data["tests"][0]["output"], "errors name the student's file, not a build path")

    def test_a_missing_folder_is_a_one_line_error_and_writes_nothing(self):
        results = self.tmp / "results.json"
        proc = lab_grade("--submission", self.tmp / "nobody", "--json", results)
        self.assertEqual(proc.returncode, 2)
        self.assertEqual(proc.stderr.strip().count("\n"), 0, proc.stderr)
        self.assertIn("submission folder not found", proc.stderr)
        self.assertFalse(results.exists())

    def test_bad_input_is_a_one_line_error_and_writes_nothing(self):
        sub = self.submission("", None)
        (self.tmp / "empty").mkdir()
        results = self.tmp / "results.json"
        for args, message in [(("--submission", self.tmp / "empty"), "holds none of the hook files"),
                              (("--submission", sub, "--worksheet", "10"), "no graded tests for worksheet 10; the worksheets"),
                              (("--submission", sub, "--worksheet", "x"), "(./lab grade --help for help)"),
                              (("--submission", sub, "--colour"), "unrecognized arguments: --colour"),
                              (("--submission", sub, "--solutions"), "not allowed with argument"),
                              (("--submission", sub, "--json", self.tmp), "it is a folder")]:
            with self.subTest(args=args):
                proc = lab_grade(*args, *(("--json", results) if "--json" not in args else ()))
                self.assertEqual(proc.returncode, 2, proc.stdout + proc.stderr)
                self.assertEqual(proc.stderr.strip().count("\n"), 0, proc.stderr)
                self.assertIn(message, proc.stderr)
                self.assertFalse(results.exists())

    def test_an_unwritable_results_path_is_refused_before_grading(self):
        sub = self.submission("", None)
        proc = lab_grade("--submission", sub, "--json", self.tmp / "no" / "such" / "results.json")
        self.assertEqual(proc.returncode, 2)
        self.assertIn("cannot write", proc.stderr)


if __name__ == "__main__":
    unittest.main()
