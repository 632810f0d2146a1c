"""./lab test shows its progress: on a terminal one line with a bar of the build's steps, then of the
tests, with only the failures and the summary printed in full; into a file or a pipe (CI) it adds
nothing: no bar, no carriage return, ctest's lines as ctest writes them, its summary last. A copy of
./lab runs here with stand-ins for cmake and ctest that print what ninja and ctest print, so that
nothing is built or tested."""
import fcntl
import os
import pathlib
import pty
import shutil
import struct
import subprocess
import tempfile
import termios
import textwrap
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]

CMAKE = textwrap.dedent("""\
    #!/bin/sh
    # configure: cmake --preset P; build: cmake --build --preset P ... (ninja's lines as NINJA_STATUS asks)
    if [ "$1" = --preset ]; then mkdir -p "build/$2" && touch "build/$2/CMakeCache.txt"; exit 0; fi
    [ "$NINJA_STATUS" = "[%f/%t] " ] || { echo "NINJA_STATUS is not [%f/%t]" >&2; exit 1; }
    for i in 1 2 3 4; do echo "[$i/4] Building CXX object step$i.o"; done
    echo "warning: a compiler's note that only the build's log keeps"
    """)
TESTS = textwrap.dedent("""\
    Test project /somewhere/build/release
        Start 1: framework.one
        Start 2: framework.two
    1/3 Test #1: framework.one ....................   Passed    0.10 sec
    2/3 Test #2: framework.two ....................***Failed    0.20 sec
    what framework.two said
        Start 3: framework.three
    3/3 Test #3: framework.three ..................   Passed    0.30 sec

    67% tests passed, 1 tests failed out of 3

    Total Test time (real) =   0.61 sec
    """)
CTEST = "#!/bin/sh\ncat <<'EOF'\n" + TESTS + "EOF\nexit 8\n"


class Progress(unittest.TestCase):
    def setUp(self):
        self.dir = pathlib.Path(tempfile.mkdtemp(prefix="gpl-progress-"))
        self.addCleanup(shutil.rmtree, self.dir, ignore_errors=True)
        for name in ("lab", "CMakePresets.json"):
            shutil.copy2(ROOT / name, self.dir / name)
        bin_dir = self.dir / "bin"
        bin_dir.mkdir()
        for name, text in (("cmake", CMAKE), ("ctest", CTEST)):
            (bin_dir / name).write_text(text)
            (bin_dir / name).chmod(0o755)
        self.env = {**os.environ, "PATH": f"{bin_dir}:{os.environ['PATH']}", "TERM": "xterm"}
        self.env.pop("NINJA_STATUS", None)

    def test_into_a_pipe_only_ctest_lines_are_added(self):
        proc = subprocess.run([self.dir / "lab", "test", "--preset", "release"], capture_output=True, text=True,
                              env=self.env, cwd=self.dir, timeout=60)
        self.assertEqual(proc.returncode, 1, proc.stderr)
        self.assertEqual(proc.stdout, "lab: building (release)\nlab: testing (release)\n" + TESTS)
        self.assertEqual(proc.stderr, "lab: tests failed in: release\n")
        self.assertIn("warning: a compiler's note", (self.dir / "build/release/last-build.log").read_text())

    def test_on_a_terminal_a_bar_moves_and_failures_are_printed(self):
        main, child = pty.openpty()
        fcntl.ioctl(child, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
        proc = subprocess.Popen([self.dir / "lab", "test", "--preset", "release"], stdin=subprocess.DEVNULL,
                                stdout=child, stderr=subprocess.PIPE, env=self.env, cwd=self.dir)
        os.close(child)
        chunks = []
        while True:
            try:
                chunk = os.read(main, 4096)
            except OSError:  # the terminal closed: the lab is done
                break
            if not chunk:
                break
            chunks.append(chunk)
        os.close(main)
        _, err = proc.communicate(timeout=60)
        self.assertEqual((proc.returncode, err), (1, b"lab: tests failed in: release\n"))
        out = b"".join(chunks).decode().replace("\r\n", "\n")
        self.assertIn("\rlab: building (release) [" + "#" * 20 + "." * 20 + "] 2/4", out)
        self.assertIn("\rlab: testing (release) [" + "#" * 26 + "." * 14 + "] 2/3, 1 failed", out)
        # What stays on the screen once each bar is erased: the headings, the failure, the summary.
        screen = [line.rsplit("\r", 1)[-1].replace("\x1b[K", "") for line in out.split("\n")]
        self.assertEqual([line for line in screen if line], [
            "lab: building (release)", "lab: testing (release)", "Test project /somewhere/build/release",
            "2/3 Test #2: framework.two ....................***Failed    0.20 sec", "what framework.two said",
            "67% tests passed, 1 tests failed out of 3", "Total Test time (real) =   0.61 sec"])
        self.assertNotIn("warning", out)


if __name__ == "__main__":
    unittest.main()
