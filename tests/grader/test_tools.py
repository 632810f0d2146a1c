"""Tests of the grader's tools (tools/grade.py, tools/hooks.py) on their own and on the real
autograder binaries, whose paths CTest passes in GPL_AUTOGRADER_SOLUTIONS / _ASSIGNMENTS."""
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import grade  # noqa: E402
import hooks  # noqa: E402

CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"


def binary(variant):
    path = os.environ.get(f"GPL_AUTOGRADER_{variant.upper()}")
    if not path:
        raise RuntimeError(f"set GPL_AUTOGRADER_{variant.upper()} (CTest does)")
    return path


class RunLimited(unittest.TestCase):
    def test_a_loop_is_stopped_at_the_time_limit(self):
        rc, _, why = grade.run_limited(["sh", "-c", "while :; do :; done"], timeout=0.5)
        self.assertEqual(why, "timeout")
        self.assertLess(rc, 0)

    def test_endless_output_is_stopped_at_the_cap(self):
        rc, out, why = grade.run_limited(["yes"], timeout=20, cap=4096)
        self.assertEqual(why, "output")
        self.assertEqual(len(out), 4096)

    def test_a_normal_command_reports_its_exit_status(self):
        rc, out, why = grade.run_limited(["sh", "-c", "echo hello; exit 3"], timeout=10)
        self.assertEqual((rc, out.strip(), why), (3, "hello", None))


class Reports(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.solutions = grade.grade_binary(binary("solutions"), worksheet=1)
        cls.stubs = grade.grade_binary(binary("assignments"), worksheet=1)

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
                data = grade.gradescope(results, 1.5)
                grade.write_atomically(path, json.dumps(data))
                proc = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), str(path)], capture_output=True, text=True)
                self.assertEqual(proc.returncode, 0, proc.stdout)
                self.assertEqual(data["max_score"], sum(r["points"] for r in results))
                if expected_score is not None:
                    self.assertEqual(data["score"], expected_score)
                    self.assertTrue(all(t["status"] == "failed" for t in data["tests"]))
                    self.assertTrue(all("hint:" in t["output"] or t["output"].startswith("not run: depends on")
                                        for t in data["tests"]))
                else:
                    self.assertEqual(data["score"], data["max_score"])

    def test_junit_counts_failures(self):
        tree = ET.fromstring(grade.junit(self.stubs, "stubs"))
        suite = tree.find("testsuite")
        self.assertEqual(suite.get("name"), "worksheet1")
        not_run = sum(r["not_run"] for r in self.stubs)
        self.assertGreater(not_run, 0)
        self.assertEqual(int(suite.get("failures")), len(self.stubs) - not_run)
        self.assertEqual(int(suite.get("skipped")), not_run)
        self.assertEqual(len(suite.findall("testcase/failure")), len(self.stubs) - not_run)
        self.assertEqual(len(suite.findall("testcase/skipped")), not_run)
        tree = ET.fromstring(grade.junit(self.solutions, "solutions"))
        self.assertEqual(tree.find("testsuite").get("failures"), "0")

    def test_table_ends_with_the_count_line(self):
        text = grade.table(self.stubs, "stubs")
        self.assertTrue(text.splitlines()[-1].startswith(f"0 passed, {len(self.stubs)} failed"))
        self.assertIn("hint:", text)

    def test_stub_failures_say_which_hooks_are_open(self):
        open_hooks = [r for r in self.stubs if "hooks still not implemented" in r["output"]]
        self.assertGreater(len(open_hooks), len(self.stubs) // 2)
        self.assertTrue(all(r["output"].startswith("hooks still not implemented") for r in open_hooks))

    def test_unknown_test_name_is_a_failure_not_a_pass(self):
        passed, output, _ = grade.run_one(pathlib.Path(binary("solutions")).resolve(), "Worksheet1.NoSuchTest", 10)
        self.assertFalse(passed)
        self.assertIn("not found", output)


class Files(unittest.TestCase):
    def test_write_atomically_refuses_a_missing_folder_and_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(grade.GradeError):
                grade.write_atomically(pathlib.Path(tmp) / "nope" / "results.json", "{}")
            self.assertEqual(list(pathlib.Path(tmp).iterdir()), [])

    def test_submission_folder_checks(self):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            with self.assertRaisesRegex(grade.GradeError, "not found"):
                grade.prepare_submission(tmp / "missing", tmp / "hooks")
            (tmp / "empty").mkdir()
            with self.assertRaisesRegex(grade.GradeError, "none of the hook files"):
                grade.prepare_submission(tmp / "empty", tmp / "hooks")
            sub = tmp / "sub"
            sub.mkdir()
            (sub / "integrator.cpp").write_text("// mine\n")
            (sub / "report.pdf").write_text("not code")
            missing, ignored = grade.prepare_submission(sub, tmp / "hooks")
            self.assertEqual((tmp / "hooks" / "integrator.cpp").read_text(), "// mine\n")
            self.assertIn("simulation_timestep.cpp", missing)
            self.assertEqual(ignored, ["report.pdf"])
            self.assertEqual((tmp / "hooks" / "simulation_timestep.cpp").read_text(),
                             (ROOT / "assignments" / "simulation_timestep.cpp").read_text())


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

    def test_every_mutant_changes_the_code_and_names_a_test(self):
        for m in hooks.load_mutants():
            self.assertTrue(m["changes"], m["name"])
            self.assertTrue(m["must_fail"].startswith("Worksheet"), m["name"])
            for change in m["changes"]:
                self.assertNotEqual(change["from"], change["to"], m["name"])


if __name__ == "__main__":
    unittest.main()
