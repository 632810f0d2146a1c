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

from grading import GradeError, running, sandbox
from grading.cgroups import Cgroups


def status_word(r):
    return "pass" if r["passed"] else ("not run" if r.get("not_run") else "FAIL")


# ---- What a failure says: GoogleTest's own text out, numbers to 6 digits -------------------------

_NUMBER = re.compile(r"(?<![\w.])-?\d+\.\d+(?:[eE][-+]?\d+)?(?!\w|\.\d)")
_EXPECTED = re.compile(r"^Expected: \((.*)\) (<|<=|>|>=|==|!=) \((.*)\), actual: (.*) vs (.*)$")
_EXCEPTION = re.compile(r'C\+\+ exception with description "(.*)" thrown in the test body\.?', re.S)


def _short_number(m):
    text = m.group(0)
    digits = re.sub(r"\D", "", re.split(r"[eE]", text)[0]).lstrip("0")
    return text if len(digits) <= 6 else f"{float(text):.6g}"


def clean(message):
    """A message without GoogleTest's raw text ("unknown file: Failure", "C++ exception with
    description ... thrown in the test body", "Expected: (a) < (b), actual: x vs y") and with numbers
    of more than 6 significant digits given to 6 (digits inside names and paths are left alone)."""
    message = _EXCEPTION.sub(lambda m: m.group(1), message)
    lines = []
    for line in message.splitlines():
        if line.strip() in ("unknown file: Failure", "unknown file", "Failure"):
            continue
        m = _EXPECTED.match(line.strip())
        if m:
            line = f"expected {m.group(1)} {m.group(2)} {m.group(3)}, got {m.group(4)} vs {m.group(5)}"
        lines.append(_NUMBER.sub(_short_number, line))
    return "\n".join(lines).strip()


# ---- One cause, one message ----------------------------------------------------------------------

_ASSERT = re.compile(r"(?P<where>[^\s:]+:\d+): (?P<function>[^\n]*?): Assertion `(?P<condition>.*)' failed\.")
_IN_HOOK = re.compile(r" in (\S+\(\))(?: in step \d+)?$")
_IN_STEP = re.compile(r" in step (\d+)$")
OPEN_HOOKS = running.OPEN_HOOKS

# What a failed assert usually means, by a pattern of its condition (the first that matches).
MEANINGS = [
    (r"energyAfter\s*<=\s*energyBefore", "the total energy grew in a step (explicit Euler's signature: x += h v "
                                          "with the old velocity), or is no longer a number (a static body, of "
                                          "infinite mass, that moved)"),
    (r"isFinite|isfinite|isnan", "a position or velocity became NaN or infinite: a division by zero, or an "
                                 "infinite mass times zero"),
]
GENERIC_MEANING = "a condition the code asserts was false: read it, and where it is checked"


def meaning(condition):
    return next((text for pattern, text in MEANINGS if re.search(pattern, condition)), GENERIC_MEANING)


def own_failure(r):
    """Whether the test failed on its own assertions (not a crash, a limit, open hooks, not run)."""
    if r["passed"] or r.get("not_run"):
        return False
    return not r["output"].startswith(running.ENGINE_FAILURES + (OPEN_HOOKS,))


def cause_of(r):
    """(key, kind) of an engine failure several tests may share: the same failed assert, or the same
    crash in the same hook; None for a test that failed otherwise."""
    if r["passed"] or r.get("not_run"):
        return None
    if r["output"].startswith(running.STOPPED_EARLY):
        # Which body and step differ from test to test; the hook to check is the cause.
        return ("finite", r["output"].rsplit("check ", 1)[-1]), "non-finite state"
    if not r["output"].startswith("crashed with"):
        return None
    first = r["output"].splitlines()[0]
    hook = _IN_HOOK.search(first)
    m = _ASSERT.search(r["output"])
    if m:
        # The assert names its own function: the same line is the same cause, whichever hook the
        # checker had in flight around it (the hook alone, or the whole step).
        function = m.group("function").split("(")[0].split("::")[-1].split()[-1]
        return ("assert", m.group("where"), m.group("condition"), function + "()" if function else
                (hook.group(1) if hook else "")), "failed assertion"
    return ("signal", first), "crash"


def _step_of(r):
    """The step a crashed test's engine was taking, from its message's first line; None if unknown."""
    m = _IN_STEP.search(r["output"].splitlines()[0])
    return int(m.group(1)) if m else None


def analyse(results):
    """What the reports say of each test, once: {"causes": [...], "groups": [...], name: view}, where
    a view is {"message", "short", "hint", "cause", "group"}."""
    views = {r["name"]: {"message": clean(r["output"]), "hint": own_failure(r), "cause": None, "group": None}
             for r in results}
    shared = {}
    for r in results:
        found = cause_of(r)
        if found:
            shared.setdefault(found[0], []).append(r)
    causes = []
    for key, rs in shared.items():
        if len(rs) < 2:
            continue
        kind = {"assert": "failed assertion", "finite": "non-finite state"}.get(key[0], "crash")
        # The whole message goes with a visible test: others (Gradescope) point at it by name.
        rs = sorted(rs, key=lambda r: bool(r.get("hidden")))
        first = views[rs[0]["name"]]["message"].splitlines()[0]
        steps = {r["name"]: _step_of(r) for r in rs}
        same_step = len(set(steps.values())) == 1 and None not in steps.values()
        at = f", in step {steps[rs[0]['name']]}" if same_step else ""
        if key[0] == "assert":
            _, where, condition, hook = key
            text = [f"{len(rs)} tests stopped on the same failed assertion" + (f", in {hook}" if hook else "") + at + ":",
                    f"  {where}: assert({clean(condition)})",
                    f"  what it usually means: {meaning(condition)}"]
        elif key[0] == "finite":
            text = [f"{len(rs)} tests {first}",
                    f"  what it usually means: {meaning('isFinite')}"]
        else:
            text = [f"{len(rs)} tests stopped on the same crash: {first}",
                    *("  " + line for line in views[rs[0]["name"]]["message"].splitlines()[1:5])]
        cause = {"kind": kind, "text": "\n".join(text), "tests": [r["name"] for r in rs], "first": rs[0]["name"]}
        causes.append(cause)
        for r in rs:
            views[r["name"]]["cause"] = cause
            views[r["name"]]["hint"] = False
            views[r["name"]]["step"] = None if same_step else steps[r["name"]]
            if r is not rs[0]:
                own = views[r["name"]]["message"].splitlines()[0]
                views[r["name"]]["short"] = f"{own}: stopped on the same {kind} as {rs[0]['name']}"
    # Tests that fail only because their hooks are still open, and those not run until they pass.
    groups, grouped = {}, set()
    by_name = {r["name"]: r for r in results}
    for r in results:
        if r["passed"] or views[r["name"]]["cause"]:
            continue
        if not r.get("not_run") and r["output"].startswith(OPEN_HOOKS):
            hooks_open = r["output"].splitlines()[0][len(OPEN_HOOKS):].strip()
            key = f"not written yet: {hooks_open}"
            views[r["name"]]["short"] = f"{OPEN_HOOKS} {hooks_open}"
        elif r.get("not_run"):
            blocked = [d for d in r.get("depends_on", []) if d in by_name and not by_name[d]["passed"]]
            if not blocked or any(d not in grouped and not by_name[d].get("not_run") for d in blocked):
                continue
            key = "not run until those pass"
        else:
            continue
        groups.setdefault(key, []).append(r)
        grouped.add(r["name"])
        views[r["name"]]["group"] = key
    views["causes"] = causes
    # Open hooks first, in the order of the course; what waits for them last.
    views["groups"] = sorted(groups.items(), key=lambda item: item[0].startswith("not run"))
    return views


def _group_line(key, rs):
    names = [r["name"] for r in rs]
    shown = ", ".join(names[:2]) + (", ..." if len(names) > 2 else "")
    points = sum(r["points"] for r in rs)
    return f"{key} — {len(rs)} test{'s' if len(rs) > 1 else ''}, 0 / {points:g} points ({shown})"


def count_line(results):
    passed = sum(bool(r["passed"]) for r in results)
    not_run = sum(bool(r.get("not_run")) for r in results)
    failed = len(results) - passed - not_run
    parts = [f"{failed} failed"] + ([f"{not_run} not run"] if not_run else [])
    return f"{passed} of {len(results)} tests passed" + (": " + ", ".join(parts) if failed or not_run else "")


def table(results, title):
    views = analyse(results)
    width = max(len(r["name"]) for r in results)
    lines = [title]
    for cause in views["causes"]:
        lines += cause["text"].splitlines()
    if any(not views[r["name"]]["group"] for r in results):
        lines.append(f"{'test':<{width}}  {'points':>9}  result")
    for r in results:
        view = views[r["name"]]
        if view["group"]:
            continue
        lines.append(f"{r['name']:<{width}}  {r['score']:>4g} / {r['points']:<2g}  {status_word(r)}")
        if r["passed"]:
            continue
        if view["cause"]:
            step = f", in step {view['step']}" if view.get("step") else ""
            own = view["message"] if view["cause"]["kind"] == "non-finite state" else ""
            if own and own in view["cause"]["text"]:
                own = ""
            lines.append(f"{'':<{width}}    | stopped on the same {view['cause']['kind']} (above){step}"
                         + (f": {own[len(running.STOPPED_EARLY):].strip()}" if own else ""))
            continue
        if view["hint"]:
            lines.append(f"{'':<{width}}    hint: {r['hint']}")
        for line in view["message"].splitlines()[:6]:
            lines.append(f"{'':<{width}}    | {line}")
    for key, rs in views["groups"]:
        lines.append(_group_line(key, rs))
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    lines.append(f"total: {total:g} / {maximum:g} points")
    lines.append(count_line(results))
    return "\n".join(lines)


def test_message(r, view):
    """The message of one test where each test is shown alone (Gradescope, JUnit)."""
    if r["passed"]:
        return "passed"
    if view.get("short") and not (view["cause"] and view["cause"]["first"] == r["name"]):
        return view["short"]
    message = view["message"]
    if view["cause"]:
        message = f"{message}\n({view['cause']['text'].splitlines()[-1].strip()})" if view["cause"]["kind"] == "failed assertion" else message
    return f"{message}\nhint: {r['hint']}".strip() if view["hint"] else message


def gradescope(results, seconds, hidden_visibility="after_published", notes=""):
    views = analyse(results)
    tests = []
    for r in results:
        tests.append({"name": r["name"], "score": r["score"], "max_score": r["points"],
                      "status": "passed" if r["passed"] else "failed", "output": test_message(r, views[r["name"]]),
                      "visibility": hidden_visibility if r.get("hidden") else "visible"})
    # The grader's own printout repeats hidden tests' names and messages: students never see it.
    stdout = "hidden" if any(r.get("hidden") for r in results) else "visible"
    data = {"score": sum(r["score"] for r in results), "max_score": sum(r["points"] for r in results),
            "execution_time": round(seconds, 3), "visibility": "visible", "stdout_visibility": stdout,
            "tests": tests}
    said = "\n".join(n for n in ([c["text"] for c in views["causes"]] + [notes]) if n)
    if said:
        data["output"] = said
    return data


_NOT_XML = re.compile("[^\u0009\u000a\u000d\u0020-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _xml_text(text):
    """Text that XML 1.0 can hold: what an engine printed may hold control characters."""
    return _NOT_XML.sub("\ufffd", text)


def junit(results, label):
    views = analyse(results)
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
                view = views[r["name"]]
                text = test_message(r, view)
                failure = ET.SubElement(case, "failure",
                                        message=_xml_text(r["hint"] if view["hint"] else text.splitlines()[0]))
                failure.text = _xml_text(text)
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
