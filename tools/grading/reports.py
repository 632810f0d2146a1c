"""Reports of a grading: the table on screen, Gradescope's results.json, JUnit XML, the gradebook."""
import csv
import io
import json
import os
import pathlib
import re
import sys
import tempfile
import threading
import xml.etree.ElementTree as ET

from grading import GradeError, sandbox
from grading.cgroups import Cgroups


def status_word(r):
    return "pass" if r["passed"] else ("not run" if r.get("not_run") else "FAIL")


def table(results, title):
    width = max(len(r["name"]) for r in results)
    lines = [title, f"{'test':<{width}}  {'points':>9}  result"]
    for r in results:
        lines.append(f"{r['name']:<{width}}  {r['score']:>4g} / {r['points']:<2g}  {status_word(r)}")
        if r.get("not_run"):
            lines.append(f"{'':<{width}}    | {r['output']}")
        elif not r["passed"]:
            lines.append(f"{'':<{width}}    hint: {r['hint']}")
            for line in r["output"].splitlines()[:6]:
                lines.append(f"{'':<{width}}    | {line}")
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    passed = sum(r["passed"] for r in results)
    not_run = sum(bool(r.get("not_run")) for r in results)
    lines.append(f"total: {total:g} / {maximum:g} points ({passed} of {len(results)} tests passed)")
    lines.append(f"{passed} passed, {len(results) - passed} failed" + (f" ({not_run} not run)" if not_run else ""))
    return "\n".join(lines)


def gradescope(results, seconds, hidden_visibility="after_published", notes=""):
    tests = []
    for r in results:
        if r["passed"]:
            output = "passed"
        elif r.get("not_run"):
            output = r["output"]
        else:
            output = f"{r['output']}\nhint: {r['hint']}".strip()
        tests.append({"name": r["name"], "score": r["score"], "max_score": r["points"],
                      "status": "passed" if r["passed"] else "failed", "output": output,
                      "visibility": hidden_visibility if r.get("hidden") else "visible"})
    # The grader's own printout repeats hidden tests' names and messages: students never see it.
    stdout = "hidden" if any(r.get("hidden") for r in results) else "visible"
    data = {"score": sum(r["score"] for r in results), "max_score": sum(r["points"] for r in results),
            "execution_time": round(seconds, 3), "visibility": "visible", "stdout_visibility": stdout,
            "tests": tests}
    if notes:
        data["output"] = notes
    return data


_NOT_XML = re.compile("[^\u0009\u000a\u000d\u0020-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _xml_text(text):
    """Text that XML 1.0 can hold: what an engine printed may hold control characters."""
    return _NOT_XML.sub("\ufffd", text)


def junit(results, label):
    suites = ET.Element("testsuites", name=f"Game Physics Lab autograder ({label})")
    for ws in sorted({r["worksheet"] for r in results}):
        rs = [r for r in results if r["worksheet"] == ws]
        suite = ET.SubElement(suites, "testsuite", name=f"worksheet{ws}", tests=str(len(rs)),
                              failures=str(sum(not r["passed"] and not r.get("not_run") for r in rs)),
                              skipped=str(sum(bool(r.get("not_run")) for r in rs)),
                              time=f"{sum(r['seconds'] for r in rs):.3f}")
        for r in rs:
            case = ET.SubElement(suite, "testcase", classname=r["name"].split(".")[0],
                                 name=r["name"].split(".", 1)[1], time=f"{r['seconds']:.3f}")
            ET.SubElement(case, "properties").append(
                ET.Element("property", name="points", value=f"{r['score']:g}/{r['points']:g}"))
            if r.get("not_run"):
                ET.SubElement(case, "skipped", message=_xml_text(r["output"]))
            elif not r["passed"]:
                failure = ET.SubElement(case, "failure", message=_xml_text(r["hint"]))
                failure.text = _xml_text(r["output"])
    return ET.tostring(suites, encoding="unicode", xml_declaration=True)


def write_atomically(path, text):
    """Writes the whole file or nothing: a temporary file beside it, then a rename."""
    path = pathlib.Path(path)
    if not path.parent.is_dir():
        raise GradeError(f"cannot write {path}: the folder {path.parent} does not exist")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    except OSError as e:
        raise GradeError(f"cannot write {path}: {e.strerror}") from e
    try:
        with os.fdopen(fd, "w", encoding="utf-8", errors="replace") as f:  # names that are not UTF-8
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as e:
        pathlib.Path(tmp).unlink(missing_ok=True)
        raise GradeError(f"cannot write {path}: {e.strerror}") from e


def check_writable(path):
    if path is None:
        return
    path = pathlib.Path(path)
    if path.is_dir():
        raise GradeError(f"cannot write {path}: it is a folder")
    parent = path.resolve().parent
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise GradeError(f"cannot write {path}: the folder {parent} does not exist or is not writable")


def worksheet_files(root):
    """{N: "worksheets/0N-name.md"} of the worksheets the course has."""
    found = {}
    for path in sorted((pathlib.Path(root) / "worksheets").glob("[0-9][0-9]-*.md")):
        found[int(path.name[:2])] = f"worksheets/{path.name}"
    return found


def next_step(results, worksheet, root):
    """What comes after full marks: the next worksheet, or that all are done; None before that."""
    if not results or not all(r["passed"] for r in results):
        return None
    files = worksheet_files(root)
    done = worksheet if worksheet else max(r["worksheet"] for r in results)
    later = sorted(n for n in files if n > done)
    head = f"full marks on worksheet {worksheet}" if worksheet else "full marks"
    if later:
        return f"{head}. Next: worksheet {later[0]}, {files[later[0]]}"
    return f"{head}: all worksheets done"


def report(results, label, args, seconds, notes="", root=None):
    lines = table(results, f"Game Physics Lab autograder: {label}"
                  + (f", worksheet {args.worksheet}" if args.worksheet else "")).splitlines()
    step = next_step(results, args.worksheet, root) if root else None
    # The last line stays the count of passed and failed tests.
    mechanisms = [line for line in (sandbox.Sandbox.here().describe(), Cgroups.here().describe()) if line]
    lines[-1:-1] = mechanisms + ([step] if step else [])
    print("\n".join(lines))
    notes = "\n".join(n for n in (notes, *mechanisms) if n)
    if args.json:
        write_atomically(args.json, json.dumps(gradescope(results, seconds, args.hidden_visibility, notes), indent=2) + "\n")
        print(f"wrote {args.json}")
    if args.junit:
        write_atomically(args.junit, junit(results, label))
        print(f"wrote {args.junit}")
    full = all(r["passed"] for r in results)
    return 0 if full else 1



class Progress:
    """One line on the terminal ("grading: 12 of 50 submissions, 3 running"), or a line per
    finished submission when the output is not a terminal."""

    def __init__(self, total, stream=sys.stderr):
        self.total, self.stream, self.done, self.running = total, stream, 0, 0
        self.tty = stream.isatty()
        self.lock = threading.Lock()

    def say(self, text):
        with self.lock:
            if self.tty:
                self.stream.write(f"\r\033[K{text}")
            else:
                self.stream.write(text + "\n")
            self.stream.flush()

    def started(self):
        with self.lock:
            self.running += 1

    def finished(self, sub):
        with self.lock:
            self.done += 1
            self.running -= 1
            done, running = self.done, self.running
        total = sum(r["score"] for r in sub.results)
        maximum = sum(r["points"] for r in sub.results)
        self.say(f"grading: {done} of {self.total} submissions done, {running} running "
                 f"(last: {sub.name} {total:g}/{maximum:g})")

    def end(self):
        if self.tty:
            self.stream.write("\n")



def gradebook(subs):
    names = [r["name"] for r in subs[0].results]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["submission", *names, "total", "max_score", "note"])
    for s in subs:
        scores = {r["name"]: r["score"] for r in s.results}
        notes = [s.error or ("does not compile" if s.build_errors is not None else "")]
        if s.missing:
            notes.append("graded as the untouched stub: " + " ".join(s.missing))
        if s.ignored:
            notes.append("ignored: " + " ".join(s.ignored[:5]) + (" ..." if len(s.ignored) > 5 else ""))
        note = "; ".join(n for n in notes if n)
        w.writerow([s.name, *(f"{scores[n]:g}" for n in names), f"{sum(scores.values()):g}",
                    f"{sum(r['points'] for r in s.results):g}", note])
    return out.getvalue()
