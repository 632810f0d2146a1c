"""Where and within what a graded test's engine (the submission's code) runs.

Limits, each with a default and a per-test override declared with the test (graded.h):
  time     of the checker and the engine together, watched by the grader (--timeout or
           grading::timeLimit): the wall clock from the engine's start, less the time they waited
           for a core that other programs held (running.LOAD_ALLOWANCE); CPU time is a kernel limit
           a second above it (SIGXCPU)
  memory   the test's memory however it is allocated, a kernel limit where a cgroup can be made
           (cgroups.py), else its resident memory watched by the grader (grading::memoryLimit)
  threads  threads and processes at once, a kernel limit (cgroup pids.max) or watched
           (grading::threadLimit)
  files    bytes written to one file, a kernel limit (SIGXFSZ, grading::fileLimit); the private
           temporary folder holds twice that in all
The launcher (gpl-launch, trusted) sets the kernel's limits and installs the system-call filter
(no process, no network, no namespace, no shared memory, no exec) before the engine's first
instruction, its static initializers included.

With bubblewrap (Debian `bubblewrap`) the engine also runs in its own namespaces: it sees the
system's /usr read-only, its own binary, a private size-limited /tmp and nothing else: not the lab,
not solutions/, not other submissions, not the results; no network, no other processes, no
capabilities. Where the kernel does not allow that (some containers), the grader says so in one line
and falls back to running the engine directly (as nobody when the grader is root), with the write
guard (guard.py) watching the lab's files. GPL_GRADER_SANDBOX=off chooses the fallback on purpose.

Submissions are compiled in the same sandbox (compile_command): the compiler sees the system, the
framework's headers and the hook files only.
"""
import dataclasses
import os
import pathlib
import shutil
import subprocess
import threading

MIB = 1 << 20
DEFAULT_MEMORY_MIB = 1024     # a test of the course needs under 100 MiB (the 1000-sphere heap: ~20)
DEFAULT_THREADS = 8           # the engine may use a thread per core; a runaway loop starts hundreds
DEFAULT_FILE_MIB = 64         # no graded test writes files; the reports written for the grader are small
SANITIZER_OPTIONS = ("ASAN_OPTIONS", "LSAN_OPTIONS", "UBSAN_OPTIONS")


@dataclasses.dataclass(frozen=True)
class Limits:
    seconds: float            # time the test could run (running.LOAD_ALLOWANCE), and as many of CPU time
    memory_mib: float
    threads: int
    file_mib: float

    def cpu_seconds(self):
        """The kernel's whole seconds of CPU time: a second above the time limit."""
        return int(self.seconds + 0.999) + 1

    def describe(self):
        return (f"{self.seconds:g} s, {self.memory_mib:g} MiB of memory, {self.threads} threads, "
                f"{self.file_mib:g} MiB per file")


def default_limits(seconds, memory_mib=DEFAULT_MEMORY_MIB):
    return Limits(seconds, memory_mib, DEFAULT_THREADS, DEFAULT_FILE_MIB)


def limits_of(test, defaults):
    """The limits of a graded test (its manifest entry); defaults (Limits, or seconds) where it sets none."""
    if not isinstance(defaults, Limits):
        defaults = default_limits(defaults)
    return Limits(seconds=test.get("time_limit") or defaults.seconds,
                  memory_mib=test.get("memory_limit") or defaults.memory_mib,
                  threads=int(test.get("thread_limit") or defaults.threads),
                  file_mib=test.get("file_limit") or defaults.file_mib)


# ---- bubblewrap -----------------------------------------------------------------------------------

def _system_binds():
    """The system as a graded test sees it: /usr read-only (Debian's merged /usr: /lib, /lib64 and /bin
    are links into it) and the dynamic loader's cache."""
    args = ["--ro-bind", "/usr", "/usr"]
    for link in ("lib", "lib64", "lib32", "bin", "sbin"):
        target = pathlib.Path("/") / link
        if target.is_symlink():
            args += ["--symlink", os.readlink(target), str(target)]
        elif target.is_dir():
            args += ["--ro-bind", str(target), str(target)]
    if pathlib.Path("/etc/ld.so.cache").is_file():
        args += ["--ro-bind", "/etc/ld.so.cache", "/etc/ld.so.cache"]
    return args


NAMESPACES = ["--unshare-all", "--unshare-user", "--uid", "65534", "--gid", "65534", "--die-with-parent",
              "--new-session", "--cap-drop", "ALL", "--proc", "/proc", "--dev", "/dev"]


class Sandbox:
    """Probed once per grader process: whether bubblewrap can make namespaces here."""

    _lock = threading.Lock()
    _probed = None

    def __init__(self, bwrap, reason):
        self.bwrap = bwrap      # the bwrap executable, or None: the fallback
        self.reason = reason    # why not, for the report

    @classmethod
    def here(cls):
        with cls._lock:
            if cls._probed is None:
                cls._probed = cls._probe()
            return cls._probed

    @classmethod
    def _probe(cls):
        if os.environ.get("GPL_GRADER_SANDBOX", "").lower() == "off":
            return cls(None, "switched off (GPL_GRADER_SANDBOX=off)")
        bwrap = shutil.which("bwrap")
        if bwrap is None:
            return cls(None, "bubblewrap is not installed (Debian package bubblewrap)")
        true = shutil.which("true") or "/usr/bin/true"
        try:
            proc = subprocess.run([bwrap, *NAMESPACES, *_system_binds(), "--remount-ro", "/", true],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=20)
        except (OSError, subprocess.TimeoutExpired) as e:
            return cls(None, f"bubblewrap could not start ({e})")
        if proc.returncode != 0:
            why = proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else f"exit status {proc.returncode}"
            return cls(None, f"the kernel does not let bubblewrap make namespaces here ({why})")
        return cls(bwrap, None)

    @property
    def isolated(self):
        return self.bwrap is not None

    def describe(self):
        """One line for the report."""
        if self.isolated:
            return ("sandbox: each test ran in bubblewrap (no view of the lab, solutions or other "
                    "submissions; no network; no processes)")
        user = " as nobody" if os.geteuid() == 0 else ""
        return (f"sandbox: not used: {self.reason}; the engine ran{user} without file isolation "
                "(processes and network are still refused, the lab's files guarded)")

    def runner_command(self, runner, args, folder, limits, launcher, cgroup=None, sanitizer=False):
        """The command that runs the untrusted `runner args` under the limits: joined to its cgroup
        (when there is one) before anything runs, in bubblewrap when there is a sandbox, and through
        the launcher, which sets the kernel's limits and the system-call filter before the runner's
        first instruction. Returns (command, environment, runner's trace file on the host).

        folder is the test's own folder on the host (made by the caller, private to the grader): the
        runner's trace file is made in folder/runner/, the only host file the runner may write;
        inside the sandbox it is /grader/trace.txt."""
        folder = pathlib.Path(folder)
        launcher = str(pathlib.Path(launcher).resolve())
        own = folder / "runner"
        own.mkdir(exist_ok=True)
        trace = own / "trace.txt"
        trace.touch()
        limit_args = ["--cpu", str(limits.cpu_seconds()), "--file-bytes", str(int(limits.file_mib * MIB))]
        if sanitizer:
            limit_args.append("--sanitizer")
        joined = cgroup.launcher_args() if cgroup else []
        env = {"PATH": "/usr/bin:/bin"}
        if not self.isolated:
            # Without namespaces the runner gives up root (when the grader has it) and works in a
            # folder of its own; the lab stays readable, which the report's sandbox line says.
            os.chmod(folder, 0o711)
            os.chmod(own, 0o777)
            os.chmod(trace, 0o666)
            drop = ["--drop-user"] if os.geteuid() == 0 else []
            env["GPL_GRADER_TRACE"] = str(trace)
            for key in SANITIZER_OPTIONS:
                if key in os.environ:
                    env[key] = os.environ[key]
            cmd = [launcher, *joined, *limit_args, *drop, "--chdir", str(own), "--",
                   str(pathlib.Path(runner).resolve()), *args]
            return cmd, env, trace
        target = f"/grader/{pathlib.Path(runner).name}"
        binds = ["--ro-bind", launcher, "/grader/gpl-launch",
                 "--ro-bind", str(pathlib.Path(runner).resolve()), target,
                 "--bind", str(trace), "/grader/trace.txt"]
        setenv = ["--setenv", "GPL_GRADER_TRACE", "/grader/trace.txt"]
        for key in SANITIZER_OPTIONS:  # the sanitizers' options travel, with their suppression files
            if key in os.environ:
                parts = []
                for part in os.environ[key].split(":"):
                    if part.startswith("suppressions=") and pathlib.Path(part.split("=", 1)[1]).is_file():
                        # Bound under /grader, not at its own path, which would show the lab's folders.
                        path = f"/grader/{key.lower()}.supp"
                        binds += ["--ro-bind", part.split("=", 1)[1], path]
                        part = f"suppressions={path}"
                    parts.append(part)
                setenv += ["--setenv", key, ":".join(parts)]
        file_bytes = int(limits.file_mib * MIB)
        cmd = [self.bwrap, *NAMESPACES, *_system_binds(), "--size", str(2 * file_bytes), "--tmpfs", "/tmp",
               *binds, "--remount-ro", "/", "--remount-ro", "/dev", "--clearenv",
               "--setenv", "PATH", "/usr/bin", *setenv, "--chdir", "/tmp",
               "/grader/gpl-launch", *limit_args, "--", target, *args]
        if joined:
            cmd = [launcher, "--join-only", *joined, "--"] + cmd
        return cmd, env, trace

    def compile_command(self, argv, binds, writable, limits, cgroup=None, launcher=None, cwd="/tmp"):
        """The command that runs a compiler (or linker) `argv` in the sandbox: the system's /usr and
        `binds` ({host path: path inside}) read-only, `writable` ({host: inside}) writable, nothing
        else; a private /tmp. With a cgroup, the compiler joins it first (memory and processes).
        Without a sandbox: argv as it is (the caller checks what it includes). Returns (command, env)."""
        env = {"PATH": "/usr/bin:/bin", "LANG": "C", "LC_ALL": "C"}
        joined = cgroup.launcher_args() if cgroup and launcher else []
        prefix = [str(launcher), "--join-only", *joined, "--"] if joined else []
        if not self.isolated:
            return prefix + list(argv), {**os.environ, **env}
        args = []
        for host, inside in binds.items():
            args += ["--ro-bind", str(host), str(inside)]
        for host, inside in writable.items():
            args += ["--bind", str(host), str(inside)]
        cmd = [self.bwrap, *NAMESPACES, *_system_binds(), "--size", str(int(limits.file_mib * MIB) * 4),
               "--tmpfs", "/tmp", *args, "--remount-ro", "/", "--clearenv",
               *(a for k, v in env.items() for a in ("--setenv", k, v)), "--chdir", cwd, *argv]
        return prefix + cmd, {"PATH": os.environ.get("PATH", "/usr/bin")}


# ---- What a running test uses ---------------------------------------------------------------------

def descendants(pid):
    """pid and every process below it (bubblewrap's own processes included)."""
    found, stack = [], [pid]
    while stack:
        p = stack.pop()
        found.append(p)
        try:
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as f:
                    stack.extend(int(c) for c in f.read().split())
        except (OSError, ValueError):
            continue
    return found


def _usage(pid):
    """(resident bytes, threads, command name) of one process, or None when it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
        with open(f"/proc/{pid}/statm") as f:
            resident = int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None
    name = stat[stat.index("(") + 1: stat.rindex(")")]
    threads = int(stat[stat.rindex(")") + 2:].split()[17])
    return resident, threads, name


def test_processes(pid):
    """The processes of a running test: those below pid that are not bubblewrap's or prlimit's."""
    return [p for p in descendants(pid) if (_usage(p) or (0, 0, "bwrap"))[2] not in ("bwrap", "prlimit", "gpl-launch")]


def usage(pid):
    """(resident MiB, threads) of the test started as pid, bubblewrap's own processes left out."""
    memory, threads = 0, 0
    for p in test_processes(pid):
        u = _usage(p)
        if u:
            memory += u[0]
            threads += u[1]
    return memory / MIB, threads


# ---- Cores and memory for tests running at once ---------------------------------------------------

def usable_cores(cgroup_root="/sys/fs/cgroup"):
    """The cores this process may use at once: those it may run on, fewer where its cgroup's CPU
    quota gives fewer (in a container os.cpu_count() counts the host's cores). At least one."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    root = pathlib.Path(cgroup_root)
    quota = None
    try:  # cgroup v2: "QUOTA PERIOD" or "max PERIOD"
        fields = (root / "cpu.max").read_text().split()
        if fields[0] != "max":
            quota = int(fields[0]) / int(fields[1])
    except (OSError, ValueError, IndexError, ZeroDivisionError):
        try:  # cgroup v1: a quota of -1 is none
            q = int((root / "cpu" / "cpu.cfs_quota_us").read_text())
            period = int((root / "cpu" / "cpu.cfs_period_us").read_text())
            if q > 0 and period > 0:
                quota = q / period
        except (OSError, ValueError):
            pass
    if quota is not None:
        cores = min(cores, int(quota))
    return max(1, cores)



def available_mib():
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) / 1024
    except (OSError, ValueError):
        pass
    return None


class MemoryBudget:
    """Tests running at once reserve their memory limit from what the machine has available, so a
    parallel batch never starts more memory-limited tests than the memory allows (one always runs)."""

    def __init__(self, total_mib=None):
        total = total_mib if total_mib is not None else available_mib()
        self.total = 0.8 * total if total else float("inf")  # leave room for the grader and the build
        self.used, self.running = 0.0, 0
        self.cond = threading.Condition()

    def slots(self, mib):
        return max(1, int(self.total // mib)) if self.total != float("inf") else None

    def reserve(self, mib):
        with self.cond:
            self.cond.wait_for(lambda: self.running == 0 or self.used + mib <= self.total)
            self.used += mib
            self.running += 1

    def release(self, mib):
        with self.cond:
            self.used -= mib
            self.running -= 1
            self.cond.notify_all()


BUDGET = MemoryBudget()
