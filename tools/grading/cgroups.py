"""A control group per graded test: the kernel counts its memory however it is allocated and its
threads and processes, stops it at its limits, and lets the grader end every process of the test.

cgroup v1 (memory and pids hierarchies mounted writable, as in many containers) or a delegated
cgroup v2 (memory and pids enabled for the grader's own group). Each test gets its own group below
the grader's own: memory.limit_in_bytes (and memsw) or memory.max (and swap 0) at the test's memory
limit, pids.max at its thread limit plus the sandbox's own processes. The launcher (gpl-launch
--cgroup DIR) joins it before anything of the test runs. Afterwards the grader reads whether the
kernel stopped the test at a limit, kills what is left and removes the group.

Where neither is available, Cgroups.here().reason says why, and the grader watches resident memory
and threads itself (sandbox.usage) as before."""
import os
import pathlib
import signal
import threading
import time

MIB = 1 << 20
ROOT = pathlib.Path("/sys/fs/cgroup")
# bubblewrap's own processes (its parent and the sandbox's init) besides the test's threads.
SANDBOX_PROCESSES = 2


def _own_paths():
    """{controller: path} of this process's cgroups ("" for the v2 unified group)."""
    found = {}
    try:
        for line in pathlib.Path("/proc/self/cgroup").read_text().splitlines():
            _, controllers, path = line.split(":", 2)
            for c in controllers.split(",") if controllers else [""]:
                found[c] = path
    except (OSError, ValueError):
        pass
    return found


def _write(path, text):
    with open(path, "w") as f:
        f.write(text)


def _read(path, default=""):
    try:
        return pathlib.Path(path).read_text()
    except OSError:
        return default


def _counter(text, key):
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] == key and parts[1].isdigit():
            return int(parts[1])
    return 0


class TestCgroup:
    """The groups of one running test (one per hierarchy: two in v1, one in v2)."""

    def __init__(self, kind, dirs, memory_dir, pids_dir, limits, extra_processes):
        self.kind, self.dirs = kind, dirs
        self.memory_dir, self.pids_dir = memory_dir, pids_dir
        self.limits, self.extra = limits, extra_processes

    def launcher_args(self):
        return [arg for d in self.dirs for arg in ("--cgroup", str(d))]

    def processes(self):
        pids = set()
        for d in self.dirs:
            for line in _read(d / "cgroup.procs").split():
                if line.isdigit():
                    pids.add(int(line))
        return sorted(pids)

    def broken(self):
        """"memory" or "threads" when the kernel stopped the test at that limit, else None."""
        if self.kind == "v1":
            oom = _read(self.memory_dir / "memory.oom_control")
            if ("oom_kill " in oom and _counter(oom, "oom_kill") > 0) or \
                    ("oom_kill " not in oom and int(_read(self.memory_dir / "memory.failcnt", "0").strip() or 0) > 0):
                return "memory"
            if _counter(_read(self.pids_dir / "pids.events"), "max") > 0:
                return "threads"
        else:
            events = _read(self.memory_dir / "memory.events")
            if _counter(events, "oom_kill") > 0 or _counter(events, "oom") > 0:
                return "memory"
            if _counter(_read(self.pids_dir / "pids.events"), "max") > 0:
                return "threads"
        return None

    def near_memory_limit(self, share=0.8):
        """Whether the test uses more than `share` of its memory limit now (the grader stops it
        there, so that it can write where it was; the kernel's limit stays the backstop)."""
        if not self.limits:
            return False
        name = "memory.usage_in_bytes" if self.kind == "v1" else "memory.current"
        text = _read(self.memory_dir / name).strip()
        return text.isdigit() and int(text) > share * self.limits.memory_mib * MIB

    def threads_refused(self):
        """Whether the kernel has refused the test a thread or process (pids.max reached)."""
        return _counter(_read(self.pids_dir / "pids.events"), "max") > 0

    def peak_mib(self):
        name = "memory.max_usage_in_bytes" if self.kind == "v1" else "memory.peak"
        text = _read(self.memory_dir / name).strip()
        return int(text) / MIB if text.isdigit() else None

    def kill(self):
        """Kills every process of the test; returns once none is left (or after a few seconds)."""
        if self.kind == "v2" and (self.memory_dir / "cgroup.kill").exists():
            try:
                _write(self.memory_dir / "cgroup.kill", "1")
            except OSError:
                pass
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            left = self.processes()
            if not left:
                return True
            for pid in left:
                try:
                    os.kill(pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
            time.sleep(0.01)
        return False

    def remove(self):
        self.kill()
        left = [d for d in self.dirs if not _rmdir(d, seconds=2.0)]
        if left:
            # A killed process leaves its group once it is reaped, which a loaded machine may take
            # longer to do: the group is removed later, without holding up the next test.
            threading.Thread(target=lambda: [_rmdir(d, seconds=60.0) for d in left], daemon=True).start()


def _rmdir(d, seconds):
    """Removes the (empty) group folder d, trying for up to `seconds`; True once it is gone."""
    deadline = time.monotonic() + seconds
    while True:
        try:
            d.rmdir()
            return True
        except FileNotFoundError:
            return True
        except OSError:
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.01)


class Cgroups:
    """Probed once per grader process: where a test's group can be made, or why not."""

    _lock = threading.Lock()
    _count_lock = threading.Lock()
    _probed = None
    _count = 0

    def __init__(self, kind, memory_base, pids_base, reason):
        self.kind = kind                    # "v1", "v2" or None
        self.memory_base, self.pids_base = memory_base, pids_base
        self.reason = reason

    @classmethod
    def here(cls):
        with cls._lock:
            if cls._probed is None:
                cls._probed = cls._probe()
            return cls._probed

    @classmethod
    def _probe(cls):
        if os.environ.get("GPL_GRADER_CGROUPS", "").lower() == "off":
            return cls(None, None, None, "switched off (GPL_GRADER_CGROUPS=off)")
        own = _own_paths()
        v1_memory, v1_pids = ROOT / "memory", ROOT / "pids"
        if (v1_memory / "memory.limit_in_bytes").exists() and (v1_pids / "pids.max").exists() or \
                (v1_memory / "cgroup.procs").exists() and (v1_pids / "cgroup.procs").exists():
            memory = v1_memory / own.get("memory", "/").lstrip("/")
            pids = v1_pids / own.get("pids", "/").lstrip("/")
            probe = cls("v1", memory, pids, None)
            why = probe._try()
            return probe if why is None else cls(None, None, None, why)
        if (ROOT / "cgroup.controllers").exists() and "" in own:
            base = ROOT / own[""].lstrip("/")
            probe = cls("v2", base, base, None)
            why = probe._try()
            return probe if why is None else cls(None, None, None, why)
        return cls(None, None, None, "no memory and pids cgroup is mounted here")

    def _try(self):
        """None when a test's group can be made here, else why not."""
        if self.kind == "v2":
            control = self.memory_base / "cgroup.subtree_control"
            enabled = _read(control).split()
            if not {"memory", "pids"} <= set(enabled):
                try:
                    _write(control, "+memory +pids")
                except OSError as e:
                    return f"the cgroup v2 group {self.memory_base} does not delegate memory and pids ({e.strerror})"
        try:
            group = self.make(None)
        except OSError as e:
            return f"cannot make a cgroup in {self.memory_base} ({e.strerror})"
        group.remove()
        self._sweep()
        return None

    def _sweep(self):
        """Removes the empty groups that graders no longer running left behind (gpl-grade-PID-N)."""
        for base in {self.memory_base, self.pids_base}:
            try:
                entries = list(base.iterdir())
            except OSError:
                continue
            for d in entries:
                parts = d.name.split("-")
                if len(parts) == 4 and d.name.startswith("gpl-grade-") and parts[2].isdigit() and \
                        not pathlib.Path(f"/proc/{parts[2]}").exists():
                    _rmdir(d, seconds=0.0)

    @property
    def available(self):
        return self.kind is not None

    def describe(self):
        """One line for the report when the kernel does not keep the limits, else None."""
        if self.available:
            return None
        return (f"limits: no cgroup for memory and threads ({self.reason}); the grader watches the "
                "resident memory and threads instead (memory in files or shared memory is refused)")

    def make(self, limits, extra_processes=SANDBOX_PROCESSES):
        """A fresh group for one test with its limits (limits None: a probe with none)."""
        with Cgroups._count_lock:
            Cgroups._count += 1
            name = f"gpl-grade-{os.getpid()}-{Cgroups._count}"
        memory_bytes = int(limits.memory_mib * MIB) if limits else None
        if self.kind == "v1":
            memory, pids = self.memory_base / name, self.pids_base / name
            memory.mkdir()
            try:
                pids.mkdir()
            except OSError:
                memory.rmdir()
                raise
            group = TestCgroup("v1", [memory, pids], memory, pids, limits, extra_processes)
            try:
                if memory_bytes:
                    _write(memory / "memory.limit_in_bytes", str(memory_bytes))
                    if (memory / "memory.memsw.limit_in_bytes").exists():
                        _write(memory / "memory.memsw.limit_in_bytes", str(memory_bytes))
                    _write(pids / "pids.max", str(limits.threads + extra_processes))
            except OSError:
                group.remove()
                raise
            return group
        group_dir = self.memory_base / name
        group_dir.mkdir()
        group = TestCgroup("v2", [group_dir], group_dir, group_dir, limits, extra_processes)
        try:
            if memory_bytes:
                _write(group_dir / "memory.max", str(memory_bytes))
                if (group_dir / "memory.swap.max").exists():
                    _write(group_dir / "memory.swap.max", "0")
                _write(group_dir / "pids.max", str(limits.threads + extra_processes))
        except OSError:
            group.remove()
            raise
        return group
