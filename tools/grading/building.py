"""Building what is graded. The trusted parts (the checker, the launcher, the engine's server and
libraries, the precompiled header) come from the lab's own build with CMake; a submission's hook
files never go through CMake: each is compiled in the sandbox by the compiler, with the flags, the
trusted build uses for hook files, seeing only the system's /usr, the framework's headers, the
precompiled header and the staged hook files; then the engine gpl-hooks-HASH is linked, in the
sandbox too, from the trusted server and libraries and those objects. Objects are cached by the
hash of their source and flags, so a hook file left as handed out (or a twin's) compiles once."""
import concurrent.futures
import hashlib
import json
import os
import pathlib
import re
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
import time

import hooks
from grading import GradeError
from grading.cgroups import Cgroups
from grading.running import Programs, checker_manifest, failed_results, grade_binary, run_limited, select
from grading.sandbox import Limits, Sandbox

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
# What the trusted build makes for grading (besides each variant's gpl-hooks-VARIANT).
TRUSTED_TARGETS = ["gpl-checker", "gpl-launch", "gpl_hooks_server_main", "gpl_grading_protocol", "gpl_framework",
                   "gpl_hook_pch"]
# A hook file compiles in a few seconds; the compiler is stopped at these, several times what the
# longest needs on a busy machine. A compile stopped at a limit is tried again at the next grading
# (the load of the moment may have stopped it).
COMPILE_LIMITS = Limits(seconds=30, memory_mib=2048, threads=16, file_mib=256)
LINK_LIMITS = Limits(seconds=120, memory_mib=2048, threads=16, file_mib=512)
# Inside the sandbox: the framework's headers, the precompiled header, the hook files, the objects.
INCLUDE, PCH, SOURCES, OBJECTS, OUT, LINK = "/gpl/include", "/gpl/pch", "/gpl/src", "/gpl/obj", "/gpl/out", "/gpl/link"


def cmake_build(build_dir, targets, jobs=None, keep_going=False):
    """Builds the targets; (whether it built, the build's output). On a terminal one line shows the
    build's steps as ninja finishes them, "grade: building [#####.....] done/total", erased at the
    end, as ./lab's builds show theirs; elsewhere nothing is printed."""
    cmd = ["cmake", "--build", str(build_dir)]
    for t in targets:
        cmd += ["--target", t]
    if jobs:
        cmd += ["-j", str(jobs)]
    if keep_going:
        cmd += ["--", "-k", "0"]
    if not sys.stdout.isatty():
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        return proc.returncode == 0, proc.stdout
    lines, shown, label = [], False, "grade: building"
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          env={**os.environ, "NINJA_STATUS": "[%f/%t] "}) as proc:
        for line in proc.stdout:
            lines.append(line)
            step = re.match(r"\[(\d+)/(\d+)\] ", line)
            if step:
                done, total = int(step[1]), int(step[2])
                counts = f"{done}/{total}"
                # A bar up to 40 wide, narrower where the terminal is, left out where it would be under 10.
                width = min(40, shutil.get_terminal_size().columns - len(label) - len(counts) - 5)
                bar = f"[{'#' * (width * done // total)}{'.' * (width - width * done // total)}] " if width >= 10 else ""
                print(f"\r{label} {bar}{counts}\x1b[K", end="", flush=True)
                shown = True
    if shown:
        print("\r\x1b[K", end="", flush=True)
    return proc.returncode == 0, "".join(lines)


def first_errors(log, limit=20):
    lines = [l for l in log.splitlines() if "error" in l.lower() or l.startswith(" ")]
    picked = [l for l in lines if "error:" in l][:limit] or lines[:limit]
    return "\n".join(picked)


def build_trusted(build_dir):
    """Builds the trusted parts of grading in build_dir (CMake); a GradeError when they do not build."""
    ok, log = cmake_build(build_dir, TRUSTED_TARGETS)
    if not ok:
        raise GradeError("the lab's grader does not build: " + first_errors(log, 3))


def _program_in_usr(program):
    """The path of the compiler by which the sandbox, which shows /usr alone, finds it: its links are
    followed out of the rest of the system (/usr/bin/c++ leads through /etc/alternatives), but not
    further inside /usr, where a name can matter: /usr/bin/clang++ leads to clang, which links as C."""
    chain = [os.path.abspath(shutil.which(program) or program)]
    while os.path.islink(chain[-1]) and len(chain) < 40:
        chain.append(os.path.normpath(os.path.join(os.path.dirname(chain[-1]), os.readlink(chain[-1]))))
    first = len(chain) - 1
    while first > 0 and all(p.startswith("/usr/") for p in chain[first - 1:]):
        first -= 1
    return chain[first]


class TrustedBuild:
    """How the lab's own build compiles a hook file and links an engine, read from its
    compile_commands.json and build.ninja (the flags of every preset, sanitizers included)."""

    def __init__(self, build_dir):
        self.dir = pathlib.Path(build_dir).resolve()
        self.tests = self.dir / "tests"
        commands = self.dir / "compile_commands.json"
        if not commands.is_file():
            raise GradeError(f"{commands} is missing: configure the build with CMAKE_EXPORT_COMPILE_COMMANDS=ON")
        entry = next((c for c in json.loads(commands.read_text())
                      if "gpl_hookfile_assignments_" in c.get("command", "") + c.get("output", "")
                      and c.get("file", "").endswith(".cpp")), None)
        if entry is None:
            raise GradeError(f"{commands} has no compile command of a hook file")
        self.compiler, self.flags, self.pch = self._compile_flags(shlex.split(entry["command"]))
        self.link = self._link_command()

    def _compile_flags(self, argv):
        self.include_dir = ROOT / "framework" / "include"
        compiler = _program_in_usr(argv[0])
        flags, pch, clang_pch = [], None, False
        i = 1
        while i < len(argv):
            a = argv[i]
            if a in ("-o", "-c", "-MF", "-MT", "-MQ"):
                i += 2
                continue
            if a in ("-MD", "-MMD"):
                i += 1
                continue
            if a == "-include" and argv[i + 1].endswith("cmake_pch.hxx"):
                pch = pathlib.Path(argv[i + 1]).parent
                flags += ["-include", f"{PCH}/cmake_pch.hxx"]
                i += 2
                continue
            if a == "-Xclang" and argv[i + 1] in ("-include-pch", "-include") and \
                    argv[i + 3].endswith(("cmake_pch.hxx.pch", "cmake_pch.hxx")):
                # Clang's precompiled header (-Xclang -include-pch -Xclang X.pch -Xclang -include
                # -Xclang X) finds the files it was made from by their paths in the build, which the
                # sandbox does not show: with Clang, a hook file is compiled without it.
                clang_pch = True
                i += 4
                continue
            if a.startswith("-I"):
                path = a[2:] or argv[i + 1]
                step = 1 if a[2:] else 2
                if pathlib.Path(path).resolve() == (ROOT / "framework" / "include").resolve() or \
                        pathlib.Path(path).parts[-2:] == ("framework", "include"):
                    self.include_dir = pathlib.Path(path).resolve()
                    flags.append(f"-I{INCLUDE}")
                elif not str(pathlib.Path(path).resolve()).startswith(str(ROOT)):
                    flags += [a] if step == 1 else [a, argv[i + 1]]
                i += step
                continue
            flags.append(a)
            i += 1
        if pch is not None and not (pch / "cmake_pch.hxx.gch").is_file():
            flags = [f for f in flags if f not in ("-include", f"{PCH}/cmake_pch.hxx", "-Winvalid-pch")]
            pch = None
        if clang_pch:
            flags = [f for f in flags if f != "-Winvalid-pch"]
        return compiler, flags + ["-fdiagnostics-color=never"], pch

    def _link_command(self):
        proc = subprocess.run(["ninja", "-C", str(self.dir), "-t", "commands", "gpl-hooks-assignments"],
                              capture_output=True, text=True)
        lines = proc.stdout.strip().splitlines()
        if proc.returncode != 0 or not lines:
            raise GradeError(f"cannot read how {self.dir} links an engine (ninja -t commands gpl-hooks-assignments)")
        line = lines[-1]
        line = re.sub(r"^:\s*&&\s*", "", line)
        line = re.sub(r"\s*&&\s*:\s*$", "", line)
        argv = shlex.split(line)
        out = []
        inputs = {}
        i = 0
        while i < len(argv):
            a = argv[i]
            if a == "-o":
                i += 2
                continue
            if "gpl_hookfile_" in a and a.endswith(".o"):
                if "HOOKS" not in out:
                    out.append("HOOKS")
                i += 1
                continue
            if a.endswith((".o", ".a")) and not a.startswith("-"):
                host = (self.dir / a).resolve()
                inside = f"{LINK}/{len(inputs)}-{host.name}"
                inputs[host] = inside
                out.append(inside)
                i += 1
                continue
            out.append(a)
            i += 1
        out[0] = _program_in_usr(out[0])
        return out, inputs

    def built_hook_objects(self):
        """{source path: object path} of the hook files the lab's own build compiled with these very
        flags (assignments/ and solutions/, when built and up to date): trusted objects that a
        submission holding the same text needs not compile again."""
        found = {}
        commands = json.loads((self.dir / "compile_commands.json").read_text())
        gch = (self.pch / "cmake_pch.hxx.gch").stat().st_mtime if self.pch else 0
        for c in commands:
            m = re.search(r" -o (\S*gpl_hookfile_(?:assignments|solutions)_\S+\.o)", c.get("command", ""))
            if not m:
                continue
            source, obj = pathlib.Path(c["file"]), pathlib.Path(c["directory"]) / m.group(1)
            try:
                if obj.stat().st_mtime >= max(source.stat().st_mtime, gch):
                    found[source] = obj
            except OSError:
                continue
        return found

    def checker(self):
        return self.tests / "gpl-checker"

    def launcher(self):
        return pathlib.Path(os.environ.get("GPL_LAUNCH") or self.tests / "gpl-launch")

    def key(self):
        """What an object depends on besides its source: the compiler, the flags, the header."""
        h = hashlib.sha256()
        h.update(self.compiler.encode() + b"\0" + "\0".join(self.flags).encode())
        if self.pch:
            st = (self.pch / "cmake_pch.hxx.gch").stat()
            h.update(f"{st.st_size}:{st.st_mtime_ns}".encode())
        headers = self.include_dir
        for p in sorted(headers.rglob("*")):
            if p.is_file():
                st = p.stat()
                h.update(f"{p.relative_to(headers)}:{st.st_size}:{st.st_mtime_ns}".encode())
        return h.hexdigest()


# ---- Compiling in the sandbox ----------------------------------------------------------------------

class Compiled:
    """The object of one hook file, or the compiler's errors (cached: a twin compiles nothing)."""

    def __init__(self, obj, errors):
        self.obj, self.errors = obj, errors


def _limited(argv, binds, writable, limits, launcher, cwd):
    """Runs a compiler or linker in the sandbox, within limits; (returncode, output, why)."""
    here = Sandbox.here()
    group = None
    if Cgroups.here().available:
        try:
            group = Cgroups.here().make(limits, extra_processes=0)
        except OSError:
            group = None
    try:
        inner = list(argv)
        if group is None:  # no cgroup: the address space is the memory limit
            inner = ["/usr/bin/prlimit", f"--as={int(limits.memory_mib * 2) << 20}", "--"] + inner
        inner = ["/usr/bin/prlimit", f"--fsize={int(limits.file_mib) << 20}", f"--cpu={limits.cpu_seconds()}",
                 "--core=0", "--"] + inner
        cmd, env = here.compile_command(inner, binds, writable, limits, group, launcher, cwd)
        rc, out, why = run_limited(cmd, limits.seconds, env=env, cwd=cwd if not here.isolated else None)
        if group:
            why = why or group.broken()
        return rc, out, why
    finally:
        if group:
            group.remove()


def _escapes(output_asm):
    """An assembler directive that reads a file (only checked without the sandbox, which hides them)."""
    m = re.search(r"^\s*\.(incbin|include)\s+(\"[^\"]*\"|\S+)", output_asm, re.M)
    return m.group(0).strip() if m else None


# A compiler's message about a place in a file: "hook.cpp:12:5: error: ..." (g++ and Clang alike).
LOCATED_ERROR = re.compile(r"^[^\s:][^:\n]*:\d+:\d+: (fatal )?error: ", re.M)


def object_key(trusted, name, source):
    return hashlib.sha256(trusted.key().encode() + name.encode() + b"\0" + source).hexdigest()


def seed_cache(trusted, cache):
    """Takes into the cache the objects the lab's own build made of assignments/ and solutions/ (the
    same compiler and flags): a submission's files left as handed out, or equal to the reference,
    compile nothing."""
    for source, obj in trusted.built_hook_objects().items():
        try:
            target = cache / f"{object_key(trusted, source.name, source.read_bytes())}.o"
            if not target.exists():
                tmp = cache / f".{target.name}.{os.getpid()}.{threading.get_ident()}"
                shutil.copy(obj, tmp)
                os.replace(tmp, target)
        except OSError:
            continue


def compile_hook(trusted, cache, source_dir, name, launcher):
    """Compiles source_dir/name (a staged hook file) into the cache; returns a Compiled."""
    source = (source_dir / name).read_bytes()
    key = object_key(trusted, name, source)
    obj, err = cache / f"{key}.o", cache / f"{key}.err"
    if obj.exists():
        return Compiled(obj, None)
    if err.exists():
        return Compiled(None, err.read_text())
    with tempfile.TemporaryDirectory(prefix="gpl-compile-", dir=cache) as tmp:
        tmp = pathlib.Path(tmp)
        (tmp / "src").mkdir()
        (tmp / "out").mkdir()
        (tmp / "src" / name).write_bytes(source)
        errors, refused = None, False  # refused: the grader's own verdict on the file's text
        if Sandbox.here().isolated:
            binds = {trusted.include_dir: INCLUDE, tmp / "src": SOURCES}
            if trusted.pch:
                binds[trusted.pch] = PCH
            argv = [trusted.compiler, *trusted.flags, "-o", f"{OUT}/hook.o", "-c", name]
            rc, out, why = _limited(argv, binds, {tmp / "out": OUT}, COMPILE_LIMITS, launcher, SOURCES)
        else:
            # Without the sandbox: the same flags with the host's paths; the includes it read and the
            # assembler directives it wrote are checked, so that it reads nothing of the lab either.
            flags = [f.replace(INCLUDE, str(trusted.include_dir)).replace(PCH, str(trusted.pch))
                     for f in trusted.flags]
            # The includes first (preprocessing only), so that no message shows a line of what is outside.
            allowed = [pathlib.Path("/usr"), trusted.include_dir, tmp / "src"] + \
                      ([trusted.pch] if trusted.pch else [])
            rc, out, why = _limited([trusted.compiler, *flags, "-M", "-MF", str(tmp / "out" / "hook.d"), name],
                                    {}, {}, COMPILE_LIMITS, launcher, str(tmp / "src"))
            if rc == 0 and not why:
                deps = (tmp / "out" / "hook.d").read_text().replace("\\\n", " ").split(":", 1)[-1].split()
                outside = [d for d in deps if not any((tmp / "src" / d).resolve().is_relative_to(a.resolve())
                                                      for a in allowed)]
                if outside:
                    rc, out = 1, f"{name}: error: includes {outside[0]}, which is not a hook file or a header of the framework"
                    refused = True
                else:
                    rc, out, why = _limited([trusted.compiler, *flags, "-S", "-o", str(tmp / "out" / "hook.s"), name],
                                            {}, {}, COMPILE_LIMITS, launcher, str(tmp / "src"))
            if rc == 0 and not why:
                directive = _escapes((tmp / "out" / "hook.s").read_text(errors="replace"))
                if directive:
                    rc, out = 1, f"{name}: error: the assembler directive '{directive}' reads a file, which a hook file may not"
                    refused = True
                else:
                    rc, out, why = _limited([trusted.compiler, *flags, "-c", "-o", str(tmp / "out" / "hook.o"),
                                             str(tmp / "out" / "hook.s")], {}, {}, COMPILE_LIMITS, launcher, str(tmp / "src"))
        if why == "timeout":
            errors = f"{name}: error: the compiler took more than {COMPILE_LIMITS.seconds:g} s and was stopped"
        elif why == "memory":
            errors = f"{name}: error: the compiler used more than {COMPILE_LIMITS.memory_mib:g} MiB and was stopped"
        elif why:
            errors = f"{name}: error: the compiler was stopped ({why})"
        elif rc != 0 or not (tmp / "out" / "hook.o").exists():
            errors = out.strip() or f"{name}: error: the compiler failed (status {rc})"
        if errors is not None:
            # Kept only as the compiler's verdict on the file: an error at a line of it (or of a
            # header it includes), or the grader's refusal of its text. A limit, or a compiler ended
            # by a signal (the kernel's CPU or memory limit: g++'s "signal terminated program",
            # Clang's "unable to execute command"), says no line and may have been the machine's
            # load: tried again next time.
            if not why and (refused or LOCATED_ERROR.search(errors)):
                _write_new(err, errors)
            return Compiled(None, errors)
        os.replace(tmp / "out" / "hook.o", obj)
        return Compiled(obj, None)


def _write_new(path, text):
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}")
    tmp.write_text(text)
    os.replace(tmp, path)


def link_engine(trusted, objects, target, launcher):
    """Links the engine target from the trusted server and libraries and the hook objects, in the
    sandbox. Returns None, or the linker's errors."""
    argv_template, inputs = trusted.link
    with tempfile.TemporaryDirectory(prefix="gpl-link-", dir=target.parent) as tmp:
        tmp = pathlib.Path(tmp)
        (tmp / "obj").mkdir()
        names = []
        for i, obj in enumerate(objects):
            os.link(obj, tmp / "obj" / f"{i:02d}.o") if _same_fs(obj, tmp) else shutil.copy(obj, tmp / "obj" / f"{i:02d}.o")
            names.append(f"{OBJECTS}/{i:02d}.o" if Sandbox.here().isolated else str(tmp / "obj" / f"{i:02d}.o"))
        argv = []
        for a in argv_template:
            if a == "HOOKS":
                argv += names
            elif not Sandbox.here().isolated and a.startswith(LINK + "/"):
                argv.append(str(next(h for h, inside in inputs.items() if inside == a)))
            else:
                argv.append(a)
        out_path = f"{OUT}/engine" if Sandbox.here().isolated else str(tmp / "engine")
        argv += ["-o", out_path]
        binds = {host: inside for host, inside in inputs.items()}
        binds[tmp / "obj"] = OBJECTS
        (tmp / "out").mkdir()
        rc, out, why = _limited(argv, binds, {tmp / "out": OUT}, LINK_LIMITS, launcher, "/tmp")
        made = tmp / "out" / "engine" if Sandbox.here().isolated else tmp / "engine"
        if rc != 0 or why or not made.exists():
            # The linker names objects: each is a hook file, in the order of the list.
            for i, hook in enumerate(hooks.hook_files()):
                out = out.replace(f"{OBJECTS}/{i:02d}.o", hook).replace(str(tmp / "obj" / f"{i:02d}.o"), hook)
            lines = out.strip().splitlines()
            picked = [l for l in lines if "undefined reference" in l or "multiple definition" in l][:10]
            picked += [l for l in lines if "error:" in l][:3]
            return "\n".join(picked) or out.strip()[-2000:] or f"the linker was stopped ({why})"
        os.replace(made, target)
        return None


def _same_fs(a, b):
    try:
        return os.stat(a).st_dev == os.stat(b).st_dev
    except OSError:
        return False


# ---- Submissions -------------------------------------------------------------------------------------

MAX_HOOK_BYTES = 1 << 20   # a hook file is a few KiB; anything above a MiB is not one


def _printable(name, limit=120):
    """A file name as text that can be written anywhere (not UTF-8, or very long, it is shown so)."""
    text = os.fsencode(name).decode("utf-8", "replace")
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _regular(path):
    """Whether path is a regular file of the submission itself (a symbolic link is not followed)."""
    try:
        st = os.lstat(path)
    except OSError:
        return False
    return stat.S_ISREG(st.st_mode)


def prepare_submission(source, hooks_dir):
    """Copies the hook files of a submission into hooks_dir. Files the submission lacks are taken
    from the untouched stubs; everything else in it is ignored. Symbolic links are never followed
    (a hook file that is one is graded as the stub). Returns (missing, ignored, folder of its hook
    files)."""
    folder = source = pathlib.Path(source)
    if source.is_symlink():
        raise GradeError(f"submission folder {_printable(source)} is a symbolic link, which is not followed")
    if not source.is_dir():
        raise GradeError(f"submission folder not found: {_printable(source)}")
    names = hooks.hook_files()
    present = [n for n in names if _regular(source / n)]
    whole_lab = source / "assignments"
    if not present and not whole_lab.is_symlink() and any(_regular(whole_lab / n) for n in names):
        source = whole_lab  # a whole copy of the lab: its assignments/ is the submission
        present = [n for n in names if _regular(source / n)]
    if not present:
        raise GradeError(f"submission folder {_printable(source)} holds none of the hook files ({', '.join(names)})")
    hooks_dir.mkdir(parents=True, exist_ok=True)
    missing, taken = [], set()
    for n in names:
        src = source / n
        if not _regular(src) or os.lstat(src).st_size > MAX_HOOK_BYTES:
            src = ROOT / "assignments" / n
            missing.append(n)
        else:
            taken.add(source / n)
        text = src.read_bytes()
        dst = hooks_dir / n
        if not dst.exists() or dst.read_bytes() != text:
            dst.write_bytes(text)
    ignored = []
    for top, dirs, files in os.walk(folder, followlinks=False):
        for f in sorted(files + [d for d in dirs if os.path.islink(os.path.join(top, d))]):
            path = pathlib.Path(top) / f
            if path not in taken:
                ignored.append(_printable(path.relative_to(folder)))
        if len(ignored) > 1000:
            break
    return missing, sorted(ignored), source


class Submission:
    """One submission folder: its hook files, the engine that builds from them and its results."""

    def __init__(self, name, folder):
        self.name, self.folder = name, pathlib.Path(folder)
        self.source = self.folder    # where its hook files are (the folder, or its assignments/)
        self.error = None            # why it cannot be graded at all (no hook files, ...)
        self.build_errors = None     # the compiler's first errors
        self.missing, self.ignored = [], []
        self.variant = None
        self.engine = None           # the linked gpl-hooks-HASH
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
    share a folder, and so one engine). Sets sub.variant; sub.error for folders without hook files."""
    root = sub_build / "submissions"
    root.mkdir(parents=True, exist_ok=True)
    for sub in subs:
        with tempfile.TemporaryDirectory(dir=sub_build) as tmp:
            try:
                sub.missing, sub.ignored, sub.source = prepare_submission(sub.folder, pathlib.Path(tmp))
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


def _student_paths(text, sub):
    """Compiler messages with the student's own file names (the compiler saw hook files only)."""
    out = []
    for line in text.splitlines():
        for n in hooks.hook_files():
            for prefix in (f"{SOURCES}/{n}", n):
                if line.startswith(prefix + ":") or line.startswith(f"In file included from {prefix}:"):
                    line = line.replace(prefix, str(sub.source / n), 1)
                    break
        out.append(line)
    return "\n".join(out)


def build_submissions(subs, sub_build, jobs, trusted=None):
    """Compiles every distinct hook file of the submissions once (in the sandbox, in parallel) and
    links an engine per distinct submission; a submission that does not compile gets its own first
    errors (with its own file names)."""
    variants = sorted({s.variant for s in subs if s.variant})
    if not variants:
        return
    trusted = trusted or TrustedBuild(sub_build.parent / sub_build.name.replace("-submission", ""))
    cache = sub_build / "objects"
    engines = sub_build / "engines"
    cache.mkdir(parents=True, exist_ok=True)
    engines.mkdir(parents=True, exist_ok=True)
    launcher = trusted.launcher()
    seed_cache(trusted, cache)
    files = {(v, n) for v in variants for n in hooks.hook_files()}
    compiled = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
        # One compile per distinct file text: the first of equal files compiles, the others wait for it.
        by_text = {}
        for v, n in sorted(files):
            text = (sub_build / "submissions" / v / n).read_bytes()
            by_text.setdefault((n, hashlib.sha256(text).hexdigest()), []).append((v, n))
        futures = {pool.submit(compile_hook, trusted, cache, sub_build / "submissions" / group[0][0], group[0][1],
                               launcher): group for group in by_text.values()}
        for future, group in futures.items():
            result = future.result()
            for key in group:
                compiled[key] = result
    link_errors = {}

    def link(v):
        parts = [compiled[(v, n)] for n in hooks.hook_files()]
        if any(p.errors is not None for p in parts):
            return
        key = hashlib.sha256("\0".join(str(p.obj.name) for p in parts).encode() +
                             json.dumps(trusted.link[0]).encode()).hexdigest()[:16]
        target = engines / f"gpl-hooks-{key}"
        if not target.exists():
            errors = link_engine(trusted, [p.obj for p in parts], target, launcher)
            if errors:
                link_errors[v] = errors
                return
        for s in subs:
            if s.variant == v:
                s.engine = target

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
        list(pool.map(link, variants))
    for s in subs:
        if not s.variant:
            continue
        errors = [compiled[(s.variant, n)].errors for n in hooks.hook_files() if compiled[(s.variant, n)].errors]
        if errors:
            text = _student_paths("\n".join(errors), s)
            s.build_errors = first_errors(text) or text.strip()[-2000:]
        elif s.variant in link_errors:
            s.build_errors = "the engine does not link:\n" + link_errors[s.variant]


def reference_tests(checker, worksheet):
    """The graded tests, from the trusted checker: the list when the code graded does not compile."""
    return select(checker_manifest(checker), worksheet)


def grade_submission(sub, args, checker, guard, tests, jobs=1):
    start = time.monotonic()
    if sub.error:
        sub.results = failed_results(tests(), sub.error)
    elif sub.build_errors is not None:
        sub.results = failed_results(tests(), "the submission does not compile:\n" + sub.build_errors)
    else:
        sub.results = grade_binary(Programs(checker, sub.engine), args.worksheet, args.defaults, guard,
                                   tests=tests(), jobs=jobs)
    sub.seconds = time.monotonic() - start
    return sub
