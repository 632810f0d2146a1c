#!/usr/bin/env python3
"""The grader: for each graded test, the trusted checker (gpl-checker: the graded tests, no student
code) asks the engine of the code graded (gpl-hooks-VARIANT, in the sandbox) for every hook over
two pipes; the checker's report decides. Points, hints, Gradescope results.json and JUnit XML.

  grade.py grade --build-dir DIR [--worksheet N] [--solutions | --submission SUBDIR]
                 [--json FILE] [--junit FILE] [--timeout S] [--memory MIB] [--hidden-visibility V]
      grades the student's assignments/ (or the reference, or a submission folder): the hook files
      compiled in the sandbox, the checker and the engine's server from the lab's build.
  grade.py grade --build-dir DIR --batch DIR --out FILE.csv [--jobs N] [--worksheet N] [--timeout S]
                [--memory MIB] [--similarity]
      grades every submission folder in DIR, in parallel, and writes a gradebook (one row per
      submission, one column per test, the total) and FILE-results/NAME/results.json for each.
  grade.py report --checker CHECKER --hooks ENGINE [--worksheet N] [--json FILE] [--junit FILE]
      grades an engine that is already built.
  grade.py prebuild --build-dir DIR
      builds the checker, the launcher, what a submission's engine links and the stubs' objects
      (Gradescope's setup.sh).
  grade.py failure --json FILE --message TEXT
      writes a results.json with zero points that says why the grading could not run.
  grade.py selfcheck --checker CHECKER --hooks ENGINE (--expect full | --expect zero | --mutant NAME)
                     [--worksheet N | --from-worksheet N] [--about TEXT] [--leave-out NAME,...]
      the grader's own checks: the solutions (and the correct alternatives, tests/alternatives/*.json)
      score full marks, the stubs zero, and each seeded mistake (tests/mutants/*.json) loses points in
      the test named for it, which fails on its own (graded on that test's worksheet unless
      --worksheet says otherwise). --from-worksheet N grades worksheet N and every later one: the
      tests that can call a hook of worksheet N. --about TEXT is printed above the table (what the
      engine graded is). --leave-out NAME,... runs every test but those (with --expect).

Exit status: 0 full marks, 1 points lost, 2 the grading itself could not run (a one-line error).

Each test runs in its own pair of processes, with a time limit (its own, declared with the test,
or --timeout) and an output cap: a crash, a timeout or endless output costs that test only. The
test list, points and limits come from the checker, never from the code graded. A test whose
prerequisite fails is "not run". One test per core runs at once (a batch: one submission per core,
each one test at a time). A submission contributes only its hook files.
"""
import argparse
import concurrent.futures
import copy
import json
import os
import pathlib
import shutil
import subprocess
import sys
import time
import traceback

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import hooks  # noqa: E402
from hooks import OneLineParser  # noqa: E402
import similarity  # noqa: E402
from grading import GradeError  # noqa: E402
from grading.building import (Submission, TrustedBuild, build_submissions, build_trusted, cmake_build,  # noqa: E402
                              first_errors, grade_submission, reference_tests, stage_submissions)
from grading.cgroups import Cgroups  # noqa: E402
from grading.guard import Guard  # noqa: E402
from grading.reports import (Progress, check_writable, gradebook, gradescope, report, table,  # noqa: E402
                             write_atomically)
from grading.sandbox import (BUDGET, DEFAULT_MEMORY_MIB, Sandbox, default_limits,  # noqa: E402
                             usable_cores)
from grading.running import (DEFAULT_TIMEOUT, SANITIZER_MARK, Programs, failed_results,  # noqa: E402
                             grade_binary, run_one, select, test_limits, with_prerequisites)

# How many of one engine's tests are graded at once, each in its own sandbox: one per usable core. A
# batch grades its submissions at once instead, each one test at a time.
TESTS_AT_ONCE = usable_cores()


class GradeParser(OneLineParser):
    """Command-line errors as one line that points at the lab's own help (./lab grade --help)."""

    def error(self, message):
        print(f"error: {message} (./lab grade --help for help)", file=sys.stderr)
        sys.exit(2)


# ---- Commands -------------------------------------------------------------------------------------

def unless_sandboxed(make_guard):
    """The write guard, needed only where tests run without the sandbox (which hides the lab)."""
    return None if Sandbox.here().isolated else make_guard()


def submission_build_dir(build_dir):
    return build_dir.parent / (build_dir.name + "-submission")


def cmd_grade(args):
    if args.batch:
        return cmd_batch(args)
    if args.similarity:
        raise GradeError("--similarity goes with --batch")
    if args.out:
        raise GradeError("--out goes with --batch")
    check_writable(args.json)
    check_writable(args.junit)
    build_dir = pathlib.Path(args.build_dir).resolve()
    start = time.monotonic()
    guard = unless_sandboxed(lambda: Guard(ROOT, build_dir / "quarantine", skip=[p for p in (args.json, args.junit) if p]))
    if args.solutions:
        if not (ROOT / "solutions").is_dir():
            raise GradeError("this is a student release: it has no solutions to grade")
        ok, log = cmake_build(build_dir, ["gpl-checker", "gpl-launch", "gpl-hooks-solutions"])
        if not ok:
            raise GradeError("the reference solutions do not build: " + first_errors(log, 1))
        programs = Programs(build_dir / "tests" / "gpl-checker", build_dir / "tests" / "gpl-hooks-solutions")
        results = grade_binary(programs, args.worksheet, args.defaults, guard, jobs=TESTS_AT_ONCE)
        return report(results, "solutions", args, time.monotonic() - start)
    # The student's assignments/ and a submission folder are graded alike: their hook files compiled
    # in the sandbox, the checker and the engine's server from the lab's own build.
    build_trusted(build_dir)
    folder = args.submission or ROOT / "assignments"
    label = f"submission {args.submission}" if args.submission else "assignments"
    sub_build = submission_build_dir(build_dir)
    sub = Submission(pathlib.Path(folder).name, folder)
    stage_submissions([sub], sub_build)
    if sub.error:
        raise GradeError(sub.error)
    if sub.notes() and args.submission:
        print(sub.notes())
    build_submissions([sub], sub_build, None, TrustedBuild(build_dir))
    checker = build_dir / "tests" / "gpl-checker"
    if sub.build_errors is not None:
        print("the code does not compile; every test scores zero. First errors:\n" + sub.build_errors)
    grade_submission(sub, args, checker, guard, lambda: reference_tests(checker, args.worksheet), TESTS_AT_ONCE)
    return report(sub.results, label, args, time.monotonic() - start, sub.notes() if args.submission else "",
                  root=None if args.submission else ROOT)


def cmd_batch(args):
    if args.submission or args.solutions or args.json or args.junit:
        raise GradeError("--batch grades folders of submissions: use --out FILE.csv, not --submission, "
                         "--solutions, --json or --junit")
    if not args.out:
        raise GradeError("--batch needs --out FILE.csv (the gradebook)")
    if args.similarity and shutil.which(similarity.SIM) is None:
        raise GradeError("--similarity needs sim_c from the Debian package similarity-tester "
                         "(./lab installs it; or: apt-get install similarity-tester)")
    batch = pathlib.Path(args.batch)
    if not batch.is_dir():
        raise GradeError(f"batch folder not found: {batch}")
    out = pathlib.Path(args.out)
    check_writable(out)
    results_dir = out.parent / (out.stem + "-results")
    if results_dir.exists() and not results_dir.is_dir():
        raise GradeError(f"cannot write the results folder {results_dir}: a file of that name exists")
    folders = sorted(p for p in batch.iterdir() if p.is_dir() and not p.name.startswith("."))
    skipped = sorted(p.name for p in batch.iterdir() if not p.is_dir())
    if not folders:
        raise GradeError(f"batch folder {batch} holds no submission folders")
    if skipped:
        print(f"not submission folders, skipped: {', '.join(skipped)}", file=sys.stderr)
    jobs = args.jobs or usable_cores()
    fits = BUDGET.slots(args.memory)
    if fits is not None and jobs > fits:
        print(f"{jobs} jobs would need more memory than the machine has available: {fits} at once "
              f"(each test may use {args.memory:g} MiB)", file=sys.stderr)
        jobs = fits
    build_dir = pathlib.Path(args.build_dir).resolve()
    sub_build = submission_build_dir(build_dir)
    start = time.monotonic()
    build_trusted(build_dir)
    checker = build_dir / "tests" / "gpl-checker"
    tests = reference_tests(checker, args.worksheet)  # the list of every submission: the checker's

    subs = [Submission(p.name, p) for p in folders]
    stage_submissions(subs, sub_build)
    distinct = len({s.variant for s in subs if s.variant})
    print(f"grading {len(subs)} submissions ({distinct} distinct) with {jobs} jobs", file=sys.stderr)
    print(Sandbox.here().describe(), file=sys.stderr)
    if Cgroups.here().describe():
        print(Cgroups.here().describe(), file=sys.stderr)
    # Compiling uses every core whatever --jobs says.
    build_submissions(subs, sub_build, os.cpu_count(), TrustedBuild(build_dir))

    def reference():
        return tests
    guard = unless_sandboxed(lambda: Guard(ROOT, build_dir / "quarantine", skip=[out, results_dir, batch]))
    results_dir.mkdir(exist_ok=True)
    progress = Progress(len(subs))

    # Identical submissions (the same hook files, so the same variant) share one build and one run:
    # the first of them is graded, the others get its results. (Compile errors name each student's
    # own folder, so those are written for each.)
    graded = {}
    for sub in subs:
        if sub.variant and not sub.error and sub.build_errors is None:
            graded.setdefault(sub.variant, sub)
    twins = [s for s in subs if s.variant in graded and graded[s.variant] is not s and s.build_errors is None]

    def write(sub):
        (results_dir / sub.name).mkdir(exist_ok=True)
        write_atomically(results_dir / sub.name / "results.json",
                         json.dumps(gradescope(sub.results, sub.seconds, args.hidden_visibility,
                                               "\n".join(n for n in (sub.notes(), Sandbox.here().describe(),
                                                                      Cgroups.here().describe()) if n)),
                                    indent=2) + "\n")
        progress.finished(sub)

    def work(sub):
        progress.started()
        try:
            grade_submission(sub, args, checker, guard, reference)
        except GradeError as e:  # whatever goes wrong with one submission, the others are graded
            sub.results = failed_results(tests, f"could not be graded: {e}")
        except Exception as e:  # a fault of the grader's own: the others are graded all the same
            traceback.print_exc()
            sub.results = failed_results(tests, f"could not be graded: an error in the grader ({type(e).__name__}: "
                                                f"{e}); grade this submission again, and report the error")
        write(sub)

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(work, [s for s in subs if s not in twins]))
    for sub in twins:
        progress.started()
        sub.results, sub.seconds = copy.deepcopy(graded[sub.variant].results), graded[sub.variant].seconds
        write(sub)
    progress.end()
    write_atomically(out, gradebook(subs))
    if args.similarity:
        staged = {s.name: sub_build / "submissions" / s.variant for s in subs if s.variant}
        try:
            rows = similarity.compare(staged, hooks.hook_files(), ROOT / "assignments")
        except similarity.SimilarityError as e:
            raise GradeError(str(e)) from None
        similarity.write_csv(rows, out.parent / (out.stem + "-similarity.csv"))
        print(similarity.summary(rows))
    full = sum(all(r["passed"] for r in s.results) for s in subs)
    print(f"graded {len(subs)} submissions in {time.monotonic() - start:.1f} s: {full} with full marks; "
          f"wrote {out} and {results_dir}/NAME/results.json")
    return 0 if full == len(subs) else 1


def cmd_prebuild(args):
    """Builds what grading a submission needs besides the submission: the checker, the launcher, the
    engine's server and libraries, the hook files' precompiled header and the stubs' objects."""
    build_dir = pathlib.Path(args.build_dir).resolve()
    if not (build_dir / "CMakeCache.txt").is_file():
        # What grading needs only: the engine, the checker, the launcher (no viewer, studies or
        # seeded mistakes), with the compile commands the submissions' hook files are compiled by.
        proc = subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-G", "Ninja",
                               "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                               "-DGPL_CORE_TESTS_ONLY=ON", "-DGPL_BUILD_VIEWER=OFF"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0:
            raise GradeError("could not configure the build: " + first_errors(proc.stdout, 3))
    build_trusted(build_dir)
    # The stubs' engine, and so their hook objects: a submission's files left as handed out compile
    # nothing (the bundle's assignments/ are the stubs, never a student's code).
    ok, log = cmake_build(build_dir, ["gpl-hooks-assignments"])
    if not ok:
        raise GradeError("the stubs do not build: " + first_errors(log, 1))
    TrustedBuild(build_dir)  # the flags and the link command are readable
    (submission_build_dir(build_dir) / "submissions").mkdir(parents=True, exist_ok=True)
    print(f"built the checker, the launcher and the engine's parts in {build_dir}")
    return 0


def cmd_failure(args):
    """A results.json that says why the grading could not run (Gradescope shows it to the student)."""
    data = {"score": 0, "output": "The submission could not be graded: " + args.message.strip(),
            "visibility": "visible", "stdout_visibility": "visible", "tests": []}
    write_atomically(args.json, json.dumps(data, indent=2) + "\n")
    return 0


def cmd_report(args):
    check_writable(args.json)
    check_writable(args.junit)
    start = time.monotonic()
    results = grade_binary(Programs(args.checker, args.hooks), args.worksheet, args.defaults, jobs=TESTS_AT_ONCE)
    return report(results, pathlib.Path(args.hooks).name, args, time.monotonic() - start)


def cmd_selfcheck(args):
    programs = Programs(args.checker, args.hooks)
    tests = programs.manifest()  # read once: each reading runs the checker
    spec = None
    if args.mutant:
        specs = {m["name"]: m for m in hooks.load_mutants()}
        if args.mutant not in specs:
            raise GradeError(f"unknown seeded mistake '{args.mutant}'; known: {', '.join(sorted(specs))}")
        spec = specs[args.mutant]
        named = next((t for t in tests if t["name"] == spec["must_fail"]), None)
        if named is None:
            raise GradeError(f"seeded mistake '{args.mutant}' names the test {spec['must_fail']}, which does not exist")
        if args.worksheet is None:
            args.worksheet = named["worksheet"]  # the other worksheets' tests would only take time
    # A seeded mistake is graded on its named test and that test's prerequisites in the worksheet:
    # what decides whether the named test loses its points; the others would only take time.
    only = None
    if spec is not None:
        only = with_prerequisites(select(tests, args.worksheet), spec["must_fail"])
    elif args.from_worksheet is not None:
        only = {t["name"] for t in tests if t["worksheet"] >= args.from_worksheet}
        if not only:
            raise GradeError(f"no graded tests for worksheet {args.from_worksheet} or later; the worksheets with "
                             "graded tests: " + ", ".join(map(str, sorted({t["worksheet"] for t in tests}))))
    if args.leave_out:
        if spec is not None:
            raise GradeError("--leave-out goes with --expect, not with --mutant")
        known = {t["name"] for t in tests}
        unknown = [n for n in args.leave_out if n not in known]
        if unknown:
            raise GradeError(f"--leave-out: no graded test is named {', '.join(unknown)}")
        only = (only if only is not None else known) - set(args.leave_out)
    results = grade_binary(programs, args.worksheet, args.defaults, only=only, tests=tests, jobs=TESTS_AT_ONCE)
    total = sum(r["score"] for r in results)
    maximum = sum(r["points"] for r in results)
    failed = [r["name"] for r in results if not r["passed"]]
    flagged = [r["name"] for r in results if r["output"].startswith(SANITIZER_MARK)]
    if args.about:
        print(args.about)
    print(table(results, f"self-check of {pathlib.Path(args.hooks).name}"))
    if flagged and args.expect in ("full", "zero"):
        print(f"WRONG: a sanitizer reported an error in {', '.join(flagged)}")
        return 1
    if args.expect == "full":
        ok = total == maximum and not failed
        print("OK: full marks" if ok else f"WRONG: {pathlib.Path(args.hooks).name} loses points in {', '.join(failed)}")
    elif args.expect == "zero":
        ok = total == 0
        passed = [r["name"] for r in results if r["passed"]]
        print("OK: the untouched stubs score zero" if ok else
              f"WRONG: the untouched stubs earn points in {', '.join(passed)}: those tests cannot fail")
    else:
        named = next((r for r in results if r["name"] == spec["must_fail"]), None)
        if named is None:
            raise GradeError(f"--worksheet {args.worksheet} leaves out {spec['must_fail']}, the test named for "
                             f"seeded mistake '{args.mutant}'")
        # The named test must lose its points in the graded run (failed or not run) AND fail when run
        # on its own: a prerequisite catching the mistake must not hide a test that cannot.
        if named.get("not_run"):
            alone, _, _ = run_one(programs, spec["must_fail"], test_limits(programs, named, args.defaults))
        else:
            alone = named["passed"]  # it ran on its own already, in its own process
        ok = not named["passed"] and named["score"] == 0 and total < maximum and not alone
        if ok:
            print(f"OK: '{spec['mistake']}' is caught by {spec['must_fail']}"
                  + (" (which is not run in grading: a prerequisite catches it first)" if named.get("not_run") else ""))
        elif named["passed"] or named["score"]:
            print(f"WRONG: '{spec['mistake']}' is not caught by {spec['must_fail']}")
        else:
            print(f"WRONG: '{spec['mistake']}' loses {spec['must_fail']} only through a prerequisite; "
                  "run on its own the test passes, so it cannot catch the mistake")
    return 0 if ok else 1


def main(argv):
    # File and folder names that are not UTF-8 are printed, not fatal.
    for stream in (sys.stdout, sys.stderr):
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="replace")
    parser = GradeParser(prog="grade.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=GradeParser)

    def common(p):
        p.add_argument("--worksheet", type=int, help="grade only this worksheet's tests")
        p.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                       help=f"seconds per test unless the test declares its own (default {DEFAULT_TIMEOUT:g})")
        p.add_argument("--memory", type=float, default=DEFAULT_MEMORY_MIB, metavar="MIB",
                       help=f"MiB of resident memory per test unless the test declares its own "
                            f"(default {DEFAULT_MEMORY_MIB:g})")
        p.add_argument("--hidden-visibility", choices=("hidden", "after_published"), default="after_published",
                       help="Gradescope visibility of hidden tests (default after_published)")

    g = sub.add_parser("grade")
    common(g)
    g.add_argument("--build-dir", required=True)
    which = g.add_mutually_exclusive_group()
    which.add_argument("--solutions", action="store_true", help="grade the reference solutions")
    which.add_argument("--submission", metavar="DIR", help="grade a folder laid out like assignments/")
    which.add_argument("--batch", metavar="DIR", help="grade every submission folder in DIR")
    g.add_argument("--out", metavar="FILE.csv", help="the gradebook of --batch")
    g.add_argument("--jobs", type=int, help="submissions graded at once with --batch (default: one per core)")
    g.add_argument("--similarity", action="store_true",
                   help="with --batch: also compare the hook files across the batch (stub text left out) "
                        "and write FILE-similarity.csv")
    g.add_argument("--json", metavar="FILE", help="write Gradescope results.json")
    g.add_argument("--junit", metavar="FILE", help="write JUnit XML")

    r = sub.add_parser("report")
    common(r)
    r.add_argument("--checker", required=True, help="the trusted checker (gpl-checker)")
    r.add_argument("--hooks", required=True, help="the engine graded (gpl-hooks-VARIANT)")
    r.add_argument("--json", metavar="FILE")
    r.add_argument("--junit", metavar="FILE")

    s = sub.add_parser("selfcheck")
    common(s)
    s.add_argument("--checker", required=True, help="the trusted checker (gpl-checker)")
    s.add_argument("--hooks", required=True, help="the engine graded (gpl-hooks-VARIANT)")
    exp = s.add_mutually_exclusive_group(required=True)
    exp.add_argument("--expect", choices=["full", "zero"])
    exp.add_argument("--mutant", metavar="NAME")
    s.add_argument("--from-worksheet", type=int, metavar="N",
                   help="with --expect: grade worksheet N and every later one (the tests that can call its hooks)")
    s.add_argument("--about", default="", metavar="TEXT", help="printed above the table: what the engine graded is")
    s.add_argument("--leave-out", type=lambda v: [n for n in v.split(",") if n], default=[], metavar="NAME,...",
                   help="with --expect: graded tests not run (the sanitizer presets leave out the longest fluid "
                        "runs, whose physics the release preset grades)")

    b = sub.add_parser("prebuild")
    b.add_argument("--build-dir", required=True)

    f = sub.add_parser("failure")
    f.add_argument("--json", metavar="FILE", required=True)
    f.add_argument("--message", required=True)

    args = parser.parse_args(argv)
    if getattr(args, "timeout", 1) <= 0:
        parser.error("--timeout must be a positive number of seconds")
    if getattr(args, "memory", 1) <= 0:
        parser.error("--memory must be a positive number of MiB")
    if hasattr(args, "timeout"):
        args.defaults = default_limits(args.timeout, args.memory)
    if getattr(args, "jobs", None) is not None and args.jobs < 1:
        parser.error("--jobs must be at least 1")
    if getattr(args, "from_worksheet", None) is not None and (args.worksheet is not None or args.mutant):
        parser.error("--from-worksheet goes with --expect, not with --worksheet or --mutant")
    try:
        return {"grade": cmd_grade, "report": cmd_report, "selfcheck": cmd_selfcheck, "prebuild": cmd_prebuild,
                "failure": cmd_failure}[args.command](args)
    except (GradeError, hooks.HookError) as e:
        print("error: " + "; ".join(line.strip() for line in str(e).splitlines() if line.strip()), file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
