#!/usr/bin/env python3
"""A student part way through the course, as hook directories: before worksheet N, the hook files of
the worksheets before N are done (the reference's text) and the others are still stubs. Which
worksheet a hook file belongs to is what the grader reads from the files' heads
(grading.running.hook_worksheets()); which worksheets there are, what its reports name
(grading.reports.worksheet_files()).

  worksheet_progress.py write DIR   writes DIR/worksheetN for every worksheet N (a file only when its
                                    text changes) and prints N per line; tests/progress.cmake builds
                                    each as the variant progress_worksheetN
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))

import hooks  # noqa: E402
from grading import reports, running  # noqa: E402


def worksheets():
    """{N: "worksheets/0N-name.md"} of the worksheets the course has."""
    return reports.worksheet_files(ROOT)


def file_worksheets():
    """{"integrator.cpp": 1, ...}: the worksheet of each hook file, that of the hook its stub
    announces. A file that announces none (the student's own scenes) has none and is left out."""
    worksheet_of = running.hook_worksheets()
    found = {}
    for name in hooks.hook_files():
        text = (hooks.ASSIGNMENTS / name).read_text()
        numbers = {n for hook, n in worksheet_of.items() if f'otImplemented("{hook}")' in text}
        if len(numbers) > 1:
            raise SystemExit(f"assignments/{name} announces hooks of worksheets {sorted(numbers)}: one file, one worksheet")
        if numbers:
            found[name] = numbers.pop()
    return found


def hook_texts(worksheet):
    """{file: text} of a student who finished the worksheets before `worksheet`."""
    worksheet_of = file_worksheets()
    texts = {}
    for name in hooks.hook_files():
        solution = (hooks.SOLUTIONS / name).read_text()
        stub = (hooks.ASSIGNMENTS / name).read_text()
        if name not in worksheet_of and solution != stub:
            raise SystemExit(f"{name} belongs to no worksheet, yet its solution and its stub differ")
        texts[name] = solution if worksheet_of.get(name, worksheet) < worksheet else stub
    return texts


def write(outdir):
    outdir = pathlib.Path(outdir)
    for number in sorted(worksheets()):
        target = outdir / f"worksheet{number}"
        target.mkdir(parents=True, exist_ok=True)
        for name, text in hook_texts(number).items():
            path = target / name
            if not path.exists() or path.read_text() != text:
                path.write_text(text)
        print(number)


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] != "write":
        raise SystemExit("usage: worksheet_progress.py write DIR")
    write(sys.argv[2])
