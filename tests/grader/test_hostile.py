"""Hostile submissions: hook files written to forge a grade or to escape the sandbox, each otherwise an
ordinary submission (the reference, or a hook that does nothing, or one with a known mistake). Each
must score exactly what its honest physics earns: the same, test by test, as an honest "twin" graded
in the same batch (the reference; an integrator that does nothing; one that crashes; one without
gravity; ...), or zero everywhere where it does not compile. Besides the scores: the message where it
matters (its first line, naming the hook), the lab's tree unchanged, no file written where the
submission aimed, no connection made, and no process of the grading alive afterwards (this test
process is a subreaper: whatever the grading leaves behind becomes its child), nor a result rewritten
seconds after the grader ended.

The mechanisms, with the issue's numbering ("grading that no submission can forge or escape"):
 1. a static initializer (in sphere_plane.cpp, run before main) that catches SIGSYS to survive what
    the filter refuses, then forks a daemon in a session of its own (which would rewrite results.json
    and the gradebook later), connects to a port this test listens on, reads solutions/ and a hidden
    test, writes into tools/ and tests/ and over the results; another that forks without catching;
 2. in-process forgeries of the verdict: a GoogleTest global environment that skips, a
    ScopedFakeTestPartResultReporter, a replaced result printer (GoogleTest is no part of the engine
    a submission is linked into, so these do not build: zero everywhere, the error naming GoogleTest),
    an atexit handler and a hook that write a passing report and _exit(0), fake "[  PASSED  ]" lines;
 3. a quoted #include of the solutions (absolute and relative), __has_include probing for them, .incbin
    of a hidden test and of a solution, a compiler bomb, an #include of /dev/zero;
 4. memfd_create, shm_open, shmget and MAP_SHARED|MAP_ANONYMOUS, 30 x 48 MiB each; bursts of threads;
    a raw clone() without CLONE_THREAD; unshare(CLONE_NEWUSER); exec of /usr/bin/true; signals to
    other processes; reading other processes through /proc; raising the open-files limit; io_uring;
 5. setGravity(0), setTimeStep() and masses changed by a hook in its own engine;
 6. an endless recursion; a hook that writes a fake call stack blaming another hook;
 and: garbage, a frame too long, or nothing (closed) on the answer pipe; non-UTF-8 output; a hook file
 that is a symlink to the solutions; assignments/ a symlink to the solutions; a submission folder that
 is a symlink to the solutions; very long and non-UTF-8 file names; a very long folder name.

Worksheet 1 only (every twist lives there), one batch for all of them, then one submission alone
(./lab grade --submission) and, in GradescopeAutograder, the Gradescope bundle's run_autograder."""
import contextlib
import csv
import ctypes
import hashlib
import json
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import hooks  # noqa: E402
import test_release  # noqa: E402

CHECK_GRADESCOPE = ROOT.parent / "shared" / "tools" / "check-gradescope.py"
MEMORY = 256        # MiB per test: the course's tests need under 10; 30 x 48 MiB is far above it
SETTLE = 3.0        # s to wait after grading for anything left behind to show itself
TOKEN = f"gh{os.getpid() % 100000:05d}"  # names this run's files and the daemon's process (comm)


def checker():
    return pathlib.Path(os.environ.get("GPL_CHECKER") or ROOT / "build" / "release" / "tests" / "gpl-checker")


def trusted_tests(worksheet=None):
    """The graded tests as the trusted checker lists them (no submission code runs for this)."""
    proc = subprocess.run([str(checker()), "--grader-manifest"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return [t for t in json.loads(proc.stdout) if worksheet is None or t["worksheet"] == worksheet]


def lab_digest():
    """The lab's own files (what a submission could aim at), build folders and caches left out."""
    h = hashlib.sha256()
    for top in ("assignments", "solutions", "tests", "tools", "framework", "cmake", "lab", "CMakeLists.txt"):
        path = ROOT / top
        for p in sorted([path] if path.is_file() else path.rglob("*")):
            if p.is_file() and "__pycache__" not in p.parts:
                h.update(str(p.relative_to(ROOT)).encode() + b"\0" + p.read_bytes())
    return h.hexdigest()


def source_digest(folder):
    """A copy of the lab's sources (the Gradescope bundle's), its build folders left out."""
    h = hashlib.sha256()
    for p in sorted(pathlib.Path(folder).rglob("*")):
        rel = p.relative_to(folder)
        if p.is_file() and rel.parts[0] != "build" and "__pycache__" not in rel.parts:
            h.update(os.fsencode(rel) + b"\0" + p.read_bytes())
    return h.hexdigest()


def results_digest(*paths):
    """The gradebook and the results files (symbolic links not followed)."""
    h = hashlib.sha256()
    for path in paths:
        for p in sorted([path] if path.is_file() else path.rglob("*") if path.is_dir() else []):
            if p.is_file() and not p.is_symlink():
                h.update(os.fsencode(p) + b"\0" + p.read_bytes())
    return h.hexdigest()


# ---- Subreaper: what the grading leaves running becomes this process's child -------------------------

PR_SET_CHILD_SUBREAPER = 36


def become_subreaper():
    libc = ctypes.CDLL(None, use_errno=True)
    return libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0


def own_children():
    """(pid, command line) of every living child of this process (zombies reaped)."""
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            break
        if pid == 0:
            break
    found = []
    for task in os.listdir(f"/proc/{os.getpid()}/task"):
        try:
            pids = pathlib.Path(f"/proc/{os.getpid()}/task/{task}/children").read_text().split()
        except OSError:
            continue
        for pid in map(int, pids):
            try:
                state = pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
                cmd = pathlib.Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                continue
            if state != "Z":
                found.append((pid, cmd.strip()))
    return found


def processes_named(comm):
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if pathlib.Path(f"/proc/{entry}/comm").read_text().strip() == comm:
                    found.append(int(entry))
            except OSError:
                pass
    return found


def end_leftovers(pids):
    """Ends what the grading left (our own children by now, as the subreaper)."""
    for pid in pids:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signal.SIGKILL)
    own_children()


class Listener:
    """A TCP port on this machine that counts connections: no submission may reach it."""

    def __init__(self):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(16)
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.connections = []
        self.running = True
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        while self.running:
            try:
                conn, peer = self.sock.accept()
            except (socket.timeout, OSError):
                continue
            self.connections.append(peer)
            conn.close()

    def close(self):
        self.running = False
        self.thread.join(timeout=2)
        self.sock.close()


# ---- Hook files ------------------------------------------------------------------------------------

SOLUTION = {name: (ROOT / "solutions" / name).read_text() for name in hooks.hook_files()}
STUB = {name: (ROOT / "assignments" / name).read_text() for name in hooks.hook_files()}
FUNCTION = "void PhysicsEngine::integrator() {\n"
# The submission's answer made wrong on purpose: what a twist does when it got what it was after (a
# file it should not see, a call that should have been refused, memory beyond the limit), so that
# any success shows as lost points with a physics message, never as a limit's or filter's message.
BREAK = "for (Body& broken : bodies()) if (!broken.isStatic()) broken.velocity.x() += 1.0;"


def c_string(text):
    return json.dumps(str(text))


def reference_integrator(at_start="", prelude="", includes=""):
    """The reference integrator with code run first in every call, `prelude` before namespace gpl."""
    text = SOLUTION["integrator.cpp"]
    assert FUNCTION in text and "#include <cmath>\n" in text and "namespace gpl {\n" in text
    text = text.replace("#include <cmath>\n", "#include <cmath>\n" + includes, 1)
    text = text.replace("namespace gpl {\n", prelude + "\nnamespace gpl {\n", 1)
    return text.replace(FUNCTION, FUNCTION + at_start + "\n", 1)


def empty_integrator(at_start="", prelude="", includes=""):
    """An integrator that does nothing (and says nothing: not the stub's "not implemented")."""
    return (f'#include "gpl/engine.h"\n{includes}\n{prelude}\n'
            f"namespace gpl {{\n\nvoid PhysicsEngine::integrator() {{\n{at_start}\n}}\n\n}}  // namespace gpl\n")


def plain_integrator(at_start="", explicit=False):
    """Euler without the reference's energy assertion (which reads gravity() of the hook's own
    engine): semi-implicit, or explicit (the velocity after the position: gains energy)."""
    update = ("        b.position += h * b.velocity;\n        b.velocity += h * b.acceleration;\n" if explicit else
              "        b.velocity += h * b.acceleration;\n        b.position += h * b.velocity;\n")
    return ('#include "gpl/engine.h"\n\nnamespace gpl {\n\nvoid PhysicsEngine::integrator() {\n'
            f"{at_start}\n    const double h = timeStep();\n    for (Body& b : bodies()) {{\n"
            f"        if (b.isStatic()) continue;\n{update}    }}\n}}\n\n}}  // namespace gpl\n")


GRAVITY_LINE = "    if (stageActive(Stage::ConstantAcceleration)) updateConstantAcceleration();\n"


def timestep(replace_with):
    text = SOLUTION["simulation_timestep.cpp"]
    assert GRAVITY_LINE in text
    return text.replace(GRAVITY_LINE, replace_with)


def with_static_init(hook_file, code, includes):
    """A hook file of the solutions with a static initializer appended (it runs before main)."""
    return (includes + SOLUTION[hook_file] +
            "\nnamespace {\nstruct HostileStart {\n    HostileStart() {\n" + code + "\n    }\n} hostileStart;\n}  // namespace\n")


CATCH_SIGSYS = r"""
// What the system-call filter refuses raises SIGSYS; caught, the refused call returns -EPERM and the
// program goes on, as a determined student would have it.
static void hostileRefused(int, siginfo_t*, void* context) {
    static_cast<ucontext_t*>(context)->uc_mcontext.gregs[REG_RAX] = -EPERM;
}
"""


def static_attack(paths, port, catch=True):
    """sphere_plane.cpp (the reference) with a static initializer that tries everything at once;
    `hostileSaw` (read by the integrator) becomes true when any of it worked."""
    includes = ("#include <arpa/inet.h>\n#include <cerrno>\n#include <csignal>\n#include <cstdio>\n#include <fcntl.h>\n"
                "#include <fstream>\n#include <netinet/in.h>\n#include <sys/prctl.h>\n#include <sys/socket.h>\n"
                "#include <ucontext.h>\n#include <unistd.h>\n" + (CATCH_SIGSYS if catch else "") +
                "bool hostileSaw = false;\n")
    forged = json.dumps({"score": 9999, "output": "forged", "tests": []})
    writes = "\n".join(f"            std::ofstream({c_string(p)}) << {c_string(forged)};" for p in paths["overwrite"])
    code = ""
    if catch:
        code += ("        struct sigaction refused {};\n        refused.sa_sigaction = hostileRefused;\n"
                 "        refused.sa_flags = SA_SIGINFO;\n        sigaction(SIGSYS, &refused, nullptr);\n")
    code += f"""
        // The instructor's files: whatever can be read is a leak.
        for (const char* path : {{{", ".join(c_string(p) for p in paths["read"])}}})
            if (std::ifstream(path).good()) hostileSaw = true;
        // The lab's own folders: a file written there is an escape.
        for (const char* path : {{{", ".join(c_string(p) for p in paths["write"])}}})
            if (std::ofstream(path) << "// written by a submission\\n") hostileSaw = true;
        // A connection out.
        const int s = socket(AF_INET, SOCK_STREAM, 0);
        if (s >= 0) {{
            sockaddr_in to{{}};
            to.sin_family = AF_INET;
            to.sin_port = htons({port});
            to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            if (connect(s, reinterpret_cast<sockaddr*>(&to), sizeof to) == 0) hostileSaw = true;
            close(s);
        }}
        // A daemon in a session of its own that rewrites the results once the grader has written them.
        const pid_t child = fork();
        if (child == 0) {{
            setsid();
            if (fork() == 0) {{
                prctl(PR_SET_NAME, "{TOKEN}");
                for (int i = 0; i < 1200; ++i) {{
                    usleep(100000);
{writes}
                    std::ofstream({c_string(paths["marker"])}) << "the daemon ran";
                }}
            }}
            _exit(0);
        }}
        if (child > 0) hostileSaw = true;
"""
    return with_static_init("sphere_plane.cpp", code, includes)


SAW = reference_integrator(f"    if (hostileSaw) {BREAK}", prelude="extern bool hostileSaw;\n")


def passing_report(names):
    """A GoogleTest JSON report in which every test passed, as a forger would write it."""
    suites = {}
    for n in names:
        suite, test = n.split(".")
        suites.setdefault(suite, []).append({"name": test, "status": "RUN", "result": "COMPLETED", "time": "0s",
                                             "classname": suite})
    return json.dumps({"tests": len(names), "failures": 0, "errors": 0, "name": "AllTests",
                       "testsuites": [{"name": s, "tests": len(c), "failures": 0, "testsuite": c}
                                      for s, c in suites.items()]})


FAKE_PASS_OUTPUT = "[==========] 1 test from 1 test suite ran. (1 ms total)\\n[  PASSED  ] 1 test.\\n"


def forge_and_exit(report):
    """C++ statements: a passing report written wherever one might be read, a passing printout, _exit(0)."""
    return (f"        for (const char* path : {{\"report.json\", \"/tmp/report.json\", \"test_detail.json\"}})\n"
            f"            std::ofstream(path) << {c_string(report)};\n"
            f"        std::printf(\"{FAKE_PASS_OUTPUT}\");\n        std::fprintf(stderr, \"{FAKE_PASS_OUTPUT}\");\n"
            f"        std::fflush(nullptr);\n        _exit(0);\n")


def memory_grab(kind):
    """30 x 48 MiB held at once through `kind`, in the first call; when all of it is held (the limit
    side-stepped), the answer is broken."""
    grab = {
        "memfd": "const int fd = memfd_create(\"cache\", 0);\n"
                 "        if (fd < 0 || ftruncate(fd, kBlock) != 0) break;\n"
                 "        void* p = mmap(nullptr, kBlock, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);",
        "shm_open": "const std::string name = \"/gpl-cache-\" + std::to_string(i);\n"
                    "        const int fd = shm_open(name.c_str(), O_CREAT | O_RDWR, 0600);\n"
                    "        if (fd < 0 || ftruncate(fd, kBlock) != 0) break;\n"
                    "        void* p = mmap(nullptr, kBlock, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);",
        "shmget": "const int id = shmget(IPC_PRIVATE, kBlock, IPC_CREAT | 0600);\n"
                  "        if (id < 0) break;\n        void* p = shmat(id, nullptr, 0);\n"
                  "        if (p == reinterpret_cast<void*>(-1)) break;",
        "mmap_shared": "void* p = mmap(nullptr, kBlock, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);",
    }[kind]
    at_start = f"""    static int held = -1;
    if (held < 0) {{
        held = 0;
        constexpr long kBlock = 48L << 20;
        for (int i = 0; i < 30; ++i) {{
        {grab}
        if (p == MAP_FAILED || p == nullptr) break;
        std::memset(p, 1, kBlock);
        ++held;
        }}
    }}
    if (held == 30) {BREAK}"""
    return reference_integrator(at_start, includes="#include <cstring>\n#include <fcntl.h>\n#include <string>\n"
                                "#include <sys/ipc.h>\n#include <sys/mman.h>\n#include <sys/shm.h>\n#include <unistd.h>\n")


FAKE_TRACE = ("grader: the crash happened elsewhere\\n"
              "/grader/gpl-hooks(_ZN3gpl12sphereSphereERKNS_4BodyES2_+0x1d) [0x55d0c0de1000]\\n"
              "/grader/gpl-hooks(_ZN3gpl12sphereSphereERKNS_4BodyES2_+0x1d) [0x55d0c0de1000]\\n")
GTEST_INCLUDES = "#include <gtest/gtest.h>\n#include <gtest/gtest-spi.h>\n"


def submissions(paths, port, names):
    """name -> {relative path: text (a hook file or another file), or ("symlink", target)}; hook
    files not named are the solutions'."""
    crash = "    *static_cast<volatile int*>(nullptr) = 1;"
    report = passing_report(names)
    integrators = {
        # ---- Honest twins: what each twist's physics earns -----------------------------------------
        "reference": SOLUTION["integrator.cpp"],
        "do_nothing": empty_integrator(),
        "crash": reference_integrator(crash),
        "exits": reference_integrator("    _exit(0);", includes="#include <unistd.h>\n"),
        "explicit_euler": plain_integrator(explicit=True),
        "fixed_step": plain_integrator().replace("const double h = timeStep();", "const double h = 0.001;"),
        # ---- 2: in-process forgeries of the verdict --------------------------------------------------
        "gtest_environment": empty_integrator(
            prelude="namespace {\nstruct SkipAll : testing::Environment {\n"
                    "    void SetUp() override { GTEST_SKIP() << \"nothing to grade\"; }\n};\n"
                    "testing::Environment* const skipAll = testing::AddGlobalTestEnvironment(new SkipAll);\n}\n",
            includes=GTEST_INCLUDES),
        "gtest_fake_reporter": empty_integrator(
            prelude="namespace {\ntesting::TestPartResultArray swallowed;\n"
                    "testing::ScopedFakeTestPartResultReporter* const reporter = new testing::ScopedFakeTestPartResultReporter(\n"
                    "    testing::ScopedFakeTestPartResultReporter::INTERCEPT_ALL_THREADS, &swallowed);\n}\n",
            includes=GTEST_INCLUDES),
        "gtest_listener": empty_integrator(
            prelude="namespace {\nstruct AllPassed : testing::EmptyTestEventListener {\n"
                    "    void OnTestProgramEnd(const testing::UnitTest&) override { std::printf(\"[  PASSED  ] all\\n\"); }\n};\n"
                    "const bool replaced = [] {\n    auto& listeners = testing::UnitTest::GetInstance()->listeners();\n"
                    "    delete listeners.Release(listeners.default_result_printer());\n"
                    "    listeners.Append(new AllPassed);\n    return true;\n}();\n}\n",
            includes=GTEST_INCLUDES + "#include <cstdio>\n"),
        "atexit_report": empty_integrator(
            prelude="namespace {\nvoid forge() {\n" + forge_and_exit(report) + "}\n"
                    "const int registered = std::atexit(forge);\n}\n",
            includes="#include <cstdio>\n#include <cstdlib>\n#include <fstream>\n#include <unistd.h>\n"),
        "exit_passing": reference_integrator(forge_and_exit(report),
                                             includes="#include <cstdio>\n#include <fstream>\n#include <unistd.h>\n"),
        "fake_output": empty_integrator(f"    static bool printed = false;\n    if (printed) return;\n    printed = true;\n"
                                        f"    std::printf(\"{FAKE_PASS_OUTPUT}\");\n"
                                        f"    std::fprintf(stderr, \"{FAKE_PASS_OUTPUT}\");",
                                        includes="#include <cstdio>\n"),
        # ---- 3: compiling ------------------------------------------------------------------------------
        "include_absolute": f'#include "{ROOT}/solutions/integrator.cpp"\n',
        "include_relative": '#include "../../../../solutions/integrator.cpp"\n',
        "include_probe": "".join(
            f'#{"if" if i == 0 else "elif"} __has_include("{p}")\n#include "{p}"\n'
            for i, p in enumerate([f"{ROOT}/solutions/integrator.cpp"] +
                                  ["../" * d + "solutions/integrator.cpp" for d in range(1, 9)]))
            + "#else\n" + empty_integrator() + "#endif\n",
        "incbin_hidden": empty_integrator(
            "    std::puts(hostileBlob);",
            prelude=f'extern "C" const char hostileBlob[];\nasm(".section .rodata\\n.globl hostileBlob\\nhostileBlob:\\n'
                    f'.incbin \\"{ROOT}/tests/autograder/worksheet1_hidden_test.cpp\\"\\n.byte 0\\n.previous\\n");\n',
            includes="#include <cstdio>\n"),
        "incbin_solution": empty_integrator(
            "    std::puts(hostileBlob);",
            prelude=f'extern "C" const char hostileBlob[];\nasm(".section .rodata\\n.globl hostileBlob\\nhostileBlob:\\n'
                    f'.incbin \\"{ROOT}/solutions/integrator.cpp\\"\\n.byte 0\\n.previous\\n");\n',
            includes="#include <cstdio>\n"),
        "compiler_bomb": empty_integrator(
            prelude="template <int N, unsigned long M> struct Bomb {\n"
                    "    static constexpr unsigned long value = Bomb<N - 1, 2 * M>::value + Bomb<N - 1, 2 * M + 1>::value;\n};\n"
                    "template <unsigned long M> struct Bomb<0, M> { static constexpr unsigned long value = M; };\n"
                    "static_assert(Bomb<40, 1>::value > 0, \"every instantiation\");\n"),
        "include_dev_zero": '#include "/dev/zero"\n' + empty_integrator(),
        # ---- 4: limits ---------------------------------------------------------------------------------
        "memfd": memory_grab("memfd"),
        "shm_open": memory_grab("shm_open"),
        "shmget": memory_grab("shmget"),
        "mmap_shared": memory_grab("mmap_shared"),
        "thread_burst": reference_integrator(f"""    static int bursts = -1;
    if (bursts < 0) {{
        bursts = 0;
        for (int round = 0; round < 20; ++round) {{
            pthread_t threads[32];
            int made = 0;
            for (int i = 0; i < 32; ++i)
                if (pthread_create(&threads[made], nullptr, [](void*) -> void* {{ usleep(20000); return nullptr; }}, nullptr) == 0)
                    ++made;
            for (int i = 0; i < made; ++i) pthread_join(threads[i], nullptr);
            if (made == 32) ++bursts;
        }}
    }}
    if (bursts == 20) {BREAK}""", includes="#include <pthread.h>\n#include <unistd.h>\n"),
        "raw_clone": reference_integrator(f"""    const long child = syscall(SYS_clone, SIGCHLD, 0, 0, 0, 0);
    if (child == 0) _exit(0);
    if (child > 0) {{
        waitpid(static_cast<pid_t>(child), nullptr, 0);
        {BREAK}
    }}""", includes="#include <csignal>\n#include <sys/syscall.h>\n#include <sys/wait.h>\n#include <unistd.h>\n"),
        "unshare_user": reference_integrator(f"    if (unshare(CLONE_NEWUSER) == 0) {BREAK}",
                                             includes="#include <sched.h>\n"),
        "exec_true": reference_integrator(f"    execl(\"/usr/bin/true\", \"true\", static_cast<char*>(nullptr));\n    {BREAK}",
                                          includes="#include <unistd.h>\n"),
        "kill_others": reference_integrator(
            f"    if (kill(1, SIGKILL) == 0 || kill(getppid(), SIGKILL) == 0 || kill(-1, SIGKILL) == 0) {BREAK}",
            includes="#include <csignal>\n#include <unistd.h>\n"),
        "raise_open_files": reference_integrator(f"""    rlimit files{{}};
    if (getrlimit(RLIMIT_NOFILE, &files) == 0) {{
        files.rlim_cur = files.rlim_max = files.rlim_max + 1024;
        if (setrlimit(RLIMIT_NOFILE, &files) == 0) {BREAK}
    }}""", includes="#include <sys/resource.h>\n"),
        "io_uring": reference_integrator(f"""    unsigned char params[120] = {{}};
    if (syscall(SYS_io_uring_setup, 4, params) >= 0) {BREAK}""",
                                         includes="#include <sys/syscall.h>\n#include <unistd.h>\n"),
        "proc_snoop": reference_integrator(f"""    static const bool saw = [] {{
        DIR* proc = opendir("/proc");
        bool found = false;
        while (dirent* e = proc ? readdir(proc) : nullptr) {{
            if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
            const std::string pid = std::string("/proc/") + e->d_name;
            std::ifstream in(pid + "/cmdline");
            const std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            for (const char* other : {{"gpl-checker", "grade.py", "unittest", "python"}})
                if (cmd.find(other) != std::string::npos) found = true;
            if (std::ifstream(pid + "/root{ROOT}/solutions/integrator.cpp").good()) found = true;
        }}
        if (proc) closedir(proc);
        return found;
    }}();
    if (saw) {BREAK}""", includes="#include <dirent.h>\n#include <fstream>\n#include <iterator>\n#include <string>\n"),
        # ---- 6: messages ------------------------------------------------------------------------------
        "recursion": reference_integrator(
            f"    volatile int depth = 0;\n    if (deeper(&depth) == 42) {BREAK}",
            prelude="namespace {\nint deeper(volatile int* depth) {\n    volatile char frame[512];\n"
                    "    frame[0] = static_cast<char>(*depth);\n    *depth = *depth + 1;\n"
                    "    return deeper(depth) + frame[0];\n}\n}\n"),
        "fake_blame": reference_integrator(
            "    signal(SIGSEGV, blameAnother);\n" + crash,
            prelude="namespace {\nvoid blameAnother(int) {\n    const char* path = std::getenv(\"GPL_GRADER_TRACE\");\n"
                    "    const int fd = open(path ? path : \"/grader/trace.txt\", O_WRONLY | O_TRUNC);\n"
                    f"    const char fake[] = \"{FAKE_TRACE}\";\n"
                    "    if (fd >= 0 && write(fd, fake, sizeof fake - 1) > 0) close(fd);\n"
                    "    signal(SIGSEGV, SIG_DFL);\n    raise(SIGSEGV);\n}\n}\n",
            includes="#include <csignal>\n#include <cstdlib>\n#include <fcntl.h>\n#include <unistd.h>\n"),
        # ---- The answer pipe --------------------------------------------------------------------------
        "garbage_answer": reference_integrator(
            "    const unsigned char junk[] = {9, 0, 0, 0, 2, 0xff, 0xff, 0xff, 0x7f, 1, 2, 3, 4};\n"
            "    if (write(4, junk, sizeof junk) < 0) return;", includes="#include <unistd.h>\n"),
        "huge_frame": reference_integrator(
            "    const unsigned int length = 0xfffffff0u;\n    if (write(4, &length, sizeof length) < 0) return;",
            includes="#include <unistd.h>\n"),
        "closed_pipes": reference_integrator("    close(3);\n    close(4);", includes="#include <unistd.h>\n"),
        "non_utf8_output": reference_integrator(
            "    const char bytes[] = \"\\xff\\xfe not UTF-8 \\xc3\\x28 \\x00 after a NUL\\n\";\n"
            "    std::fwrite(bytes, 1, sizeof bytes - 1, stdout);\n    std::fflush(stdout);\n" + crash,
            includes="#include <cstdio>\n"),
    }
    subs = {name: {"integrator.cpp": text} for name, text in integrators.items()}
    # ---- 5: the checker owns gravity, the time step and the masses ---------------------------------------
    subs["no_gravity"] = {"integrator.cpp": plain_integrator(),
                          "simulation_timestep.cpp": timestep("    if (stageActive(Stage::ConstantAcceleration))\n"
                                                              "        for (Body& b : bodies()) b.acceleration.setZero();\n")}
    subs["set_gravity"] = {"integrator.cpp": plain_integrator(),
                           "simulation_timestep.cpp": timestep("    setGravity(Vec3::Zero());\n" + GRAVITY_LINE)}
    subs["set_time_step"] = {"integrator.cpp": plain_integrator("    setTimeStep(0.001);")}
    subs["set_masses"] = {"integrator.cpp": plain_integrator("    for (Body& b : bodies()) b.mass = 1e-9;", explicit=True)}
    subs["stub_integrator"] = {"integrator.cpp": STUB["integrator.cpp"]}
    # ---- 1: static initializers ------------------------------------------------------------------------
    subs["static_init"] = {"integrator.cpp": SAW, "sphere_plane.cpp": static_attack(paths, port)}
    subs["static_init_uncaught"] = {"integrator.cpp": SAW, "sphere_plane.cpp": static_attack(paths, port, catch=False)}
    # ---- Folders and files -------------------------------------------------------------------------------
    subs["symlink_hook"] = {"integrator.cpp": ("symlink", ROOT / "solutions" / "integrator.cpp")}
    subs["symlink_assignments"] = {None: None, "assignments": ("symlink", ROOT / "solutions"),
                                   "lab": ("symlink", ROOT)}
    subs["long_names"] = {"integrator.cpp": SOLUTION["integrator.cpp"], "n" * 250 + ".txt": "notes",
                          "/".join(["deep"] * 40) + "/notes.txt": "notes", b"notes-\xff\xfe.txt": "notes"}
    return subs


# name -> what it must score. ("twin", NAME, FIRST_LINE): every test the same status and score as the
# honest NAME; FIRST_LINE a regex each failed test's message must start with ("twin": the same first
# line as the twin's). ("no_compile", REGEX): zero everywhere, every message says the submission does
# not compile and matches REGEX. ("zero",): zero everywhere. ("passes_or_limit",): each test passes
# or fails at the memory limit, never on its physics.
# The hook a message names for a call within a whole step: the call the checker had in flight
# (simulationTimestep()), or the stage that was running where the checker lists the step's stages
# (integrator()); never another hook, whatever call stack the engine leaves behind.
HOOK = r"in (integrator|simulationTimestep)\(\)"
# What the student reads when the engine does not link for want of GoogleTest: which symbols.
GTEST_MISSING = r"undefined reference to .*testing::|gtest"
# The compiler stopped at its time or memory limit, in one line naming the file.
COMPILER_STOPPED = r"\n\S*integrator\.cpp: error: the compiler (took|used) more than [0-9.]+ (s|MiB) and was stopped\n"
EXPECTED = {
    "reference": ("twin", "reference", None),
    "do_nothing": ("twin", "do_nothing", None),
    "crash": ("twin", "crash", rf"^crashed with SIGSEGV {HOOK}"),
    "exits": ("twin", "exits", rf"^the engine (exited \(status 0\) |did not answer ){HOOK}"),
    "explicit_euler": ("twin", "explicit_euler", None),
    "fixed_step": ("twin", "fixed_step", None),
    "no_gravity": ("twin", "no_gravity", None),
    "stub_integrator": ("twin", "stub_integrator", None),
    "gtest_environment": ("no_compile", GTEST_MISSING),
    "gtest_fake_reporter": ("no_compile", GTEST_MISSING),
    "gtest_listener": ("no_compile", GTEST_MISSING),
    "atexit_report": ("twin", "do_nothing", "twin"),
    "exit_passing": ("twin", "exits", "twin"),
    "fake_output": ("twin", "do_nothing", "twin"),
    "include_absolute": ("no_compile", r"solutions/integrator\.cpp"),
    "include_relative": ("no_compile", r"solutions/integrator\.cpp"),
    "include_probe": ("twin", "do_nothing", "twin"),
    "incbin_hidden": ("no_compile", r"worksheet1_hidden_test\.cpp"),
    "incbin_solution": ("no_compile", r"solutions/integrator\.cpp"),
    "compiler_bomb": ("no_compile", COMPILER_STOPPED),
    "include_dev_zero": ("no_compile", COMPILER_STOPPED),
    "memfd": ("twin", "crash", rf"^(tried to allocate shared memory or a memory file|used more than {MEMORY} MiB "
                               rf"of memory) {HOOK}"),
    "shmget": ("twin", "crash", rf"^tried to allocate shared memory or a memory file {HOOK}"),
    "shm_open": ("passes_or_limit",),
    "mmap_shared": ("twin", "crash", rf"^used more than {MEMORY} MiB of memory {HOOK}"),
    "thread_burst": ("twin", "crash", rf"^ran more than 8 threads at once {HOOK}"),
    "raw_clone": ("twin", "crash", rf"^tried to start a process {HOOK}"),
    "unshare_user": ("twin", "crash", rf"^tried to make a namespace or mount something {HOOK}"),
    "exec_true": ("twin", "crash", rf"^tried to start a process {HOOK}"),
    "kill_others": ("twin", "crash", rf"^tried to send a signal to another process {HOOK}"),
    "raise_open_files": ("twin", "crash", rf"^tried to raise its limit of open files {HOOK}"),
    "io_uring": ("twin", "crash", rf"^tried to use a kernel interface that graded code may not use {HOOK}"),
    "proc_snoop": ("twin", "reference", None),
    "recursion": ("twin", "crash", rf"^overflowed its stack {HOOK}"),
    "fake_blame": ("twin", "crash", rf"^crashed with SIGSEGV {HOOK}"),
    "garbage_answer": ("twin", "crash", rf"^the engine did not answer {HOOK}"),
    "huge_frame": ("twin", "crash", rf"^the engine did not answer {HOOK}"),
    "closed_pipes": ("twin", "crash", rf"^the engine (did not answer|exited \(status \d+\)) {HOOK}"),
    "non_utf8_output": ("twin", "crash", "twin"),
    "set_gravity": ("twin", "no_gravity", None),
    "set_time_step": ("twin", "fixed_step", None),
    "set_masses": ("twin", "explicit_euler", None),
    "static_init": ("twin", "reference", None),
    "static_init_uncaught": ("zero", r"^tried to start a process"),
    "symlink_hook": ("twin", "stub_integrator", None),
    "symlink_assignments": ("zero", None),
    "long_names": ("twin", "reference", None),
}
# The gravity tests a hook could pass by setting gravity to zero in the checker's view (issue, item 5).
GRAVITY_TESTS = ["Worksheet1.GravityAppliedExactlyOnce", "Worksheet1.MatchesDiscreteFreeFall",
                 "Worksheet1.GravityIndependentOfMass"]
# A very long folder name (an honest copy of the reference) and a batch entry that is a symlink to the
# solutions (it must not score the solutions' marks).
LONG_FOLDER = "student-" + "x" * 200
LINKED_FOLDER = "linked_to_solutions"


def write_submission(folder, files):
    folder.mkdir(parents=True)
    hook_names = set(hooks.hook_files())
    if None not in files:  # None: a folder of nothing but what is listed
        for name in hook_names - set(files):
            (folder / name).write_text(SOLUTION[name])
    for rel, content in files.items():
        if rel is None:
            continue
        path = folder / os.fsdecode(rel)
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, tuple) and content[0] == "symlink":
            path.symlink_to(content[1])
        else:
            path.write_text(content)


def attack_paths(tmp, results):
    """What the static initializer aims at: the instructor's files, the lab's folders, the results."""
    return {
        "read": [ROOT / "solutions" / "integrator.cpp", ROOT / "tests" / "autograder" / "worksheet1_hidden_test.cpp",
                 ROOT / "tests" / "autograder" / "worksheet1_test.cpp"],
        "write": [ROOT / "tools" / f"hostile_{TOKEN}.py", ROOT / "tests" / "autograder" / f"hostile_{TOKEN}_test.cpp",
                  ROOT / "solutions" / f"hostile_{TOKEN}.cpp", tmp / "written-by-submission"],
        "overwrite": results,
        "marker": tmp / "daemon-ran",
    }


def first_line(text):
    return text.split("\n", 1)[0]


class HostileBatch(unittest.TestCase):
    """Every hostile submission and its honest twins, graded as one batch of worksheet 1."""

    @classmethod
    def setUpClass(cls):
        cls.subreaper = become_subreaper()
        cls.before = lab_digest()
        cls.tmp = pathlib.Path(tempfile.mkdtemp(prefix="gpl-hostile-"))
        cls.listener = Listener()
        cls.tests = trusted_tests(1)
        names = [t["name"] for t in cls.tests]
        cls.batch = cls.tmp / "batch"
        cls.gradebook = cls.tmp / "grades.csv"
        cls.results_dir = cls.tmp / "grades-results"
        cls.single_json = cls.tmp / "single" / "results.json"
        targets = [cls.gradebook, cls.single_json] + [cls.results_dir / n / "results.json" for n in EXPECTED]
        cls.paths = attack_paths(cls.tmp, targets)
        cls.subs = submissions(cls.paths, cls.listener.port, names)
        assert set(cls.subs) == set(EXPECTED), set(cls.subs) ^ set(EXPECTED)
        for name, files in cls.subs.items():
            write_submission(cls.batch / name, files)
        write_submission(cls.batch / LONG_FOLDER, {})
        (cls.batch / LINKED_FOLDER).symlink_to(ROOT / "solutions")
        start = time.monotonic()
        cls.proc = subprocess.run([str(ROOT / "lab"), "grade", "--batch", str(cls.batch), "--out", str(cls.gradebook),
                                   "--worksheet", "1", "--memory", str(MEMORY)],
                                  capture_output=True, text=True, errors="replace", cwd=ROOT, timeout=900)
        cls.seconds = time.monotonic() - start
        print(f"\nhostile batch of {len(EXPECTED) + 2} graded in {cls.seconds:.1f} s", file=sys.stderr)
        cls.digest_at_end = results_digest(cls.gradebook, cls.results_dir)
        cls.left_at_end = own_children()
        time.sleep(SETTLE)
        cls.left_later = own_children()
        cls.named_later = processes_named(TOKEN)
        cls.digest_later = results_digest(cls.gradebook, cls.results_dir)
        end_leftovers([p for p, _ in cls.left_later] + cls.named_later)
        cls.results = {}
        for name in list(EXPECTED) + [LONG_FOLDER, LINKED_FOLDER]:
            path = cls.results_dir / name / "results.json"
            if path.exists():
                cls.results[name] = json.loads(path.read_text())

    @classmethod
    def tearDownClass(cls):
        cls.listener.close()
        end_leftovers([p for p, _ in own_children()] + processes_named(TOKEN))
        for path in cls.paths["write"][:3]:
            if path.exists():
                path.unlink()  # only ever files this test named; their presence failed a test already
        shutil.rmtree(cls.tmp, ignore_errors=True)

    # ---- The batch as a whole ---------------------------------------------------------------------

    def test_the_batch_finished_with_every_results_file(self):
        self.assertEqual(self.proc.returncode, 1, self.proc.stdout[-3000:] + self.proc.stderr[-3000:])
        self.assertEqual((set(EXPECTED) | {LONG_FOLDER}) - set(self.results), set(), self.proc.stderr[-3000:])
        self.assertIn("sandbox: each test ran in bubblewrap", self.proc.stderr)

    def test_the_gradebook_is_whole_with_the_trusted_test_names(self):
        with open(self.gradebook, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
        header, rows = rows[0], rows[1:]
        names = [t["name"] for t in self.tests]
        self.assertEqual(header[0], "submission")
        self.assertEqual(header[-3:], ["total", "max_score", "note"])
        self.assertEqual(sorted(header[1:-3]), sorted(names), "a column per trusted test, no other")
        by_name = {r[0]: dict(zip(header, r)) for r in rows}
        self.assertEqual((set(EXPECTED) | {LONG_FOLDER}) - set(by_name), set())
        maximum = sum(t["points"] for t in self.tests)
        for name, row in by_name.items():
            with self.subTest(submission=name):
                self.assertEqual(float(row["max_score"]), maximum)
                if name in self.results:
                    for t in self.results[name]["tests"]:
                        self.assertEqual(float(row[t["name"]]), t["score"], t["name"])
                    self.assertEqual(float(row["total"]), self.results[name]["score"])

    def test_a_submission_folder_that_links_to_the_solutions_scores_nothing(self):
        # Left out of the batch, or graded as the empty folder it is to the grader: never as the solutions.
        results = self.results.get(LINKED_FOLDER)
        if results is not None:
            self.assertEqual(results["score"], 0, "a symlinked submission folder was graded as the solutions")
        with open(self.gradebook, newline="", encoding="utf-8") as f:
            for row in csv.DictReader(f):
                if row["submission"] == LINKED_FOLDER:
                    self.assertEqual(float(row["total"]), 0)

    def test_honest_submissions_get_their_marks(self):
        for name in ("reference", LONG_FOLDER, "long_names", "proc_snoop", "static_init"):
            with self.subTest(submission=name):
                results = self.results[name]
                self.assertEqual(results["score"], sum(t["points"] for t in self.tests),
                                 [(t["name"], t["output"][:300]) for t in results["tests"] if t["status"] != "passed"])

    def test_results_files_are_valid_for_gradescope(self):
        for name, results in self.results.items():
            with self.subTest(submission=name):
                check = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), "/dev/stdin"], input=json.dumps(results),
                                       capture_output=True, text=True)
                self.assertEqual(check.returncode, 0, check.stdout)
                self.assertEqual(sorted(t["name"] for t in results["tests"]), sorted(t["name"] for t in self.tests),
                                 "every trusted test, by its trusted name, once")
                for t in results["tests"]:
                    self.assertEqual(t["max_score"], next(m["points"] for m in self.tests if m["name"] == t["name"]))

    # ---- Nothing escaped --------------------------------------------------------------------------

    def test_the_lab_is_unchanged(self):
        for path in self.paths["write"]:
            self.assertFalse(path.exists(), f"a submission wrote {path}")
        self.assertEqual(lab_digest(), self.before, "a submission changed the lab's files")

    def test_no_connection_reached_this_machine(self):
        self.assertEqual(self.listener.connections, [])

    def test_no_process_outlives_the_grading(self):
        self.assertTrue(self.subreaper, "this test could not become a subreaper")
        self.assertEqual(self.left_at_end, [], "processes left running when the grader ended")
        self.assertEqual(self.left_later, [], f"processes running {SETTLE:g} s after the grader ended")
        self.assertEqual(self.named_later, [], "the submission's daemon is running")

    def test_nothing_rewrote_the_results_afterwards(self):
        self.assertFalse(self.paths["marker"].exists(), "the submission's daemon ran")
        self.assertEqual(self.digest_later, self.digest_at_end, "results changed after the grader ended")
        self.assertNotIn("forged", self.gradebook.read_text(encoding="utf-8"))

    # ---- Each submission scores what its honest physics earns -----------------------------------------

    def check(self, name):
        kind, *args = EXPECTED[name]
        self.assertIn(name, self.results, f"no results.json for {name}")
        tests = {t["name"]: t for t in self.results[name]["tests"]}
        self.assertEqual(self.results[name]["score"], sum(t["score"] for t in tests.values()))
        if kind == "twin":
            twin, line = args
            mine = {n: t for n, t in tests.items()}
            theirs = {t["name"]: t for t in self.results[twin]["tests"]}
            for n, t in mine.items():
                with self.subTest(submission=name, test=n):
                    self.assertEqual((t["status"], t["score"]), (theirs[n]["status"], theirs[n]["score"]),
                                     f"{name}: {t['output'][:600]!r}\n{twin}: {theirs[n]['output'][:300]!r}")
                    if t["status"] == "failed" and line and not t["output"].startswith("not run:"):
                        if line == "twin":
                            self.assertEqual(first_line(t["output"]), first_line(theirs[n]["output"]))
                        else:
                            self.assertRegex(t["output"], line)
        elif kind == "no_compile":
            for n, t in tests.items():
                with self.subTest(submission=name, test=n):
                    self.assertEqual((t["status"], t["score"]), ("failed", 0), t["output"][:600])
                    self.assertRegex(t["output"], r"does not compile", t["output"][:600])
                    self.assertRegex(t["output"], args[0])
        elif kind == "zero":
            for n, t in tests.items():
                with self.subTest(submission=name, test=n):
                    self.assertEqual((t["status"], t["score"]), ("failed", 0), t["output"][:600])
                    if args and args[0] and not t["output"].startswith("not run:"):
                        self.assertRegex(t["output"], args[0])
        elif kind == "passes_or_limit":
            for n, t in tests.items():
                with self.subTest(submission=name, test=n):
                    if t["status"] != "passed" and not t["output"].startswith("not run:"):
                        self.assertRegex(t["output"], rf"^used more than {MEMORY} MiB of memory {HOOK}")

    def test_honest_twins(self):
        for name in ("reference", "do_nothing", "crash", "exits", "explicit_euler", "fixed_step", "no_gravity",
                     "stub_integrator"):
            self.check(name)
        self.assertEqual(self.results["reference"]["score"], sum(t["points"] for t in self.tests))
        self.assertLess(self.results["do_nothing"]["score"], self.results["reference"]["score"])

    def test_1_static_initializer_runs_only_in_the_sandbox(self):
        self.check("static_init")

    def test_1_static_initializer_refused_without_catching(self):
        self.check("static_init_uncaught")

    def test_2_gtest_global_environment(self):
        self.check("gtest_environment")

    def test_2_gtest_fake_result_reporter(self):
        self.check("gtest_fake_reporter")

    def test_2_gtest_replaced_result_printer(self):
        self.check("gtest_listener")

    def test_2_atexit_handler_writes_a_passing_report(self):
        self.check("atexit_report")

    def test_2_hook_writes_a_passing_report_and_exits(self):
        self.check("exit_passing")

    def test_2_fake_passed_lines(self):
        self.check("fake_output")

    def test_3_include_of_the_solutions(self):
        self.check("include_absolute")
        self.check("include_relative")

    def test_3_has_include_finds_nothing(self):
        self.check("include_probe")

    def test_3_incbin(self):
        self.check("incbin_hidden")
        self.check("incbin_solution")
        for name in ("incbin_hidden", "incbin_solution"):  # nothing of the embedded files in a message
            for t in self.results[name]["tests"]:
                self.assertNotIn("GRADED_TEST", t["output"])
                self.assertNotIn("BEGIN SOLUTION", t["output"])

    def test_3_compiler_bomb(self):
        self.check("compiler_bomb")
        for name in ("compiler_bomb", "include_dev_zero"):  # the heading and one line (then the hint)
            for t in self.results[name]["tests"]:
                lines = [l for l in t["output"].strip().splitlines() if not l.startswith("hint:")]
                self.assertLessEqual(len(lines), 2, t["output"][:2000])

    def test_3_include_of_an_endless_file(self):
        self.check("include_dev_zero")

    def test_4_memfd(self):
        self.check("memfd")

    def test_4_shm_open(self):
        self.check("shm_open")

    def test_4_shmget(self):
        self.check("shmget")

    def test_4_shared_anonymous_mapping(self):
        self.check("mmap_shared")

    def test_4_thread_bursts(self):
        self.check("thread_burst")

    def test_4_raw_clone(self):
        self.check("raw_clone")

    def test_4_unshare_user_namespace(self):
        self.check("unshare_user")

    def test_4_exec(self):
        self.check("exec_true")

    def test_4_signals_to_other_processes(self):
        self.check("kill_others")

    def test_4_raising_the_open_files_limit(self):
        self.check("raise_open_files")

    def test_4_kernel_interfaces(self):
        self.check("io_uring")

    def test_4_other_processes_out_of_sight(self):
        self.check("proc_snoop")

    def test_5_set_gravity(self):
        self.check("set_gravity")
        tests = {t["name"]: t for t in self.results["set_gravity"]["tests"]}
        for name in GRAVITY_TESTS:
            self.assertEqual(tests[name]["score"], 0, f"{name} passed without gravity")

    def test_5_set_time_step(self):
        self.check("set_time_step")

    def test_5_set_masses(self):
        self.check("set_masses")

    def test_6_stack_overflow(self):
        self.check("recursion")

    def test_6_fake_call_stack(self):
        self.check("fake_blame")
        for t in self.results["fake_blame"]["tests"]:
            self.assertNotIn("sphereSphere", t["output"])

    def test_answer_pipe_garbage(self):
        self.check("garbage_answer")

    def test_answer_pipe_frame_too_long(self):
        self.check("huge_frame")

    def test_answer_pipe_closed(self):
        self.check("closed_pipes")

    def test_non_utf8_output(self):
        self.check("non_utf8_output")

    def test_symlinked_hook_file_is_not_followed(self):
        self.check("symlink_hook")

    def test_symlinked_assignments_is_not_followed(self):
        self.check("symlink_assignments")

    def test_long_and_non_utf8_file_names(self):
        self.check("long_names")

    def test_one_hostile_submission_alone(self):
        """./lab grade --submission on the static initializer's submission: full marks, its own
        results.json untouched seconds later, nothing left running."""
        self.single_json.parent.mkdir(exist_ok=True)
        proc = subprocess.run([str(ROOT / "lab"), "grade", "--submission", str(self.batch / "static_init"),
                               "--worksheet", "1", "--json", str(self.single_json), "--memory", str(MEMORY)],
                              capture_output=True, text=True, errors="replace", cwd=ROOT, timeout=600)
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:] + proc.stderr[-3000:])
        written = self.single_json.read_bytes()
        self.assertEqual(json.loads(written)["score"], sum(t["points"] for t in self.tests))
        self.assertEqual(own_children(), [])
        time.sleep(SETTLE)
        left = own_children()
        end_leftovers([p for p, _ in left])
        self.assertEqual(left, [])
        self.assertEqual(self.single_json.read_bytes(), written, "results.json rewritten after the grader ended")
        self.assertFalse(self.paths["marker"].exists())


class GradescopeAutograder(test_release.GradescopeAutograder):
    """The Gradescope bundle of test_release.py (its tests run here too, on one build), grading as
    well the static initializer's submission, then the untouched stubs, with run_autograder."""

    @classmethod
    def setUpClass(cls):
        cls.subreaper = become_subreaper()
        super().setUpClass()  # the bundle in cls.tmp, unpacked to cls.fake / "source", setup.sh run
        cls.listener = Listener()
        if cls.made.returncode != 0:
            cls.setup = None
        cls.source_before = source_digest(cls.fake / "source") if cls.made.returncode == 0 else None
        results = cls.fake / "results" / "results.json"
        cls.paths = attack_paths(cls.tmp, [results])
        # The Gradescope tree's own hidden tests and sources are what a submission would want there.
        cls.paths["read"] += [cls.fake / "source" / "tests" / "autograder" / "worksheet1_hidden_test.cpp"]
        cls.paths["write"] += [cls.fake / "source" / "tools" / f"hostile_{TOKEN}.py"]

    @classmethod
    def tearDownClass(cls):
        cls.listener.close()
        end_leftovers([p for p, _ in own_children()] + processes_named(TOKEN))
        super().tearDownClass()

    def run_autograder(self, files):
        submission = self.fake / "submission"
        shutil.rmtree(submission, ignore_errors=True)
        shutil.rmtree(self.fake / "results", ignore_errors=True)
        write_submission(submission, files)
        proc = subprocess.run([str(self.fake / "source" / "run_autograder")], cwd=self.tmp, capture_output=True,
                              text=True, errors="replace", timeout=900,
                              env={**os.environ, "GPL_AUTOGRADER_ROOT": str(self.fake)})
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:] + proc.stderr[-3000:])
        results = self.fake / "results" / "results.json"
        written = results.read_bytes()
        self.assertEqual(own_children(), [], "processes left running when run_autograder ended")
        time.sleep(SETTLE)
        left = own_children() + [(p, "") for p in processes_named(TOKEN)]
        end_leftovers([p for p, _ in left])
        self.assertEqual(left, [], f"processes running {SETTLE:g} s after run_autograder ended")
        self.assertEqual(results.read_bytes(), written, "results.json rewritten after run_autograder ended")
        check = subprocess.run([sys.executable, str(CHECK_GRADESCOPE), str(results)], capture_output=True, text=True)
        self.assertEqual(check.returncode, 0, check.stdout)
        return json.loads(written)

    def full_marks(self):
        """The static initializer's submission, graded once: the reference otherwise, it earns full
        marks over the whole course, and the bundle's checks of a full-marks grading (hidden tests
        after publishing) are made on it, so that the course is graded whole once for both."""
        cls = type(self)
        if not hasattr(cls, "hostile"):
            self.assertEqual(self.made.returncode, 0, self.made.stdout[-2000:] + self.made.stderr[-2000:])
            self.assertEqual(self.setup.returncode, 0, self.setup.stdout[-3000:] + self.setup.stderr[-3000:])
            cls.hostile = self.run_autograder({"integrator.cpp": SAW,
                                               "sphere_plane.cpp": static_attack(self.paths, self.listener.port)})
        return cls.hostile

    def test_hostile_then_honest(self):
        """The static initializer's submission (the reference otherwise: full marks over the whole
        course), then the untouched stubs (zero) in the same tree: a daemon left by the first would
        rewrite the second's results.json, which is the file it aims at."""
        tests = trusted_tests()
        hostile = self.full_marks()
        honest = self.run_autograder({name: STUB[name] for name in hooks.hook_files()})
        for name, data, score in (("hostile", hostile, sum(t["points"] for t in tests)), ("honest", honest, 0)):
            with self.subTest(submission=name):
                self.assertEqual(sorted(t["name"] for t in data["tests"]), sorted(t["name"] for t in tests))
                self.assertEqual(data["score"], score,
                                 [(t["name"], t["output"][:300]) for t in data["tests"] if t["status"] != "passed"])
                self.assertIn("sandbox: each test ran in bubblewrap", data["output"])
        self.assertFalse(self.paths["marker"].exists(), "the submission's daemon ran")
        for path in self.paths["write"]:
            self.assertFalse(path.exists(), f"a submission wrote {path}")
        self.assertEqual(self.listener.connections, [])
        self.assertEqual(source_digest(self.fake / "source"), self.source_before,
                         "a submission changed the autograder's files")


if __name__ == "__main__":
    unittest.main()
