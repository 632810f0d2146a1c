"""Building what is graded: the variants of the autograder, submissions staged and compiled."""
import hashlib
import pathlib
import shutil
import subprocess
import tempfile
import time

import hooks
from grading import GradeError
from grading.running import failed_results, grade_binary, manifest, select

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


def cmake_build(build_dir, targets, jobs=None, keep_going=False):
    cmd = ["cmake", "--build", str(build_dir)]
    for t in targets:
        cmd += ["--target", t]
    if jobs:
        cmd += ["-j", str(jobs)]
    if keep_going:
        cmd += ["--", "-k", "0"]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return proc.returncode == 0, proc.stdout


def first_errors(log, limit=20):
    lines = [l for l in log.splitlines() if "error" in l.lower() or l.startswith(" ")]
    picked = [l for l in lines if "error:" in l][:limit] or lines[:limit]
    return "\n".join(picked)


def prepare_submission(source, hooks_dir):
    """Copies the hook files of a submission into hooks_dir. Files the submission lacks are taken
    from the untouched stubs; everything else in it is ignored. Returns (missing, ignored)."""
    folder = source = pathlib.Path(source)
    if not source.is_dir():
        raise GradeError(f"submission folder not found: {source}")
    names = hooks.hook_files()
    present = [n for n in names if (source / n).is_file()]
    if not present and any((source / "assignments" / n).is_file() for n in names):
        source = source / "assignments"  # a whole copy of the lab: its assignments/ is the submission
        present = [n for n in names if (source / n).is_file()]
    if not present:
        raise GradeError(f"submission folder {source} holds none of the hook files ({', '.join(names)})")
    hooks_dir.mkdir(parents=True, exist_ok=True)
    missing = []
    for n in names:
        src = source / n if (source / n).is_file() else ROOT / "assignments" / n
        if src.parent != source:
            missing.append(n)
        text = src.read_bytes()
        dst = hooks_dir / n
        if not dst.exists() or dst.read_bytes() != text:
            dst.write_bytes(text)  # a fresh modification time, so the build sees the change
    taken = {source / n for n in names}
    ignored = sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() and p not in taken)
    return missing, ignored


class Submission:
    """One submission folder: its hook files, the variant that builds them and its results."""

    def __init__(self, name, folder):
        self.name, self.folder = name, pathlib.Path(folder)
        self.error = None            # why it cannot be graded at all (no hook files, ...)
        self.build_errors = None     # the compiler's first errors
        self.missing, self.ignored = [], []
        self.variant = None
        self.results = None
        self.seconds = 0.0

    def notes(self):
        """What the student should know besides the tests: files not graded."""
        lines = []
        if self.missing:
            lines.append(f"not in the submission, graded as the untouched stub: {', '.join(self.missing)}")
        if self.ignored:
            lines.append(f"ignored (only hook files are graded): {', '.join(self.ignored[:20])}"
                         + (f" and {len(self.ignored) - 20} more" if len(self.ignored) > 20 else ""))
        return "\n".join(lines)


def stage_submissions(subs, sub_build):
    """Puts the hook files of each submission into SUB_BUILD/submissions/HASH (identical submissions
    share a folder, and so one build). Sets sub.variant; sub.error for folders without hook files."""
    root = sub_build / "submissions"
    root.mkdir(parents=True, exist_ok=True)
    for sub in subs:
        with tempfile.TemporaryDirectory(dir=sub_build) as tmp:
            try:
                sub.missing, sub.ignored = prepare_submission(sub.folder, pathlib.Path(tmp))
            except (GradeError, OSError) as e:
                sub.error = str(e)
                continue
            digest = hashlib.sha256()
            for n in hooks.hook_files():
                digest.update(n.encode() + b"\0" + (pathlib.Path(tmp) / n).read_bytes() + b"\0")
            sub.variant = digest.hexdigest()[:16]
            target = root / sub.variant
            if not target.exists():
                shutil.copytree(tmp, target)


# The submission build makes autograders only (the engine, the variants' hook files, the graded tests):
# without the viewer, the studies and the seeded mistakes (the options of the asan-core preset) its
# configure, which runs again for every new submission folder, takes a third of the time.
SUBMISSION_BUILD_OPTIONS = {"GPL_CORE_TESTS_ONLY:BOOL": "ON", "GPL_BUILD_VIEWER:BOOL": "OFF"}


def configure_submission_build(sub_build):
    cache = sub_build / "CMakeCache.txt"
    options = {"GPL_SUBMISSIONS_DIR:PATH": str(sub_build / "submissions"), **SUBMISSION_BUILD_OPTIONS}
    if cache.exists():
        text = cache.read_text(errors="replace").splitlines()
        if all(f"{name}={value}" in text for name, value in options.items()):
            return
    proc = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(sub_build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                           *(f"-D{name}={value}" for name, value in options.items())],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        raise GradeError("could not configure the submission build: " + first_errors(proc.stdout, 3))


def build_submissions(subs, sub_build, jobs):
    """Builds the autograder of every distinct variant in one build (the engine once, each variant's
    hook files once); a variant that does not compile gets its own first errors."""
    variants = sorted({s.variant for s in subs if s.variant})
    if not variants:
        return
    configure_submission_build(sub_build)
    targets = [f"autograder_submission_{v}" for v in variants]
    ok, _ = cmake_build(sub_build, targets, jobs, keep_going=True)
    errors = {}
    if not ok:
        for v, target in zip(variants, targets):
            ok_one, log = cmake_build(sub_build, [target])
            if not ok_one:
                errors[v] = log
        if not errors:
            raise GradeError("the submission build fails for a reason outside the submissions; see "
                             f"cmake --build {sub_build}")
    for s in subs:
        if s.variant in errors:
            # The compiler names the file as ccache passed it: relative to the build folder when
            # the build is inside the lab (ccache's base_dir), else with its whole path.
            log = errors[s.variant].replace(str(sub_build / "submissions" / s.variant), str(s.folder))
            log = log.replace(f"submissions/{s.variant}/", f"{s.folder}/")
            s.build_errors = first_errors(log) or log.strip()[-2000:]


def reference_tests(build_dir, worksheet, avoid):
    """The graded tests as a variant that builds lists them (the list is the same in every variant):
    used when the code being graded does not compile."""
    candidates = [v for v in ("solutions", "assignments") if v != avoid]
    if not (ROOT / "solutions").is_dir() and "solutions" in candidates:
        candidates.remove("solutions")
    for v in candidates:
        ok, _ = cmake_build(build_dir, [f"autograder_{v}"])
        if ok:
            return select(manifest(build_dir / "tests" / f"autograder_{v}"), worksheet)
    raise GradeError("no variant of the autograder builds, so the tests cannot be listed")


def grade_submission(sub, args, sub_build, guard, reference):
    start = time.monotonic()
    if sub.error:
        sub.results = failed_results(reference(), sub.error)
    elif sub.build_errors is not None:
        sub.results = failed_results(reference(), "the submission does not compile:\n" + sub.build_errors)
    else:
        binary = sub_build / "tests" / f"autograder_submission_{sub.variant}"
        sub.results = grade_binary(binary, args.worksheet, args.defaults, guard)
    sub.seconds = time.monotonic() - start
    return sub
