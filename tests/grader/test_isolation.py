"""Submissions that misbehave, graded together as a batch: one that segfaults, one that loops forever,
one that prints without end, one that returns NaN, one that does not compile and one that writes
into the tests folder. Each misbehaves only in some tests (a condition on the time step or the
masses), so the test checks that exactly those tests lose their points, with the right message,
and that every other test of the same submission, and every other submission, is unaffected."""
import csv
import hashlib
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import grade  # noqa: E402
import hooks  # noqa: E402
CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"
SOLUTION = (ROOT / "solutions" / "integrator.cpp").read_text()
UPDATE = "        b.velocity += h * b.acceleration;\n"


def tree_digest(folder):
    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        if p.is_file() and "__pycache__" not in p.parts:
            h.update(str(p.relative_to(folder)).encode() + p.read_bytes())
    return h.hexdigest()


def integrator(inserted_before_update="", replace=None, includes=""):
    text = SOLUTION
    assert UPDATE in text
    text = text.replace(UPDATE, inserted_before_update + UPDATE)
    if replace:
        assert replace[0] in text
        text = text.replace(*replace)
    return text.replace("#include <cmath>\n", "#include <cmath>\n" + includes)


TAMPERED = ROOT / "tests" / "autograder" / "worksheet1_test.cpp"
INJECTED = ROOT / "tests" / "autograder" / "injected_test.cpp"

# name -> integrator.cpp; the time steps pick the tests: 0.02 OneStepIsSemiImplicitEuler and
# UsesEngineTimeStep (and the hidden test), 0.005 and 0.001 only UsesEngineTimeStep, 0.004 only
# MatchesDiscreteFreeFall; 1000 kg bodies only the mass line (GravityIndependentOfMass,
# GravityPointsDown) and the worksheet's scenes (StaysFinite, EnergyNeverIncreases).
SUBMISSIONS = {
    "reference": integrator(),
    "segfault": integrator("        if (h == 0.02) *static_cast<volatile int*>(nullptr) = 1;\n"),
    "endless_loop": integrator("        while (h == 0.005) b.position.x() = b.position.x() + 0.0 * h;\n"),
    "endless_output": integrator("        while (h == 0.004) std::printf(\"debug: x = %g\\n\", b.position.x());\n",
                                 includes="#include <cstdio>\n"),
    "nan": integrator("        if (b.mass >= 1000.0) b.velocity.x() = std::sqrt(-b.mass);\n"),
    "no_compile": integrator(replace=("b.position += h * b.velocity;", "b.position += h * b.velocity")),
    "writes_tests": integrator(
        f"        if (h == 0.001) {{\n"
        f"            std::ofstream(\"{TAMPERED}\", std::ios::app) << \"// every test passes\\n\";\n"
        f"            std::ofstream(\"{INJECTED}\") << \"// injected\\n\";\n"
        f"        }}\n", includes="#include <fstream>\n"),
}

# name -> {test: ("FAIL" | "not run", regex of its output)}; every test not named must pass.
PASS = None
EXPECTED = {
    "reference": {},
    "segfault": {
        "Worksheet1.OneStepIsSemiImplicitEuler": ("FAIL", r"^crashed with SIGSEGV in integrator\(\)"),
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^crashed with SIGSEGV in integrator\(\)"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.OneStepIsSemiImplicitEuler"),
        "Worksheet1Hidden.EnergyLossPerStepIsExact": ("not run", r"^not run: depends on Worksheet1.OneStep"),
    },
    "endless_loop": {
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^timed out after 2 s in integrator\(\)"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
    },
    "endless_output": {
        "Worksheet1.MatchesDiscreteFreeFall": ("FAIL", r"^printed more than 1024 KiB of output in integrator\(\) "
                                                       r"and was stopped; it began:\ndebug: x = "),
    },
    "nan": {
        "Worksheet1.GravityIndependentOfMass": ("FAIL", r"Assertion `isFinite\(b.position\)"),
        "Worksheet1.GravityPointsDown": ("FAIL", r"Assertion `isFinite\(b.position\)"),
        "Worksheet1.StaysFinite": ("FAIL", r"Assertion `isFinite\(b.position\)"),
        "Worksheet1.EnergyNeverIncreases": ("not run", r"^not run: depends on Worksheet1.GravityPointsDown"),
    },
    "writes_tests": {
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^wrote into the lab's own files, which is not allowed \(undone\): "
                                                  r"tests/autograder/injected_test.cpp, tests/autograder/worksheet1_test.cpp"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
    },
}

# Tests of later worksheets that step the engine depend on worksheet 1's free fall (the integrator
# and the time step): where that loses its points, they are not run.
STEPPING = [t["name"] for t in grade.manifest(pathlib.Path(os.environ["GPL_AUTOGRADER_DIR"]) / "autograder_solutions")
            if "Worksheet1.MatchesDiscreteFreeFall" in t["depends_on"]]
for expected in EXPECTED.values():
    if "Worksheet1.MatchesDiscreteFreeFall" in expected:
        expected.update({name: ("not run", r"^not run: depends on Worksheet1.MatchesDiscreteFreeFall")
                         for name in STEPPING})


class Misbehaving(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-isolation-"))
        cls.before = tree_digest(ROOT / "tests")
        batch = cls.tmp / "batch"
        for name, text in SUBMISSIONS.items():
            sub = batch / name
            sub.mkdir(parents=True)
            (sub / "integrator.cpp").write_text(text)
            for hook in hooks.hook_files():
                if hook not in ("integrator.cpp", "student_scenes.cpp"):
                    shutil.copy(ROOT / "solutions" / hook, sub)
        # A submission cannot bring its own tests: the file is ignored.
        fake = batch / "writes_tests" / "tests" / "autograder" / "worksheet1_test.cpp"
        fake.parent.mkdir(parents=True)
        fake.write_text("// a test file that lets everything pass\n")
        cls.gradebook = cls.tmp / "gradebook.csv"
        cls.proc = subprocess.run([str(ROOT / "lab"), "grade", "--batch", str(batch), "--out", str(cls.gradebook),
                                   "--timeout", "2"], capture_output=True, text=True, cwd=ROOT, timeout=500)
        cls.results = {}
        for name in SUBMISSIONS:
            path = cls.tmp / "gradebook-results" / name / "results.json"
            if path.exists():
                cls.results[name] = json.loads(path.read_text())

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_the_batch_ran_and_lost_points(self):
        self.assertEqual(self.proc.returncode, 1, self.proc.stdout + self.proc.stderr)
        self.assertEqual(set(self.results), set(SUBMISSIONS), self.proc.stderr)

    def test_the_tests_folder_is_unchanged(self):
        self.assertFalse(INJECTED.exists())
        self.assertEqual(tree_digest(ROOT / "tests"), self.before, "a submission changed the tests folder")

    def check(self, name):
        results = self.results[name]
        check = subprocess.run(["python3", str(CHECK_GRADESCOPE), "/dev/stdin"], input=json.dumps(results),
                               capture_output=True, text=True)
        self.assertEqual(check.returncode, 0, check.stdout)
        expected = EXPECTED[name]
        for t in results["tests"]:
            with self.subTest(submission=name, test=t["name"]):
                if t["name"] not in expected:
                    self.assertEqual((t["status"], t["score"]), ("passed", t["max_score"]), t["output"])
                    continue
                kind, pattern = expected[t["name"]]
                self.assertEqual((t["status"], t["score"]), ("failed", 0), t["output"])
                self.assertRegex(t["output"], pattern)
                if kind == "not run":
                    self.assertNotIn("hint:", t["output"])
        self.assertEqual(results["score"], sum(t["score"] for t in results["tests"]))

    def test_reference_scores_full_marks(self):
        self.check("reference")

    def test_segfault_costs_only_the_tests_that_crash(self):
        self.check("segfault")

    def test_endless_loop_costs_only_the_test_that_loops(self):
        self.check("endless_loop")

    def test_endless_output_costs_only_the_test_that_prints(self):
        self.check("endless_output")

    def test_nan_costs_only_the_tests_with_heavy_bodies(self):
        self.check("nan")

    def test_writing_into_the_tests_costs_that_test_and_is_undone(self):
        self.check("writes_tests")
        quarantined = list((ROOT / "build" / "release" / "quarantine").rglob("injected_test.cpp"))
        self.assertTrue(quarantined, "what the submission wrote is kept aside")

    def test_a_submission_that_does_not_compile_scores_zero_with_the_error(self):
        results = self.results["no_compile"]
        self.assertEqual(results["score"], 0)
        for t in results["tests"]:
            self.assertEqual(t["status"], "failed")
            self.assertRegex(t["output"], r"^the submission does not compile:\n.*no_compile/integrator.cpp:\d+:\d+: error")

    def test_gradebook_notes(self):
        with open(self.gradebook) as f:
            rows = {r["submission"]: r for r in csv.DictReader(f)}
        self.assertTrue(rows["no_compile"]["note"].startswith("does not compile"))
        self.assertEqual(rows["reference"]["total"], rows["reference"]["max_score"])
        self.assertEqual(rows["writes_tests"]["note"], "graded as the untouched stub: student_scenes.cpp; "
                                                      "ignored: tests/autograder/worksheet1_test.cpp")
        self.assertIn("ignored (only hook files are graded): tests/autograder/worksheet1_test.cpp",
                      self.results["writes_tests"]["output"])
        self.assertIn("not in the submission, graded as the untouched stub: student_scenes.cpp",
                      self.results["reference"]["output"])


if __name__ == "__main__":
    unittest.main()
