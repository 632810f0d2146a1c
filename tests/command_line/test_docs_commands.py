"""Every `./lab` command that README.md and docs/*.md show works as shown. A command is shown in a
fenced code block (a line that starts with `./lab` or `$ ./lab`, or a `./lab` after `run:` or
`command:` in a workflow) or in inline code (`./lab ...`). Each is held to `./lab help` and to the
program behind it, the way the student README's commands are held to a student release
(tests/grader/test_release.py), but in seconds: the long commands are checked, not run.

- The command (and the study of `./lab bench`) is one that `./lab help` lists.
- Every option is one that the command's lines of `./lab help` show, or that the program behind it
  lists in its --help (the runner, the viewer, tools/grade.py, tools/release.py); `./lab bench
  stages` passes Google Benchmark's `--benchmark_*` options on.
- A value is one the option takes: one of the choices `./lab help` or --help shows
  (`--preset release|debug|asan|asan-core`), a whole number where the option takes one, a scene that
  `./lab run --list` lists, a worksheet that exists.
- `./lab help`, `./lab viewer --help` and every `./lab run` run, the last through the runner that
  `./lab run` builds (exit 0), with `--csv` files written to a temporary folder.
- A command shown with the line after it starting with `error:` shows a mistake: it must exit
  with status 2 and print that line.

A word in capitals (`DIR`, `FILE.csv`, `N`, `SCENE`) stands for a value the reader chooses: such a
command is checked, never run. Shell syntax that cannot be checked ([optional] parts, a|b
alternatives) is reported: the docs show concrete commands.

The same test also holds every link to a file of the lab, every path of the lab in inline code and
every GoogleTest name (`Suite.Name`) shown to files and tests that exist.
"""
import dataclasses
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
RUN = os.environ.get("GPL_RUN_SOLUTIONS")
RUN_STUBS = os.environ.get("GPL_RUN_ASSIGNMENTS")
VIEWER = os.environ.get("GPL_VIEWER_SOLUTIONS")


def doc_files():
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@dataclasses.dataclass
class Shown:
    command: str               # as written, from ./lab on
    line: int                  # where in the file
    error: str | None = None   # the error line shown after it, for a command shown failing


FENCE = re.compile(r"^\s*```")
INLINE = re.compile(r"`(\./lab\b[^`]*)`")
# Where a command starts in a line of a code block: at its start (after "$ " for a prompt), or
# after "run:" / "command:" of a workflow.
BLOCK_COMMAND = re.compile(r"^\s*(?:\$ |(?:- )?(?:run|command): )?(\./lab\b.*)$|(?:command|run): (\./lab\b.*)$")
# Where a command ends inside a YAML flow mapping ("{..., command: ./lab grade --worksheet 1, timeout: 20}").
YAML_END = re.compile(r",\s|\}")


def commands_in(text):
    """The ./lab commands a Markdown text shows, in order, each once."""
    shown, in_block, lines = [], False, text.splitlines()
    for i, line in enumerate(lines):
        if FENCE.match(line):
            in_block = not in_block
            continue
        if not in_block:
            continue
        match = BLOCK_COMMAND.search(line)
        if match:
            command = (match.group(1) or match.group(2)).strip()
            if "{" in line[:line.index("./lab")]:
                command = YAML_END.split(command)[0].strip()
            after = lines[i + 1].strip() if i + 1 < len(lines) else ""
            shown.append(Shown(command, i + 1, after if after.startswith("error:") else None))
    # Inline code: outside the code blocks (a backtick inside a block is the shell's).
    outside, in_block = [], False
    for line in lines:
        if FENCE.match(line):
            in_block = not in_block
            outside.append("")
        else:
            outside.append("" if in_block else line)
    prose = "\n".join(outside)
    for match in INLINE.finditer(prose):
        shown.append(Shown(" ".join(match.group(1).split()), prose.count("\n", 0, match.start()) + 1))
    unique = {}
    for s in shown:
        unique.setdefault((s.command, s.error), s)
    return list(unique.values())


# A value the reader chooses: DIR, FILE.csv, N, N..., SCENE (a scene key such as F3 is not one).
PLACEHOLDER = re.compile(r"(?:[A-Z]{2,}|[NSH])(?:[._-][A-Za-z0-9]+)*(?:\.\.\.|…)?|\.\.\.|…")
SCENE_KEY = re.compile(r"F\d+")


def placeholder(word):
    return bool(PLACEHOLDER.fullmatch(word)) and not SCENE_KEY.fullmatch(word)


@dataclasses.dataclass
class Option:
    takes: str | None = None       # its value's kind (its metavar): None for a flag
    choices: set | None = None
    many: bool = False             # --sizes N...: every word up to the next option


ALTERNATIVES = re.compile(r"\w\|\w")  # release|debug, outside quotes
QUOTED = re.compile(r"'[^']*'|\"[^\"]*\"")


def words_of(command):
    """The words of a command as the shell splits them, up to a shell operator (`|| true`, `| tee`)
    or a comment; an [optional] part or a|b alternatives are a ValueError."""
    if ALTERNATIVES.search(QUOTED.sub("", command)):
        raise ValueError("a|b: show one value, not the alternatives")
    lexer = shlex.shlex(command, posix=True, punctuation_chars=";&|<>()")
    lexer.whitespace_split = True
    words = []
    for word in lexer:
        if set(word) <= set(";&|<>()"):
            break
        words.append(word)
    for w in words:
        if w.startswith("[") or w.endswith("]"):
            raise ValueError(f"'{w}': show a concrete command, not a synopsis with [optional] parts")
    return words


def positionals_of_synopsis(tokens):
    """The words a synopsis line shows apart from options: SCENE in '[--debug] [SCENE]', DIR in
    'release DIR [--reference-demo]'."""
    return {t.strip("[]") for i, t in enumerate(tokens)
            if t.strip("[]").isupper() and (i == 0 or tokens[i - 1].endswith("]"))}


def options_of_synopsis(tokens, positionals):
    """The options of one synopsis line of ./lab help: '--scene NAME|KEY' takes a value, '[--list]'
    is a flag, '--preset release|debug' takes one of those, '--sizes N...' several; '--headless
    SCENE' is a flag when SCENE is a word of its own elsewhere ('[SCENE]')."""
    options = {}
    tokens = [t.strip("[]") for t in tokens]
    for i, token in enumerate(tokens):
        if not token.startswith("--"):
            continue
        name, _, value = token.partition("=")
        if (not value and i + 1 < len(tokens) and tokens[i + 1] and not tokens[i + 1].startswith(("-", "|"))
                and tokens[i + 1] not in positionals):
            value = tokens[i + 1]
        if not value:
            options[name] = Option()
            continue
        many = value.endswith("...")
        value = value.removesuffix("...")
        choices = set(value.split("|")) if "|" in value and value == value.lower() else None
        options[name] = Option(takes=value, choices=choices, many=many)
    return options


# An option in a program's --help: CLI11 ("  -s,--scene TEXT   ...", "  --paused   ...") or argparse
# ("  -h, --help", "  --hidden-visibility {hidden,after_published}", "  --out FILE.csv   ...").
HELP_OPTION = re.compile(r"^\s{2}(?:(-\w),\s?)?(--[\w-]+)(?: (\{[^}]*\}|[A-Z][\w.]*))?(?:\s|$)")


def options_of_help(text):
    options = {}
    for line in text.splitlines():
        match = HELP_OPTION.match(line)
        if not match:
            continue
        short, name, value = match.groups()
        choices = set(value[1:-1].split(",")) if value and value.startswith("{") else None
        option = Option(takes=value, choices=choices)
        options.setdefault(name, option)
        if short:
            options.setdefault(short, option)
    return options


def output(cmd, env=None):
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=60, cwd=ROOT,
                          env={**os.environ, **(env or {})})
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} exited with {proc.returncode}: {proc.stderr[-500:]}")
    return proc.stdout


INTEGER = re.compile(r"\d+")
NUMBER = re.compile(r"[0-9.]+(?:e-?\d+)?")


class Lab:
    """What ./lab and the programs behind it accept, read from their help."""

    # The command's own program, whose --help lists options beyond ./lab help's lines.
    PROGRAMS = {"grade": [ROOT / "tools" / "grade.py", "grade"], "release": [ROOT / "tools" / "release.py", "release"],
                "gradescope": [ROOT / "tools" / "release.py", "gradescope"]}
    POSITIONALS = {"release": 1, "gradescope": 1, "viewer": 1}

    def __init__(self):
        self.usage = output([ROOT / "lab", "help"])
        lines = {}  # "run", "bench engine", ... -> the words of their synopsis lines
        for line in self.usage.splitlines():
            match = re.match(r"^\s{2}\./lab (\w+)(?: (accuracy|contacts|engine|solvers|cloth|fluids|stages)\b)?(.*)$", line)
            if match:
                lines.setdefault(" ".join(filter(None, match.groups()[:2])), []).append(match.group(3).split())
        self.synopses = {}  # the same -> their options
        for name, synopses in lines.items():
            positionals = set().union(*(positionals_of_synopsis(tokens) for tokens in synopses))
            self.synopses[name] = {}
            for tokens in synopses:
                self.synopses[name].update(options_of_synopsis(tokens, positionals))
        # "(--solutions, as in ./lab grade --solutions, is --reference for run, viewer and bench.)"
        assert "is --reference for run, viewer and bench" in self.usage, "./lab help says what --solutions is"
        for name, options in self.synopses.items():
            if "--reference" in options:
                options["--solutions"] = options["--reference"]
        self.helps = {name: options_of_help(output([sys.executable, *cmd, "--help"]))
                      for name, cmd in self.PROGRAMS.items()}
        if RUN:
            self.helps["run"] = options_of_help(output([RUN, "--help"]))
            self.scenes = set()
            for line in output([RUN, "--list"]).splitlines():
                key, name = line.split("\t")[:2]
                self.scenes |= {name, key} - {""}
        if VIEWER:
            self.helps["viewer"] = options_of_help(output([VIEWER, "--help"], env={"DISPLAY": ""}))
        self.worksheets = {str(int(p.name[:2])) for p in (ROOT / "worksheets").glob("[0-9][0-9]-*.md")}

    def check(self, shown, tmp):
        """What is wrong with a command shown (an empty list: nothing), and whether it ran."""
        try:
            words = words_of(shown.command)
        except ValueError as e:
            return [str(e)], False
        if not words or words[0] != "./lab":
            return ["not a ./lab command"], False
        if len(words) == 1:
            words = ["./lab", "help"]  # ./lab alone prints its help
        name = words[1]
        rest = words[2:]
        if name == "bench":
            if not rest or f"bench {rest[0]}" not in self.synopses:
                return [f"./lab bench {rest[0] if rest else ''}: not a study of ./lab help"], False
            name, rest = f"bench {rest[0]}", rest[1:]
        if name not in self.synopses:
            return [f"'{name}' is not a command of ./lab help"], False
        problems, positionals = [], []
        options = {**self.helps.get(name, {}), **self.synopses[name]}
        checked_whole = name not in ("run", "viewer") or name in self.helps
        i = 0
        while i < len(rest):
            word = rest[i]
            i += 1
            if not word.startswith("-") or word == "-":
                positionals.append(word)
                continue
            key, eq, value = word.partition("=")
            if name == "bench stages" and key.startswith("--benchmark_"):
                continue  # Google Benchmark's own options pass through
            option = options.get(key)
            if option is None and not checked_whole:
                # An option of the viewer, in a build without it: the rest cannot be told apart.
                return problems, False
            if option is None:
                problems.append(f"{key}: not an option of ./lab {name}")
                continue
            if option.takes is None:
                if eq:
                    problems.append(f"{key} takes no value")
                continue
            values = [value] if eq else []
            while not eq and i < len(rest) and (not values or option.many) and not rest[i].startswith("--"):
                values.append(rest[i])
                i += 1
            if not values:
                problems.append(f"{key} needs a value ({option.takes})")
            for v in values:
                # A command shown failing may have a wrong value: running it tells.
                problems += [] if shown.error else self.value_problems(key, option, v)
        if name == "viewer" and positionals:
            problems += self.value_problems("scene", Option(takes="SCENE"), positionals[0])
        if len(positionals) != self.POSITIONALS.get(name, 0) and not (name == "viewer" and len(positionals) < 2):
            problems.append(f"./lab {name} takes {self.POSITIONALS.get(name, 0)} word(s) besides options, "
                            f"got {positionals}")
        if problems or any(placeholder(w) for w in rest):
            return problems, False
        return self.run(shown, name, words, tmp)

    def value_problems(self, key, option, value):
        if placeholder(value):
            return []
        if option.choices is not None:
            return [] if value in option.choices else [f"{key} {value}: expects {'|'.join(sorted(option.choices))}"]
        if key in ("--scene", "-s", "scene") and RUN:
            return [] if value in self.scenes else [f"{key} {value}: not a scene of ./lab run --list"]
        if key == "--scenes" and RUN:
            return [f"--scenes: {s} is not a scene of ./lab run --list" for s in value.split(",") if s not in self.scenes]
        if key == "--worksheet":
            return [] if value in self.worksheets else [f"--worksheet {value}: there is no such worksheet"]
        if option.takes in ("N", "INT") and not INTEGER.fullmatch(value):
            return [f"{key} {value}: expects a whole number"]
        if option.takes in ("FLOAT", "H", "S") and not NUMBER.fullmatch(value):
            return [f"{key} {value}: expects a number"]
        return []

    def run(self, shown, name, words, tmp):
        """Runs a cheap command: its problems (none when it did what was shown), and whether it ran."""
        env, rest = None, words[2:]
        if name == "help":
            cmd = [ROOT / "lab", "help"]
        elif name == "run" and RUN and RUN_STUBS:
            # What ./lab run runs after building, before it opens the viewer (tests/viewer covers that).
            reference = {"--reference", "--solutions"} & set(rest)
            args = [w for w in rest if w not in ("--reference", "--solutions", "--debug")]
            args = [str(tmp / pathlib.Path(a).name) if i and args[i - 1] == "--csv" else a for i, a in enumerate(args)]
            cmd = [RUN if reference else RUN_STUBS, *args]
        elif name == "viewer" and rest == ["--help"] and VIEWER:
            cmd, env = [VIEWER, "--help"], {"DISPLAY": ""}
        elif shown.error:
            cmd = [ROOT / "lab", *words[1:]]  # a mistake ./lab stops at before it builds anything
        else:
            return [], False
        proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=120, cwd=tmp,
                              env={**os.environ, **(env or {})})
        if shown.error:
            if proc.returncode != 2 or proc.stderr.strip() != shown.error:
                return [f"shown failing with '{shown.error}', but it exited with {proc.returncode}: "
                        f"{proc.stderr.strip()}"], True
            return [], True
        if proc.returncode != 0:
            return [f"exited with {proc.returncode}: {(proc.stdout + proc.stderr)[-1000:]}"], True
        return [], True


def problems_of(lab, text):
    """Each command of a Markdown text with what is wrong with it; and how many commands ran."""
    found, ran = [], 0
    with tempfile.TemporaryDirectory(prefix="gpl-docs-") as tmp:
        for shown in commands_in(text):
            problems, did_run = lab.check(shown, pathlib.Path(tmp))
            ran += did_run
            if problems:
                found.append((shown, problems))
    return found, ran


# Paths of the lab in inline code ("tests/mutants/*.json", "tools/grading/guard.py").
LAB_PATH = re.compile(r"`((?:framework|assignments|solutions|tests|tools|bench|cmake|worksheets|docs)/[^`\s]*)`")
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")
GTEST_NAME = re.compile(r"`([A-Z]\w+)\.([A-Z]\w+)`")


@unittest.skipUnless(RUN and RUN_STUBS, "GPL_RUN_SOLUTIONS and GPL_RUN_ASSIGNMENTS name the runners")
class DocsCommands(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.lab = Lab()

    def test_every_command_shown_works(self):
        total, ran = 0, 0
        for path in doc_files():
            commands = commands_in(path.read_text())
            total += len(commands)
            found, did_run = problems_of(self.lab, path.read_text())
            ran += did_run
            for shown, problems in found:
                with self.subTest(file=path.name, line=shown.line, command=shown.command):
                    self.fail("; ".join(problems))
        # The README and the docs show the lab's every command; a handful would mean the reading failed.
        self.assertGreaterEqual(total, 40)
        self.assertGreaterEqual(ran, 10)

    def test_a_wrong_command_is_caught(self):
        # A text like the docs with one mistake per command; each must be found, and only those.
        text = "\n".join([
            "```sh",
            "./lab run --scene projectile --steps 10",
            "./lab frobnicate",
            "./lab test --preset fastest",
            "./lab bench speed",
            "./lab bench engine --sizes 1000 8000 --bogus",
            "./lab grade --worksheet 99",
            "./lab run --scene nowhere",
            "./lab run --steps ten",
            "./lab release DIR --reference-demo",
            "./lab grade --batch DIR --out grades.csv --jobs 2",
            "```",
            "Run `./lab viewer --headless projectile --frames 2 --out DIR` or `./lab grade [--json FILE]`.",
            "```",
            "$ ./lab run --steps abc",
            "error: --steps: expects a whole number of 0 or more, got 'abc'",
            "$ ./lab run --steps 5",
            "error: --steps: this is not what it says",
            "```",
        ])
        found, _ = problems_of(self.lab, text)
        wrong = sorted(shown.command for shown, _ in found)
        expected = ["./lab bench engine --sizes 1000 8000 --bogus", "./lab bench speed", "./lab frobnicate",
                    "./lab grade --worksheet 99", "./lab grade [--json FILE]", "./lab run --scene nowhere",
                    "./lab run --steps 5", "./lab run --steps ten", "./lab test --preset fastest"]
        self.assertEqual(wrong, expected, found)

    def test_links_paths_and_test_names_exist(self):
        sources = "\n".join(p.read_text() for p in (ROOT / "tests").rglob("*_test.cpp"))
        for path in doc_files():
            text = path.read_text()
            # The student README becomes a release's top-level README.md: its links start there.
            base = ROOT if path.name == "student-README.md" else path.parent
            for target in LINK.findall(text):
                if "://" in target:
                    continue
                with self.subTest(file=path.name, link=target):
                    self.assertTrue((base / target).exists(), f"{path.name} links to {target}, which does not exist")
            for shown in LAB_PATH.findall(text):
                # Placeholders and patterns (worksheetN_test.cpp, mutant_NAME, *.json) match any such file.
                pattern = re.sub(r"(?<=[a-z])N(?=[_.])|NAME|VARIANT|\*", "*", shown.rstrip("/…."))
                with self.subTest(file=path.name, path=shown):
                    self.assertTrue(list(ROOT.glob(pattern)), f"{path.name} names {shown}, which does not exist")
            for suite, name in GTEST_NAME.findall(text):
                with self.subTest(file=path.name, test=f"{suite}.{name}"):
                    self.assertRegex(sources, rf"TEST\(\s*{suite},\s*{name}\b", f"{path.name} names a test that does not exist")


if __name__ == "__main__":
    unittest.main()
