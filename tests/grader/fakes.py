"""Small programs the grader's own tests run in place of the real ones: a probe of the launcher's
system-call filter, and a fake engine and checker that speak a one-word protocol over the same two
pipes (fd 3 and 4) as gpl-checker and gpl-hooks-VARIANT, so that every way an engine can end is
tried in a second. The C programs are compiled by the tests (cc), into a temporary folder."""
import pathlib
import subprocess
import sys

# ---- The launcher's probe: `probe WHAT` makes one system call; the filter's tag is printed ---------
PROBE_C = r'''#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <linux/perf_event.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/mount.h>
#include <sys/personality.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/shm.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <sys/wait.h>
#include <unistd.h>

static void onSigsys(int s, siginfo_t* info, void* c) {
    (void)s; (void)c;
    char text[64];
    int n = snprintf(text, sizeof text, "refused %d\n", info->si_errno);
    write(1, text, n);
    _exit(99);
}
static void* idle(void* a) { return a; }
// A thread made by clone(CLONE_VM) runs on a stack of its own and ends at once: sharing the caller's
// stack, it would return into the caller's frames while the caller runs on them.
static int quiet(void* a) { (void)a; return 0; }
static char cloneStack[1 << 16] __attribute__((aligned(16)));
static const char* early;
__attribute__((constructor)) static void before_main(void) {
    struct sigaction sa; memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = onSigsys; sa.sa_flags = SA_SIGINFO;
    sigaction(SIGSYS, &sa, 0);
    early = getenv("PROBE_EARLY");
    if (early && !strcmp(early, "fork")) { fork(); write(1, "forked\n", 7); }
}
int main(int argc, char** argv) {
    const char* what = argc > 1 ? argv[1] : "hello";
    long r = 0;
    char* none[] = {"true", 0};
    if (!strcmp(what, "exists")) { for (int i = 2; i < argc; ++i) printf("%s\n", access(argv[i], F_OK) == 0 ? "True" : "False"); return 0; }
    if (!strcmp(what, "getenv")) { const char* v = getenv(argv[2]); printf("%s\n", v ? v : "(none)"); return 0; }
    if (!strcmp(what, "cat")) { FILE* f = fopen(argv[2], "r"); int c; if (!f) return 4; while ((c = fgetc(f)) != EOF) putchar(c); return 0; }
    if (!strcmp(what, "hello")) { printf("hello pid=%d fds1000=%d\n", getpid(), fcntl(1000, F_GETFD)); return 0; }
    else if (!strcmp(what, "threads")) { pthread_t t[8]; for (int i = 0; i < 8; ++i) if (pthread_create(&t[i], 0, idle, 0)) return 2; for (int i = 0; i < 8; ++i) pthread_join(t[i], 0); printf("threads ok\n"); return 0; }
    else if (!strcmp(what, "fork")) r = fork();
    else if (!strcmp(what, "vfork")) r = syscall(SYS_vfork);
    else if (!strcmp(what, "clone")) r = syscall(SYS_clone, SIGCHLD, 0, 0, 0, 0);
    else if (!strcmp(what, "clone_vm")) r = clone(quiet, cloneStack + sizeof cloneStack, CLONE_VM | CLONE_FS | CLONE_FILES | CLONE_UNTRACED, 0);
    else if (!strcmp(what, "clone_newuser")) r = syscall(SYS_clone, CLONE_NEWUSER | SIGCHLD, 0, 0, 0, 0);
    else if (!strcmp(what, "execve")) r = execv("/bin/true", none);
    else if (!strcmp(what, "execveat_abs")) r = syscall(SYS_execveat, 1000, "/bin/true", none, none, AT_EMPTY_PATH);
    else if (!strcmp(what, "execveat_null")) r = syscall(SYS_execveat, 1000, NULL, none, none, AT_EMPTY_PATH);
    else if (!strcmp(what, "dup1000")) { r = dup2(1, 1000); printf("dup2 -> %ld %s\n", r, strerror(errno)); return 0; }
    else if (!strcmp(what, "raise_nofile")) { struct rlimit l = {2000, 2000}; r = setrlimit(RLIMIT_NOFILE, &l); }
    else if (!strcmp(what, "prlimit_nofile")) { struct rlimit l = {2000, 2000}; r = prlimit(0, RLIMIT_NOFILE, &l, 0); }
    else if (!strcmp(what, "prlimit_other")) { struct rlimit l = {1, 1}; r = prlimit(1, RLIMIT_CPU, &l, 0); }
    else if (!strcmp(what, "getrlimit")) { struct rlimit l; r = getrlimit(RLIMIT_NOFILE, &l); printf("nofile %ld %ld\n", (long)l.rlim_cur, (long)l.rlim_max); r = prlimit(0, RLIMIT_NOFILE, 0, &l); printf("prlimit read %ld\n", r); struct rlimit c = {0, 0}; r = setrlimit(RLIMIT_CORE, &c); printf("core %ld\n", r); return 0; }
    else if (!strcmp(what, "socket")) r = socket(AF_INET, SOCK_STREAM, 0);
    else if (!strcmp(what, "unix")) r = socket(AF_UNIX, SOCK_STREAM, 0);
    else if (!strcmp(what, "socketpair")) { int sv[2]; r = socketpair(AF_UNIX, SOCK_STREAM, 0, sv); }
    else if (!strcmp(what, "unshare")) r = unshare(CLONE_NEWUSER);
    else if (!strcmp(what, "setns")) r = setns(0, 0);
    else if (!strcmp(what, "mount")) r = mount("none", "/proc/gpl-no-folder-here", "tmpfs", 0, 0);  /* harmless where the filter is missing */
    else if (!strcmp(what, "chroot")) r = chroot("/");
    else if (!strcmp(what, "memfd")) r = memfd_create("x", 0);
    else if (!strcmp(what, "shmget")) r = shmget(IPC_PRIVATE, 4096, IPC_CREAT | 0600);
    else if (!strcmp(what, "io_uring")) r = syscall(SYS_io_uring_setup, 4, 0);
    else if (!strcmp(what, "bpf")) r = syscall(SYS_bpf, 0, 0, 0);
    else if (!strcmp(what, "perf")) r = syscall(SYS_perf_event_open, 0, 0, -1, -1, 0);
    else if (!strcmp(what, "userfaultfd")) r = syscall(SYS_userfaultfd, 0);
    else if (!strcmp(what, "ptrace")) r = ptrace(PTRACE_TRACEME, 0, 0, 0);
    else if (!strcmp(what, "vm_read")) { char b[4]; struct iovec l = {b, 4}, rr = {b, 4}; r = process_vm_readv(1, &l, 1, &rr, 1, 0); }
    else if (!strcmp(what, "keyctl")) r = syscall(SYS_keyctl, 0, 0, 0, 0, 0);
    else if (!strcmp(what, "personality")) r = personality(ADDR_NO_RANDOMIZE);
    else if (!strcmp(what, "personality_ask")) { r = personality(0xffffffff); printf("persona %lx\n", r); return 0; }
    else if (!strcmp(what, "kill_other")) r = kill(1, 0);
    else if (!strcmp(what, "kill_group")) r = kill(-1, 0);
    else if (!strcmp(what, "kill_self")) { r = kill(getpid(), 0); printf("kill self %ld\n", r); return 0; }
    else if (!strcmp(what, "tgkill_other")) r = syscall(SYS_tgkill, 1, 1, 0);
    else if (!strcmp(what, "raise")) { signal(SIGUSR1, SIG_IGN); r = raise(SIGUSR1); printf("raise %ld\n", r); return 0; }
    else if (!strcmp(what, "pidfd_other")) r = syscall(SYS_pidfd_open, 1, 0);
    else if (!strcmp(what, "clone3_thread")) { r = syscall(SYS_clone3, 0, 0); printf("clone3 %ld %s\n", r, strerror(errno)); return 0; }
    else { printf("unknown %s\n", what); return 3; }
    printf("allowed: %s -> %ld (%s)\n", what, r, strerror(errno));
    return 0;
}
'''

# ---- A fake engine: reads a word per request from fd 3, does it, answers "ok" on fd 4 --------------
RUNNER_C = r'''/* A fake engine: reads a word per request from fd 3, acts, answers "ok\n" on fd 4. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>
static int traceFd = -1;
static volatile int stacky, fakestack;
static void handler(int s, siginfo_t* info, void* c) {
    (void)c;
    if (traceFd >= 0) {
        const char* tags[] = {"?", "process", "network", "namespace", "memory", "kernel", "signal", "limit"};
        if (s == SIGSYS) { dprintf(traceFd, "grader: forbidden system call: %s\n", info->si_errno >= 1 && info->si_errno <= 7 ? tags[info->si_errno] : "?"); }
        if (s == SIGSEGV && stacky) dprintf(traceFd, "grader: stack overflow\n");
        dprintf(traceFd, fakestack ? "./gpl-hooks(_ZN3gpl13PhysicsEngine18simulationTimestepEv+0x2a)[0x56]\n"
                                   : "./gpl-hooks(_ZN3gpl13PhysicsEngine10integratorEv+0x2a)[0x56]\n");
    }
    signal(s, SIG_DFL); raise(s);
}
static void* sleeper(void* a) { sleep(10); return a; }
static void* napper(void* a) { usleep(300000); return a; }
static int recurse(int n) { volatile char buf[4096]; buf[0] = n; return recurse(n + 1) + buf[0]; }
__attribute__((constructor)) static void init(void) {
    const char* p = getenv("GPL_GRADER_TRACE");
    if (p) traceFd = open(p, O_WRONLY | O_CLOEXEC);
    static char alt[1 << 16]; stack_t st = {.ss_sp = alt, .ss_size = sizeof alt}; sigaltstack(&st, 0);
    struct sigaction sa; memset(&sa, 0, sizeof sa); sa.sa_sigaction = handler; sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
    int sigs[] = {SIGSEGV, SIGABRT, SIGSYS, SIGXCPU, SIGXFSZ, SIGUSR1};
    for (unsigned i = 0; i < sizeof sigs / sizeof *sigs; ++i) sigaction(sigs[i], &sa, 0);
}
int main(int argc, char** argv) {
    if (argc < 2 || strcmp(argv[1], "--serve")) return 2;
    FILE* in = fdopen(3, "r");
    char word[64];
    while (fscanf(in, "%63s", word) == 1) {
        if (!strcmp(word, "crash")) *(volatile int*)0 = 1;
        else if (!strcmp(word, "loop")) for (;;) {}
        else if (!strcmp(word, "sleep")) sleep(100);
        else if (!strcmp(word, "work")) { while (clock() < CLOCKS_PER_SEC) {} }  /* a second of CPU time */
        else if (!strcmp(word, "fork")) fork();
        else if (!strcmp(word, "socket")) socket(AF_INET, SOCK_STREAM, 0);
        else if (!strcmp(word, "memfd")) memfd_create("x", 0);
        else if (!strcmp(word, "print")) for (;;) printf("debug: x = 1\n");
        else if (!strcmp(word, "exit")) exit(3);
        else if (!strcmp(word, "abort")) { fprintf(stderr, "runner: x.cpp:3: void gpl::PhysicsEngine::integrator(): Assertion `false' failed.\n"); abort(); }
        else if (!strcmp(word, "memory")) { for (;;) { char* p = malloc(1 << 20); memset(p, 1, 1 << 20); } }
        else if (!strcmp(word, "threads")) { pthread_t t; for (int i = 0; i < 64; ++i) pthread_create(&t, 0, sleeper, 0); sleep(10); }
        else if (!strcmp(word, "file")) { FILE* f = fopen("dump.bin", "wb"); char b[1 << 16] = {0}; for (int i = 0; i < 2000; ++i) fwrite(b, 1, sizeof b, f); fclose(f); }
        else if (!strcmp(word, "stack")) { stacky = 1; recurse(0); }
        else if (!strcmp(word, "fakestack")) { fakestack = 1; *(volatile int*)0 = 1; }
        else if (!strcmp(word, "nonsense")) { write(4, "nonsense\n", 9); continue; }
        else if (!strcmp(word, "eight")) { pthread_t t[7]; for (int i = 0; i < 7; ++i) if (pthread_create(&t[i], 0, napper, 0)) abort(); for (int i = 0; i < 7; ++i) pthread_join(t[i], 0); }
        else if (!strcmp(word, "survive")) { /* a detached thread that tries to outlive the test */ pthread_t t; pthread_create(&t, 0, sleeper, 0); }
        write(4, "ok\n", 3);
    }
    return 0;
}
'''

# ---- A fake checker: test Fake.Word sends "word" and passes when the engine answers "ok" ----------
CHECKER_PY = r'''#!/usr/bin/env python3
"""A fake checker: test Fake.<Word> sends <word> to the engine and passes iff it answers ok."""
import json, os, signal, sys
status = os.environ.get("GPL_CHECKER_STATUS")
call = None
def note(event, **kw):
    if status:
        with open(status, "a") as f:
            f.write(json.dumps({"event": event, "call": call, **kw}) + "\n")
signal.signal(signal.SIGUSR2, lambda *a: note("waiting"))
if "--grader-manifest" in sys.argv:
    print(json.dumps([{"name": f"Fake.{w}", "worksheet": 1, "points": 1, "hint": "a hint long enough to read",
                       "time_limit": 0, "memory_limit": 0, "thread_limit": 0, "file_limit": 0, "depends_on": [], "hidden": False}
                      for w in ("Ok", "Crash")]))
    sys.exit(0)
test = next(a.split("=", 1)[1] for a in sys.argv if a.startswith("--gtest_filter="))
out = next(a.split("json:", 1)[1] for a in sys.argv if a.startswith("--gtest_output="))
suite, name = test.split(".")
failures = []
call = "simulationTimestep()" if name.lower() == "stack" else "integrator()"
os.write(4, name.lower().encode() + b"\n")
reply = b""
while not reply.endswith(b"\n"):
    chunk = os.read(3, 100)
    if not chunk:
        note("ended", detail="the engine closed its pipe")
        failures.append({"failure": "x.cpp:1\nthe engine stopped answering in integrator()", "type": ""})
        break
    reply += chunk
if reply and reply != b"ok\n":
    note("ended", detail="the answer is not one")
    failures.append({"failure": "x.cpp:1\nnonsense", "type": ""})
call = None
json.dump({"tests": 1, "failures": len(failures), "testsuites": [{"name": suite, "testsuite": [
    {"name": name, "classname": suite, "status": "RUN", "result": "COMPLETED", "failures": failures}]}]}, open(out, "w"))
sys.exit(1 if failures else 0)
'''


def build(folder):
    """Compiles the probe and the fake engine into folder and writes the fake checker; returns
    {"probe": path, "engine": path, "checker": path}."""
    folder = pathlib.Path(folder)
    made = {}
    for name, source, flags in (("probe", PROBE_C, ["-pthread"]), ("engine", RUNNER_C, ["-pthread"])):
        (folder / f"{name}.c").write_text(source)
        subprocess.run(["cc", "-O1", *flags, "-o", str(folder / name), str(folder / f"{name}.c")], check=True,
                       capture_output=True)
        made[name] = folder / name
    checker = folder / "checker"
    # This Python, not whichever comes first on PATH (a pyenv shim there takes seconds to start).
    checker.write_text(CHECKER_PY.replace("#!/usr/bin/env python3", f"#!{sys.executable}", 1))
    checker.chmod(0o755)
    made["checker"] = checker
    return made
