"""Submissions that misbehave, graded together as a batch: one that segfaults, one that loops forever,
one that prints without end, one that returns NaN, one that does not compile, one that writes into
the tests folder, one whose cache grows without end, one that starts processes, one that writes a
huge file, one that starts threads in a loop, one that opens a network connection and one that reads
the solutions, another submission and the results. Each misbehaves only in some tests (a condition
on the time step or the masses), so the test checks that exactly those tests lose their points, with
the right message, and that every other test of the same submission, and every other submission, is
unaffected. The batch runs in the sandbox (bubblewrap), which this machine allows, and grades
worksheet 1, where every misbehaviour is; a second, smaller batch runs without it
(GPL_GRADER_SANDBOX=off), where the write guard catches the writer, and grades the whole course: a
free fall that loses its points there leaves the later worksheets' stepping tests not run."""
import csv
import hashlib
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from grading import running  # noqa: E402
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
    # A cache that grows every step, without end: the memory limit, not the time limit, stops it.
    "memory_hog": integrator("        static std::vector<std::vector<double>> cache;\n"
                             "        while (h == 0.005) cache.emplace_back(1 << 20, b.position.x());\n",
                             includes="#include <vector>\n"),
    # Twenty processes, each ending at once (bounded, so that the test cannot hurt the machine).
    "forks": integrator("        for (int i = 0; h == 0.004 && i < 20; ++i) {\n"
                        "            const pid_t child = fork();\n"
                        "            if (child == 0) _exit(0);\n"
                        "            if (child > 0) waitpid(child, nullptr, 0);\n"
                        "        }\n", includes="#include <sys/wait.h>\n#include <unistd.h>\n"),
    # 200 MiB into one file, in 1 MiB blocks.
    "huge_file": integrator("        if (h == 0.004) {\n"
                            "            const std::vector<char> block(1 << 20, 'x');\n"
                            "            std::FILE* f = std::fopen(\"debug-dump.bin\", \"wb\");\n"
                            "            for (int i = 0; f && i < 200; ++i) std::fwrite(block.data(), 1, block.size(), f);\n"
                            "            if (f) std::fclose(f);\n"
                            "        }\n", includes="#include <cstdio>\n#include <vector>\n"),
    # 64 threads at once, each asleep for a second.
    "threads": integrator("        if (h == 0.005) {\n"
                          "            std::vector<std::thread> pool;\n"
                          "            for (int i = 0; i < 64; ++i)\n"
                          "                pool.emplace_back([] { std::this_thread::sleep_for(std::chrono::seconds(1)); });\n"
                          "            for (auto& t : pool) t.join();\n"
                          "        }\n", includes="#include <chrono>\n#include <thread>\n#include <vector>\n"),
    # One connection attempt to a port on this machine.
    "network": integrator("        if (h == 0.02) {\n"
                          "            const int s = socket(AF_INET, SOCK_STREAM, 0);\n"
                          "            sockaddr_in to{};\n"
                          "            to.sin_family = AF_INET;\n"
                          "            to.sin_port = htons(9);\n"
                          "            to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);\n"
                          "            if (s >= 0) connect(s, reinterpret_cast<sockaddr*>(&to), sizeof to);\n"
                          "            if (s >= 0) close(s);\n"
                          "        }\n",
                          includes="#include <arpa/inet.h>\n#include <netinet/in.h>\n#include <sys/socket.h>\n"
                                   "#include <unistd.h>\n"),
    # Looks at the solutions, another submission and the batch's results: whatever it can open makes
    # its answer wrong, so full marks prove it saw none of them.
    "snoops": integrator("        static const bool saw = [] {\n"
                         "            for (const char* path : {SNOOPED_PATHS})\n"
                         "                if (std::ifstream(path).good() || opendir(path)) return true;\n"
                         "            return false;\n"
                         "        }();\n"
                         "        if (saw) b.velocity.x() += 1.0;\n", includes="#include <dirent.h>\n#include <fstream>\n"),
}

# MiB per test: the course's tests need under 10; this machine gives a process new memory at about
# 150 MB/s, so the default 1024 MiB would take the growing cache longer than the 2 s time limit.
MEMORY = 100

# name -> {test: ("FAIL" | "not run", regex of its output)}; every test not named must pass. The hook
# named is the checker's call in flight: integrator() where the test asks for it alone, the whole
# step where it asks for a step (the engine's own stack is not believed there).
PASS = None
EXPECTED = {
    "reference": {},
    "segfault": {
        "Worksheet1.OneStepIsSemiImplicitEuler": ("FAIL", r"^crashed with SIGSEGV in (integrator|simulationTimestep)\(\)"),
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^crashed with SIGSEGV in (integrator|simulationTimestep)\(\)"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.OneStepIsSemiImplicitEuler"),
        "Worksheet1Hidden.EnergyLossPerStepIsExact": ("not run", r"^not run: depends on Worksheet1.OneStep"),
    },
    "endless_loop": {
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^timed out after 2 s in (integrator|simulationTimestep)\(\)"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
    },
    "endless_output": {
        "Worksheet1.MatchesDiscreteFreeFall": ("FAIL", r"^printed more than 1024 KiB of output in (integrator|simulationTimestep)\(\) "
                                                       r"and was stopped; it began:\ndebug: x = "),
    },
    # The assertion in full in the first test it stopped, one line naming that test in the others.
    "nan": {
        "Worksheet1.GravityIndependentOfMass": ("FAIL", r"Assertion `isFinite\(b.position\) && isFinite\(b.velocity\)'"),
        "Worksheet1.GravityPointsDown": ("FAIL", r"^crashed with SIGABRT .*: stopped on the same failed assertion as "
                                                 r"Worksheet1.GravityIndependentOfMass"),
        "Worksheet1.StaysFinite": ("FAIL", r"^crashed with SIGABRT .*: stopped on the same failed assertion as "
                                           r"Worksheet1.GravityIndependentOfMass"),
        "Worksheet1.EnergyNeverIncreases": ("not run", r"^not run: depends on Worksheet1.GravityPointsDown"),
    },
    # In the sandbox the tests folder is not there to write into: the writes go nowhere.
    "writes_tests": {},
    "memory_hog": {
        "Worksheet1.UsesEngineTimeStep": ("FAIL", rf"^used more than {MEMORY} MiB of memory in (integrator|simulationTimestep)\(\) and was stopped"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
    },
    "forks": {
        "Worksheet1.MatchesDiscreteFreeFall": ("FAIL", r"^tried to start a process in (integrator|simulationTimestep)\(\), which graded "
                                                       r"code may not do"),
    },
    "huge_file": {
        "Worksheet1.MatchesDiscreteFreeFall": ("FAIL", r"^wrote more than 64 MiB to a file in (integrator|simulationTimestep)\(\) and was "
                                                       r"stopped"),
    },
    "threads": {
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^ran more than 8 threads at once in (integrator|simulationTimestep)\(\) and was stopped"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
    },
    "network": {
        "Worksheet1.OneStepIsSemiImplicitEuler": ("FAIL", r"^tried to open a network connection in (integrator|simulationTimestep)\(\)"),
        "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^tried to open a network connection in (integrator|simulationTimestep)\(\)"),
        "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.OneStepIsSemiImplicitEuler"),
        "Worksheet1Hidden.EnergyLossPerStepIsExact": ("not run", r"^not run: depends on Worksheet1.OneStep"),
    },
    "snoops": {},
}

# Tests of later worksheets that step the engine depend on worksheet 1's free fall (the integrator
# and the time step): where that loses its points, they are not run (WithoutSandbox grades them).
STEPPING = [t["name"] for t in running.checker_manifest(os.environ["GPL_CHECKER"])
            if "Worksheet1.MatchesDiscreteFreeFall" in t["depends_on"]]


def whole_course(expected):
    """What a submission that misbehaves as `expected` says on worksheet 1 loses in the whole course."""
    if "Worksheet1.MatchesDiscreteFreeFall" not in expected:
        return dict(expected)
    return {**expected, **{name: ("not run", r"^not run: depends on Worksheet1.MatchesDiscreteFreeFall")
                           for name in STEPPING}}


def grade_batch(cls, names, env=None, worksheet=None):
    """Grades the named submissions as one batch; sets cls.tmp, cls.proc, cls.gradebook, cls.results."""
    cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-isolation-"))
    batch = cls.tmp / "batch"
    snooped = [ROOT / "solutions" / "integrator.cpp", batch / "reference" / "integrator.cpp",
               cls.tmp / "gradebook-results", cls.tmp]
    for name in names:
        sub = batch / name
        sub.mkdir(parents=True)
        text = SUBMISSIONS[name].replace("SNOOPED_PATHS", ", ".join(f'"{p}"' for p in snooped))
        (sub / "integrator.cpp").write_text(text)
        for hook in hooks.hook_files():
            if hook not in ("integrator.cpp", "student_scenes.cpp"):
                shutil.copy(ROOT / "solutions" / hook, sub)
    if "writes_tests" in names:  # a submission cannot bring its own tests: the file is ignored
        fake = batch / "writes_tests" / "tests" / "autograder" / "worksheet1_test.cpp"
        fake.parent.mkdir(parents=True)
        fake.write_text("// a test file that lets everything pass\n")
    cls.gradebook = cls.tmp / "gradebook.csv"
    only = ["--worksheet", str(worksheet)] if worksheet else []
    cls.proc = subprocess.run([str(ROOT / "lab"), "grade", "--batch", str(batch), "--out", str(cls.gradebook),
                               "--timeout", "2", "--memory", str(MEMORY), *only], capture_output=True, text=True,
                              cwd=ROOT, timeout=500, env={**os.environ, **(env or {})})
    cls.results = {}
    for name in names:
        path = cls.tmp / "gradebook-results" / name / "results.json"
        if path.exists():
            cls.results[name] = json.loads(path.read_text())


class Misbehaving(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.before = tree_digest(ROOT / "tests")
        grade_batch(cls, list(SUBMISSIONS), worksheet=1)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_the_batch_ran_and_lost_points(self):
        self.assertEqual(self.proc.returncode, 1, self.proc.stdout + self.proc.stderr)
        self.assertEqual(set(self.results), set(SUBMISSIONS), self.proc.stderr)
        graded = {t["name"].split(".")[0] for t in self.results["reference"]["tests"]}
        self.assertEqual(graded, {"Worksheet1", "Worksheet1Hidden"})

    def test_the_tests_folder_is_unchanged(self):
        self.assertFalse(INJECTED.exists())
        self.assertEqual(tree_digest(ROOT / "tests"), self.before, "a submission changed the tests folder")

    def check(self, name):
        results = self.results[name]
        check = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), "/dev/stdin"], input=json.dumps(results),
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

    def test_the_sandbox_was_used(self):
        self.assertIn("sandbox: each test ran in bubblewrap", self.proc.stderr)
        self.assertIn("sandbox: each test ran in bubblewrap", self.results["reference"]["output"])

    def test_writing_into_the_tests_goes_nowhere(self):
        self.check("writes_tests")

    def test_a_growing_cache_is_stopped_by_the_memory_limit(self):
        self.check("memory_hog")

    def test_starting_processes_is_refused(self):
        self.check("forks")

    def test_a_huge_file_is_stopped_by_the_file_limit(self):
        self.check("huge_file")

    def test_threads_in_a_loop_are_stopped_by_the_thread_limit(self):
        self.check("threads")

    def test_a_network_connection_is_refused(self):
        self.check("network")

    def test_the_solutions_other_submissions_and_results_are_out_of_sight(self):
        self.check("snoops")

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


class WithoutSandbox(unittest.TestCase):
    """Where bubblewrap cannot run, the grader says so and falls back: the engine runs as nobody when
    the grader is root (it cannot write the lab's files), else the write guard puts the lab's files
    back and fails the writer; starting a process is still refused (the launcher's filter); what the
    sandbox hid is in sight where it is readable by everyone, which the snooping submission shows."""

    @classmethod
    def setUpClass(cls):
        cls.before = tree_digest(ROOT / "tests")
        # The writer and the snoop do what they do in worksheet 1's integrator: graded on worksheet 1.
        # The reference (full marks without the sandbox) and the forking submission over the course.
        grade_batch(cls, ["writes_tests", "snoops"], env={"GPL_GRADER_SANDBOX": "off"}, worksheet=1)
        first_tmp, first_results = cls.tmp, cls.results
        grade_batch(cls, ["reference", "forks"], env={"GPL_GRADER_SANDBOX": "off"})
        cls.tmps = [first_tmp, cls.tmp]
        cls.results.update(first_results)

    @classmethod
    def tearDownClass(cls):
        for tmp in cls.tmps:
            shutil.rmtree(tmp)

    check = Misbehaving.check

    def test_the_fallback_is_reported(self):
        line = "sandbox: not used: switched off (GPL_GRADER_SANDBOX=off); the engine ran" + \
               (" as nobody" if os.geteuid() == 0 else "")
        self.assertIn(line, self.proc.stderr)
        self.assertIn(line, self.results["reference"]["output"])
        self.check("reference")

    def test_writing_into_the_tests_costs_that_test_and_is_undone(self):
        if os.geteuid() == 0:
            # The engine ran as nobody: its writes into the lab were refused by the file system.
            expected = {}
        else:
            expected = whole_course({
                "Worksheet1.UsesEngineTimeStep": ("FAIL", r"^wrote into the lab's own files, which is not allowed "
                                                          r"\(undone\): tests/autograder/injected_test.cpp, "
                                                          r"tests/autograder/worksheet1_test.cpp"),
                "Worksheet1.MatchesDiscreteFreeFall": ("not run", r"^not run: depends on Worksheet1.UsesEngineTimeStep"),
            })
        EXPECTED["writes_tests (no sandbox)"] = expected
        self.results["writes_tests (no sandbox)"] = self.results["writes_tests"]
        self.check("writes_tests (no sandbox)")
        self.assertFalse(INJECTED.exists())
        self.assertEqual(tree_digest(ROOT / "tests"), self.before, "a submission changed the tests folder")
        if os.geteuid() != 0:
            quarantined = list((ROOT / "build" / "release" / "quarantine").rglob("injected_test.cpp"))
            self.assertTrue(quarantined, "what the submission wrote is kept aside")

    def test_starting_processes_is_still_refused(self):
        EXPECTED["forks (no sandbox)"] = whole_course(EXPECTED["forks"])
        self.results["forks (no sandbox)"] = self.results["forks"]
        self.check("forks (no sandbox)")
        self.assertTrue(any(t["name"].startswith("Worksheet7") for t in self.results["forks"]["tests"]))

    def test_without_the_sandbox_the_solutions_are_in_sight(self):
        # Where the lab is readable by everyone, nobody reads it too (the report says so).
        readable = os.access(ROOT / "solutions" / "integrator.cpp", os.R_OK) and \
            (ROOT / "solutions" / "integrator.cpp").stat().st_mode & 0o004 and all(
                p.stat().st_mode & 0o001 for p in (ROOT / "solutions").parents)
        results = self.results["snoops"]
        if readable or os.geteuid() != 0:
            self.assertLess(results["score"], results["max_score"])


if __name__ == "__main__":
    unittest.main()
