"""Each worksheet's "Before you start" tells a student what `./lab run` shows when the worksheets
before it are done and its own hooks are still stubs. These tests run every such bullet's command
with that engine (the variant progress_worksheetN of tests/progress.cmake) and hold the bullet to
what the run prints. In a bullet that runs a scene (`./lab run --scene X ...`):

- the code span `hooks not implemented yet: ...` is the summary's line, exactly (the same hooks, in
  the same order); a bullet without one says that the run lists no hook as not implemented;
- "stages are `A, B`" is the summary's whole list of stages, "stages end in `A, B`" its last ones,
  and "ends with `...`" its last line;
- every other code span, except commands (`./lab ...`), options (`--...`) and hook names (`name()`),
  quotes the run's output: it appears in it as written; one with a `<placeholder>` is a whole line,
  the placeholder standing for any word.

In a bullet that lists the scenes (`./lab run --list`), every other code span is the name of a scene
the list shows, on the key in the parentheses that follow it ("(F7)", "(key 9)") when there are any.
"""
import os
import re
import shlex
import subprocess
import unittest

import worksheet_progress

SPAN = re.compile(r"`([^`]+)`")
HOOKS_LINE = "hooks not implemented yet:"
HOOK_NAME = re.compile(r"^\w+\(\)$")
SCENE_KEY = re.compile(r"`([^`]+)` \((?:key )?(\d|F\d+)\)")


def before_you_start(path):
    """The bullets of the section "Before you start", each as one line."""
    bullets, inside = [], False
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            inside = line.lstrip("#").strip() == "Before you start"
        elif inside and line.startswith("- "):
            bullets.append(line[2:].removeprefix("[ ]").strip())
        elif inside and bullets and line.startswith(" ") and line.strip():
            bullets[-1] += " " + line.strip()
    return bullets


def words(text):
    return " ".join(text.split())


def run(worksheet, args):
    runner = os.environ.get(f"GPL_RUN_WORKSHEET{worksheet}")
    if not runner:
        raise AssertionError(f"GPL_RUN_WORKSHEET{worksheet} is not set: run these tests with ctest "
                             "(tests/progress.cmake builds the runner of each worksheet's start)")
    proc = subprocess.run([runner, *args], capture_output=True, text=True, timeout=120)
    if proc.returncode != 0:
        raise AssertionError(f"./lab run {shlex.join(args)} failed (exit {proc.returncode}): {proc.stderr.strip()}")
    return proc.stdout, proc.stderr


class BeforeYouStart(unittest.TestCase):
    def setUp(self):
        self.worksheets = worksheet_progress.worksheets()
        self.assertTrue(self.worksheets, "no worksheets found")

    def bullets(self, command):
        """(worksheet, bullet, the arguments of ./lab run) of every bullet whose first command is
        `./lab run` with `command` among its arguments."""
        for number, name in sorted(self.worksheets.items()):
            for bullet in before_you_start(worksheet_progress.ROOT / name):
                commands = [span for span in SPAN.findall(bullet) if span.startswith("./lab run")]
                if commands and command in shlex.split(commands[0]):
                    yield number, bullet, shlex.split(commands[0])[2:]

    def test_every_worksheet_runs_a_scene_first(self):
        """Each worksheet starts by running a scene, so that each has a bullet these tests check."""
        running = {number for number, _, _ in self.bullets("--scene")}
        for number, name in sorted(self.worksheets.items()):
            with self.subTest(worksheet=number):
                self.assertIn(number, running, f"{name}: \"Before you start\" runs no scene with `./lab run --scene`")

    def test_scene_runs_show_what_the_bullets_say(self):
        for number, bullet, args in self.bullets("--scene"):
            with self.subTest(worksheet=number, command=shlex.join(args)):
                stdout, stderr = run(number, args)
                self.check_run(number, bullet, args, stdout, stderr)

    def check_run(self, number, bullet, args, stdout, stderr):
        done = {1: "no worksheet done", 2: "worksheet 1 done"}.get(number, f"worksheets 1-{number - 1} done")
        where = f"worksheet {number}, `./lab run {shlex.join(args)}` with {done}"
        spans = [words(span) for span in SPAN.findall(bullet)]

        listed = [words(line) for line in stdout.splitlines() if line.startswith(HOOKS_LINE)]
        claimed = [span for span in spans if span.startswith(HOOKS_LINE)]
        self.assertLessEqual(len(claimed), 1, f"{where}: the bullet quotes more than one line of open hooks")
        if claimed != listed:
            self.fail(f"{where}: the bullet quotes {' and '.join(f'`{line}`' for line in claimed) or 'no open hooks'}, "
                      f"the summary says {' and '.join(f'`{line}`' for line in listed) or 'no hook is open'}")

        stages = re.search(r"stages: (.*?)(?:, integrator:|$)", stdout, re.M)
        self.assertIsNotNone(stages, f"{where}: the summary names no stages")
        stages = stages.group(1).split(", ")
        for said in re.findall(r"stages are `([^`]+)`", bullet):
            self.assertEqual(said.split(", "), stages, f"{where}: the summary's stages are not `{said}`")
        for said in re.findall(r"stages end in `([^`]+)`", bullet):
            self.assertEqual(said.split(", "), stages[-len(said.split(", ")):],
                             f"{where}: the summary's stages do not end in `{said}`")

        last = words(stdout.splitlines()[-1]) if stdout.strip() else ""
        for said in re.findall(r"ends with `([^`]+)`", bullet):
            self.assertEqual(words(said), last, f"{where}: the summary does not end with `{words(said)}`")

        output = stdout + stderr
        for span in spans:
            if span.startswith(("./lab", "--", HOOKS_LINE)) or HOOK_NAME.match(span):
                continue
            parts = re.split(r"<\w+>", span)
            pattern = r"\S+".join(re.escape(part) for part in parts)
            if len(parts) > 1:  # a template: of a whole line
                pattern = f"(?m)^{pattern}$"
            self.assertRegex(output, pattern, f"{where}: the run does not print `{span}`")

    def test_scene_lists_show_the_scenes_the_bullets_name(self):
        for number, bullet, args in self.bullets("--list"):
            with self.subTest(worksheet=number, command=shlex.join(args)):
                stdout, _ = run(number, args)
                keys = dict(reversed(line.split("\t")[:2]) for line in stdout.splitlines() if "\t" in line)
                for name in SPAN.findall(bullet):
                    if not name.startswith("./lab"):
                        self.assertIn(name, keys, f"worksheet {number}: `./lab run --list` shows no scene `{name}`")
                for name, key in SCENE_KEY.findall(bullet):
                    self.assertEqual(keys.get(name), key, f"worksheet {number}: `{name}` is not on key {key}")


if __name__ == "__main__":
    unittest.main()
