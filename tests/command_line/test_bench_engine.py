"""./lab bench engine's options that are not about speed: --busy runs one busy process beside the run
and never leaves it behind, and --threads 1 2 gives a row for each thread count side by side. The
heaps are tiny and nothing is timed: the tests read which rows the table has, never their figures."""
import csv
import os
import pathlib
import re
import signal
import subprocess
import tempfile
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BENCH = os.environ.get("GPL_BENCH_ENGINE")
BUSY_LINE = re.compile(r"^beside one busy process \(pid (\d+),", re.MULTILINE)


def gone(pid):
    """True when process `pid` has ended: no such process, or one that has ended and waits to be
    reaped (a zombie takes no core)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] in ("Z", "X")
    except FileNotFoundError:
        return True


def until_gone(pid, seconds=20.0):
    """Whether `pid` ends within `seconds`: the kernel kills an orphaned spinner at once, but a
    loaded machine may take a moment to reap it. Not a timing: a generous bound on a liveness."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if gone(pid):
            return True
        time.sleep(0.05)
    return gone(pid)


@unittest.skipUnless(BENCH, "GPL_BENCH_ENGINE names gpl-bench-engine")
class BenchEngine(unittest.TestCase):
    def run_bench(self, *args):
        with tempfile.TemporaryDirectory() as out:
            cmd = [BENCH, "--sizes", "20", "--out", out, *args]
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            if proc.returncode == 2 and "built without Bullet" in proc.stderr:
                proc = subprocess.run([*cmd, "--no-bullet"], capture_output=True, text=True, timeout=300)
            self.assertEqual(proc.returncode, 0, proc.stdout[-2000:] + proc.stderr[-2000:])
            with open(pathlib.Path(out) / "engine.csv") as f:
                rows = list(csv.DictReader(f))
        return proc.stdout, rows

    def test_busy_compares_one_and_two_threads_beside_a_busy_process_it_then_ends(self):
        text, rows = self.run_bench("--busy")
        busy = BUSY_LINE.search(text)
        self.assertIsNotNone(busy, text)
        self.assertTrue(gone(int(busy.group(1))), "the busy process outlives the run")
        self.assertRegex(text, r"\n20 +ours 1 thread +\d+ ")
        # The two-thread row has its time over the one-thread row's.
        self.assertRegex(text, r"\n20 +ours 2 threads +\d+ +[0-9.]+ +[0-9.]+ +(?:[0-9.]+ +)?[0-9.]+ +\d+ ")
        self.assertEqual(sorted((r["engine"], r["threads"]) for r in rows if r["engine"] == "ours"),
                         [("ours", "1"), ("ours", "2")])
        self.assertTrue(all(r["busy"] == "1" for r in rows), rows)

    def test_without_busy_no_busy_process_runs(self):
        text, rows = self.run_bench("--threads", "1", "2")
        self.assertIsNone(BUSY_LINE.search(text), text)
        self.assertRegex(text, r"\n20 +ours 1 thread .*\n20 +ours 2 threads ")
        self.assertTrue(all(r["busy"] == "0" for r in rows), rows)

    @unittest.skipUnless({0, 1} <= os.sched_getaffinity(0), "needs processors 0 and 1")
    def test_two_threads_report_each_processors_access_time_alone(self):
        # The probe that shows two processors of unequal speed: both figures, and the slower over
        # the faster as they give it (to their printed digits: a tenth of a nanosecond each).
        text, _ = self.run_bench("--threads", "1", "2")
        line = re.search(r"each processor alone, .*: processor 0 ([0-9.]+) ns, processor 1 ([0-9.]+) ns "
                         r"per access \(the slower ([0-9.]+)x the faster\)", text)
        self.assertIsNotNone(line, text)
        first, second, ratio = (float(g) for g in line.groups())
        self.assertGreater(min(first, second), 0.0)
        self.assertGreaterEqual(ratio, 1.0)
        low, high = sorted((first, second))
        self.assertLessEqual((high - 0.05) / (low + 0.05) - 0.01, ratio)
        self.assertLessEqual(ratio, (high + 0.05) / (low - 0.05) + 0.01)

    def test_busy_with_one_thread_count_runs_that_one(self):
        text, rows = self.run_bench("--busy", "--threads", "2")
        self.assertIsNotNone(BUSY_LINE.search(text), text)
        self.assertEqual([r["threads"] for r in rows if r["engine"] == "ours"], ["2"])

    def test_the_busy_process_dies_with_the_bench(self):
        # The bench killed mid-run, with no chance to clean up: its busy process must not live on.
        with tempfile.TemporaryDirectory() as out:
            bench = subprocess.Popen([BENCH, "--busy", "--no-bullet", "--sizes", "8000", "--out", out],
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
            try:
                pid = None
                for line in bench.stdout:
                    busy = BUSY_LINE.search(line)
                    if busy:
                        pid = int(busy.group(1))
                        break
                self.assertIsNotNone(pid, "no busy process named")
                self.assertFalse(gone(pid), "the busy process has not started")
                bench.send_signal(signal.SIGKILL)
                bench.wait(timeout=60)
                self.assertTrue(until_gone(pid), f"the busy process {pid} outlives the bench")
            finally:
                if bench.poll() is None:
                    bench.kill()
                    bench.wait()
                bench.stdout.close()

    def test_bad_values_name_the_option(self):
        for args, says in ((["--threads", "3"], "--threads"), (["--busy=maybe"], "--busy")):
            with self.subTest(args=args):
                proc = subprocess.run([BENCH, *args], capture_output=True, text=True, timeout=60)
                self.assertEqual(proc.returncode, 2, proc.stdout + proc.stderr)
                self.assertIn(says, proc.stderr)


class LabBenchEngineOptions(unittest.TestCase):
    """./lab bench engine checks its options before it installs or builds anything."""

    def test_bad_thread_counts_stop_the_command(self):
        for args, says in ((["--threads"], "needs 1 or 2"), (["--threads", "3"], "needs 1 or 2"),
                           (["--threads", "1", "5"], "expects 1 or 2, got '5'"),
                           (["--busy", "now"], "unknown option for bench engine: now")):
            with self.subTest(args=args):
                proc = subprocess.run([ROOT / "lab", "bench", "engine", *args], capture_output=True, text=True,
                                      timeout=60, cwd=ROOT)
                self.assertEqual(proc.returncode, 2, proc.stdout[-1000:] + proc.stderr[-1000:])
                lines = proc.stderr.strip().splitlines()
                self.assertEqual(len(lines), 1, proc.stderr)
                self.assertIn(says, lines[0])


if __name__ == "__main__":
    unittest.main()
