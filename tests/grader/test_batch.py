"""A batch of 50 submissions made from the solutions, the untouched stubs, a half-done submission and
a seeded mistake, graded with ./lab grade --batch. Checks: the gradebook
matches each submission's results.json; each submission but the solutions' copies (full marks, every
test passed) scores what the engine built from the same code by the main build (an independent
oracle) scores with the checker; identical submissions share one build and one run."""
import concurrent.futures
import contextlib
import csv
import io
import json
import os
import pathlib
import random
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from grading import running  # noqa: E402
import hooks  # noqa: E402

CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"


def tests_dir():
    folder = os.environ.get("GPL_TESTS_DIR")
    if not folder:
        raise RuntimeError("set GPL_TESTS_DIR (CTest does)")
    return pathlib.Path(folder)


def engine(variant):
    """The main build's checker with the engine of a variant (solutions, assignments, mutant_NAME)."""
    return running.Programs(tests_dir() / "gpl-checker", tests_dir() / f"gpl-hooks-{variant}", tests_dir() / "gpl-launch")


class Batch(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-batch-"))
        mutants = cls.tmp / "mutants"
        with contextlib.redirect_stdout(io.StringIO()):
            hooks.write_mutants(mutants)
        sources = {"solutions": ROOT / "solutions", "assignments": ROOT / "assignments"}
        sources.update({f"mutant_{m['name']}": mutants / m["name"] for m in hooks.load_mutants()})
        # 50 submissions: one seeded mistake (a fixed sample: each distinct submission compiles its
        # hook files and runs every graded test twice, here and in the oracle, and ctest's
        # grader.mutant.* check every mistake), the stubs five, a half-done one (integrator only, the
        # rest missing) five, three with extra files besides the solutions, and the solutions.
        by_worksheet = {}
        for m in hooks.load_mutants():
            by_worksheet.setdefault(m["spec"], []).append(f"mutant_{m['name']}")
        picked = random.Random(5)
        plan = ["assignments"] * 5 + ["half"] * 5 + ["solutions+notes"] * 3
        for spec in picked.sample(sorted(by_worksheet), 1):
            plan += picked.sample(by_worksheet[spec], 1)
        plan += ["solutions"] * (50 - len(plan))
        assert len(plan) == 50, "more seeded mistakes than a batch of 50 holds"
        cls.distinct = len({v.split("+")[0] for v in plan})
        random.Random(5).shuffle(plan)
        cls.batch = cls.tmp / "submissions"
        cls.variant_of = {}
        for i, variant in enumerate(plan, 1):
            sub = cls.batch / f"student-{i:02d}"
            sub.mkdir(parents=True)
            if variant == "half":
                shutil.copy(ROOT / "solutions" / "integrator.cpp", sub)
            else:
                for name in hooks.hook_files():
                    shutil.copy(sources[variant.split("+")[0]] / name, sub)
            if variant.endswith("+notes"):
                (sub / "notes.txt").write_text("what I did")
                (sub / "build").mkdir()
                (sub / "build" / "a.out").write_bytes(b"\x7fELF")
            cls.variant_of[sub.name] = variant
        cls.gradebook = cls.tmp / "grades.csv"
        start = time.monotonic()
        cls.proc = subprocess.run([str(ROOT / "lab"), "grade", "--batch", str(cls.batch), "--out", str(cls.gradebook),
                                   "--similarity"],
                                  capture_output=True, text=True, cwd=ROOT, timeout=550)
        cls.seconds = time.monotonic() - start
        print(f"\nbatch of {len(plan)} graded in {cls.seconds:.1f} s", file=sys.stderr)

    @classmethod
    def tearDownClass(cls):
        # Removed in the background: the batch leaves tens of thousands of files, whose unlinking
        # takes half a minute on a disk that discards on delete, and nothing waits for it.
        subprocess.Popen(["rm", "-rf", "--", str(cls.tmp)], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)

    def rows(self):
        with open(self.gradebook, newline="") as f:
            return list(csv.DictReader(f))

    def results(self, name):
        return json.loads((self.tmp / "grades-results" / name / "results.json").read_text())

    def test_exit_status_and_progress(self):
        self.assertEqual(self.proc.returncode, 1, self.proc.stdout + self.proc.stderr)
        self.assertIn(f"grading 50 submissions ({self.distinct} distinct)", self.proc.stderr)
        self.assertIn("grading: 50 of 50 submissions done", self.proc.stderr)
        self.assertIn("graded 50 submissions", self.proc.stdout)

    def test_gradebook_has_one_row_per_submission_and_a_column_per_test(self):
        rows = self.rows()
        self.assertEqual([r["submission"] for r in rows], sorted(self.variant_of))
        tests = [t["name"] for t in running.checker_manifest(tests_dir() / "gpl-checker")]
        with open(self.gradebook, newline="") as f:
            header = next(csv.reader(f))
        self.assertEqual(header, ["submission", *tests, "total", "max_score", "note"])

    def test_gradebook_matches_each_results_file(self):
        for row in self.rows():
            with self.subTest(submission=row["submission"]):
                results = self.results(row["submission"])
                check = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), "/dev/stdin"],
                                       input=json.dumps(results), capture_output=True, text=True)
                self.assertEqual(check.returncode, 0, check.stdout)
                for t in results["tests"]:
                    self.assertEqual(float(row[t["name"]]), t["score"], t["name"])
                self.assertEqual(float(row["total"]), results["score"])
                self.assertEqual(float(row["max_score"]), results["max_score"])

    def test_scores_match_the_autograders_of_the_main_build(self):
        # The solutions' copies are left to test_each_kind_scores_as_it_should: full marks is every
        # test passed with its points, and grader.solutions_score_full_marks grades the main build's.
        # The other variants are graded by the main build two at a time (a grading mostly waits on
        # its sandboxes).
        variants = sorted({v.split("+")[0] for v in self.variant_of.values()} - {"half", "solutions"})

        def graded(variant):
            return {r["name"]: (r["score"], r["passed"], r.get("not_run", False))
                    for r in running.grade_binary(engine(variant))}

        with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
            oracle = dict(zip(variants, pool.map(graded, variants)))
        self.assertIn("assignments", oracle)
        for row in self.rows():
            variant = self.variant_of[row["submission"]].split("+")[0]
            if variant not in oracle:
                continue
            with self.subTest(submission=row["submission"], variant=variant):
                results = {t["name"]: t for t in self.results(row["submission"])["tests"]}
                for name, (score, passed, not_run) in oracle[variant].items():
                    self.assertEqual(results[name]["score"], score, name)
                    self.assertEqual(results[name]["status"], "passed" if passed else "failed", name)
                    self.assertEqual(results[name]["output"].startswith("not run:"), not_run, name)

    def test_each_kind_scores_as_it_should(self):
        specs = {f"mutant_{m['name']}": m["must_fail"] for m in hooks.load_mutants()}
        for row in self.rows():
            variant = self.variant_of[row["submission"]]
            with self.subTest(submission=row["submission"], variant=variant):
                if variant.startswith("solutions"):
                    self.assertEqual(row["total"], row["max_score"])
                elif variant == "assignments":
                    self.assertEqual(float(row["total"]), 0)
                elif variant == "half":
                    # The integrator is done, gravity never applied (the instructor notes' "3.1 forgotten"):
                    # graded with assertions on, its energy assertion fires even in the static bodies'
                    # test (bodies that rise without gravity gain energy), so nothing passes.
                    passed = {t["name"] for t in self.results(row["submission"])["tests"] if t["status"] == "passed"}
                    self.assertEqual(passed, set())
                    self.assertEqual(float(row["total"]), 0)
                    missing = [n for n in hooks.hook_files() if n != "integrator.cpp"]
                    self.assertIn("graded as the untouched stub: " + " ".join(missing), row["note"])
                else:
                    self.assertEqual(float(row[specs[variant]]), 0, specs[variant])
                    self.assertLess(float(row["total"]), float(row["max_score"]))
                if variant.endswith("+notes"):
                    self.assertEqual(row["note"], "ignored: build/a.out notes.txt")

    def test_similarity_pairs_the_copies_and_leaves_the_stubs_out(self):
        with open(self.tmp / "grades-similarity.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        percent = {(r["submission"], r["similar_to"], r["hook_file"]): int(r["percent"]) for r in rows}
        copies = sorted(n for n, v in self.variant_of.items() if v.startswith("solutions"))
        for hook in ("collision_impulse.cpp", "sphere_sphere.cpp", "integrator.cpp"):
            self.assertGreaterEqual(percent.get((copies[0], copies[1], hook), 0), 90, hook)
        # The stubs' text is left out, so untouched stubs share nothing with anyone.
        stubs = {n for n, v in self.variant_of.items() if v == "assignments"}
        self.assertFalse([r for r in rows if r["submission"] in stubs or r["similar_to"] in stubs])
        # The half-done submission wrote integrator.cpp only; its other files are stubs.
        half = {n for n, v in self.variant_of.items() if v == "half"}
        self.assertEqual({r["hook_file"] for r in rows if r["submission"] in half}, {"integrator.cpp"})
        self.assertIn("most similar", self.proc.stdout)


class BadBatches(unittest.TestCase):
    def lab_grade(self, *args):
        return subprocess.run([str(ROOT / "lab"), "grade", *map(str, args)], capture_output=True, text=True, cwd=ROOT)

    def test_missing_or_empty_batch_folder_and_bad_output(self):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            (tmp / "empty").mkdir()
            (tmp / "one" / "alice").mkdir(parents=True)
            for args, message in [
                (("--batch", tmp / "nowhere", "--out", tmp / "g.csv"), "batch folder not found"),
                (("--batch", tmp / "empty", "--out", tmp / "g.csv"), "holds no submission folders"),
                (("--batch", tmp / "one"), "--batch needs --out"),
                (("--batch", tmp / "one", "--out", tmp / "no" / "g.csv"), "cannot write"),
                (("--batch", tmp / "one", "--out", tmp / "g.csv", "--jobs", "0"), "--jobs must be at least 1"),
            ]:
                with self.subTest(args=args):
                    proc = self.lab_grade(*args)
                    self.assertEqual(proc.returncode, 2, proc.stdout + proc.stderr)
                    self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
                    self.assertIn(message, proc.stderr)
            self.assertEqual(sorted(p.name for p in tmp.iterdir()), ["empty", "one"], "nothing written")


if __name__ == "__main__":
    unittest.main()
