// gpl-launch: starts a graded test's untrusted runner with its limits and the system-call filter in
// force before the runner's first instruction (its static initializers included).
//
//   gpl-launch [--cgroup DIR]... [--cpu SECONDS] [--file-bytes N] [--sanitizer] [--drop-user]
//              [--chdir DIR] [--join-only] -- PROGRAM ARGS...
//
// In order: joins each cgroup DIR (writes its own pid to DIR/cgroup.procs; the pid stays across
// exec, so PROGRAM and everything it starts are counted there); with --join-only it then simply
// executes PROGRAM (the grader puts bubblewrap there, which runs this launcher again inside the
// sandbox). Otherwise: sets the kernel's limits (CPU seconds, bytes per file, no core files, 256
// open files, an 8 MiB stack), changes to DIR (--chdir), with --drop-user and when running as
// root becomes nobody (65534), opens PROGRAM as file descriptor 1000 (close-on-exec, and above
// the 256 files the program may open: it can never make a descriptor 1000 of its own), installs
// the filter (no new privileges) and executes PROGRAM through that descriptor: execveat(1000,
// NULL, ..., AT_EMPTY_PATH) from one instruction of the launcher, the only exec the filter lets
// through (on kernels before 6.11, which refuse a NULL path, an empty string at an address drawn
// at random). After it, no program can be executed any more.
//
// The filter (x86_64 only; other system-call tables and x32 end the process) refuses, raising
// SIGSYS with a tag in si_errno that the runner's handler names ("grader: forbidden system call:
// TAG"):
//   process    fork, vfork, execve, every other execveat, clone other than a thread (with
//              --sanitizer also exactly LeakSanitizer's tracer: CLONE_VM|CLONE_FS|CLONE_FILES|
//              CLONE_UNTRACED), ptrace (allowed with --sanitizer), process_vm_readv/writev, kcmp,
//              pidfd_getfd
//   network    socket, socketpair
//   namespace  unshare, setns, clone with a CLONE_NEW* flag, mount and its relatives, chroot
//   memory     memfd_create, memfd_secret, System V shared memory and message queues, POSIX
//              message queues (memory that is nobody's resident memory)
//   kernel     io_uring, bpf, perf_event_open, userfaultfd, the key ring, personality (other than
//              asking), modules, kexec, reboot, swap, clock and syslog changes
//   signal     kill, tkill, tgkill, rt_(tg)sigqueueinfo and pidfd_open aimed at another process
//              (its own pid, as the launcher had it and the program keeps, or 0 only)
//   limit      raising the open-files limit (setrlimit/prlimit64 of RLIMIT_NOFILE)
// clone3 fails with ENOSYS (the C library falls back to clone, which the filter can inspect).
//
// Exit status: 125 when the launcher itself cannot do its work (a message on stderr).
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <grp.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <sched.h>
#include <signal.h>
#include <stddef.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#ifndef __x86_64__
#error "gpl-launch's system-call filter is written for x86_64"
#endif

namespace {

constexpr int kProgramFd = 1000;
constexpr rlim_t kOpenFiles = 256;
constexpr rlim_t kStackBytes = 8u << 20;
constexpr uid_t kNobody = 65534;

// The tags of refused calls (SECCOMP_RET_DATA, seen by the handler as si_errno).
enum Tag : unsigned { kProcess = 1, kNetwork = 2, kNamespace = 3, kMemory = 4, kKernel = 5, kSignal = 6, kLimit = 7 };

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "gpl-launch: %s\n", what.c_str());
    std::exit(125);
}

[[noreturn]] void failErrno(const std::string& what) { fail(what + ": " + std::strerror(errno)); }

// ---- The exec through descriptor 1000 -------------------------------------------------------------
// The system call is made from this one instruction; the filter lets an execveat through only from
// its address (seccomp reports the address after the instruction), which the program executed
// afterwards cannot know (address-space randomisation) and which is gone once it runs.
extern "C" long gpl_launch_execveat(long dirfd, const char* path, char* const* argv, char* const* envp, long flags);
extern "C" char gpl_launch_after_execveat[];
asm(".text\n"
    ".globl gpl_launch_execveat\n"
    ".type gpl_launch_execveat, @function\n"
    "gpl_launch_execveat:\n"
    "  mov %rcx, %r10\n"
    "  mov $322, %eax\n"  // SYS_execveat
    "  syscall\n"
    ".globl gpl_launch_after_execveat\n"
    "gpl_launch_after_execveat:\n"
    "  ret\n"
    ".size gpl_launch_execveat, .-gpl_launch_execveat\n");
static_assert(SYS_execveat == 322, "x86_64's execveat");

// Whether the kernel accepts execveat(fd, NULL, ..., AT_EMPTY_PATH) (Linux 6.11 and later): asked
// with a descriptor that is not open, so nothing is executed (EBADF: yes; EFAULT: the NULL path
// was refused first). Where it does not, the path is an empty string at an address drawn at random.
bool kernelTakesNullPath() {
    char* none[] = {nullptr};
    const long r = syscall(SYS_execveat, 999, nullptr, none, none, AT_EMPTY_PATH);
    return r < 0 && errno == EBADF;
}

const char* emptyPathAtRandom() {
    std::uint64_t r = 0;
    if (syscall(SYS_getrandom, &r, sizeof r, 0) != static_cast<long>(sizeof r)) failErrno("getrandom");
    // A page somewhere in the lower half of the user address space, the string anywhere in it.
    void* hint = reinterpret_cast<void*>(((r >> 12) % (1ull << 34) + (1ull << 20)) << 12);
    void* page = mmap(hint, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED_NOREPLACE, -1, 0);
    if (page == MAP_FAILED) page = mmap(nullptr, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (page == MAP_FAILED) failErrno("mmap");
    char* empty = static_cast<char*>(page) + (r & 4095);
    *empty = '\0';
    return empty;
}

// ---- The filter -------------------------------------------------------------------------------------

class Filter {
public:
    void add(sock_filter f) { program_.push_back(f); }
    void load(unsigned offset) { add({BPF_LD | BPF_W | BPF_ABS, 0, 0, offset}); }
    void ret(unsigned value) { add({BPF_RET | BPF_K, 0, 0, value}); }
    // if (A == k) skip `t` instructions else skip `f`
    void jeq(unsigned k, unsigned char t, unsigned char f) { add({BPF_JMP | BPF_JEQ | BPF_K, t, f, k}); }
    void jset(unsigned k, unsigned char t, unsigned char f) { add({BPF_JMP | BPF_JSET | BPF_K, t, f, k}); }
    void jge(unsigned k, unsigned char t, unsigned char f) { add({BPF_JMP | BPF_JGE | BPF_K, t, f, k}); }
    void andk(unsigned k) { add({BPF_ALU | BPF_AND | BPF_K, 0, 0, k}); }
    std::vector<sock_filter>& program() { return program_; }

private:
    std::vector<sock_filter> program_;
};

constexpr unsigned kAllow = SECCOMP_RET_ALLOW;
constexpr unsigned trap(Tag tag) { return SECCOMP_RET_TRAP | tag; }
constexpr unsigned kNr = offsetof(seccomp_data, nr);
constexpr unsigned argLow(int i) { return offsetof(seccomp_data, args) + 8 * i; }
constexpr unsigned argHigh(int i) { return offsetof(seccomp_data, args) + 8 * i + 4; }
constexpr unsigned kIpLow = offsetof(seccomp_data, instruction_pointer);
constexpr unsigned kIpHigh = offsetof(seccomp_data, instruction_pointer) + 4;

// A block for one system call: "if nr == number: <body>", where the body ends in returns. The jump
// over the body is patched when the body is known.
template <typename Body>
void forCall(Filter& f, long number, Body body) {
    f.load(kNr);
    f.jeq(static_cast<unsigned>(number), 0, 0);
    const size_t at = f.program().size() - 1;
    body();
    const size_t skip = f.program().size() - at - 1;
    if (skip > 255) fail("filter block too long");
    f.program()[at].jf = static_cast<unsigned char>(skip);
}

// Returns `verdict` unless the 64-bit argument (or value at offsets low/high) equals `value`, in
// which case it goes on with the next instruction.
void requireEqual(Filter& f, unsigned low, unsigned high, std::uint64_t value, unsigned verdict) {
    f.load(low);
    f.jeq(static_cast<unsigned>(value), 1, 0);
    f.ret(verdict);
    f.load(high);
    f.jeq(static_cast<unsigned>(value >> 32), 1, 0);
    f.ret(verdict);
}

struct Options {
    std::vector<std::string> cgroups;
    long cpu = 0;
    long long fileBytes = 0;
    bool sanitizer = false;
    bool dropUser = false;
    bool joinOnly = false;
    std::string chdirTo;
    char** program = nullptr;
};

std::vector<sock_filter> buildFilter(const Options& o, pid_t self, const char* path, bool nullPath) {
    Filter f;
    // Only this machine's own system-call table: the 32-bit one and x32 end the process.
    f.load(offsetof(seccomp_data, arch));
    f.jeq(AUDIT_ARCH_X86_64, 1, 0);
    f.ret(SECCOMP_RET_KILL_PROCESS);
    f.load(kNr);
    f.jge(0x40000000, 0, 1);
    f.ret(SECCOMP_RET_KILL_PROCESS);

    // The calls of every moment first, so that they pass after a few instructions.
    for (long nr : {SYS_futex, SYS_read, SYS_write, SYS_mmap, SYS_munmap, SYS_mprotect, SYS_brk, SYS_madvise,
                    SYS_clock_gettime, SYS_sched_yield, SYS_close, SYS_openat, SYS_fstat, SYS_newfstatat,
                    SYS_lseek, SYS_rt_sigprocmask, SYS_rt_sigaction, SYS_getpid, SYS_gettid, SYS_exit,
                    SYS_exit_group, SYS_nanosleep, SYS_clock_nanosleep, SYS_pread64, SYS_pwrite64}) {
        f.load(kNr);
        f.jeq(static_cast<unsigned>(nr), 0, 1);
        f.ret(kAllow);
    }

    // execveat: only the launcher's own, through descriptor 1000, from its one instruction.
    forCall(f, SYS_execveat, [&] {
        const unsigned no = trap(kProcess);
        requireEqual(f, argLow(0), argHigh(0), kProgramFd, no);
        requireEqual(f, argLow(1), argHigh(1), reinterpret_cast<std::uint64_t>(nullPath ? nullptr : path), no);
        requireEqual(f, argLow(4), argHigh(4), AT_EMPTY_PATH, no);
        requireEqual(f, kIpLow, kIpHigh, reinterpret_cast<std::uint64_t>(gpl_launch_after_execveat), no);
        f.ret(kAllow);
    });

    // clone: a thread (no new namespaces), or the leak checker's tracer in a sanitizer build.
    constexpr unsigned kNewNamespaces = CLONE_NEWNS | CLONE_NEWCGROUP | CLONE_NEWUTS | CLONE_NEWIPC |
                                        CLONE_NEWUSER | CLONE_NEWPID | CLONE_NEWNET;
    forCall(f, SYS_clone, [&] {
        f.load(argLow(0));
        f.jset(kNewNamespaces, 0, 1);
        f.ret(trap(kNamespace));
        if (o.sanitizer) {
            f.jeq(CLONE_VM | CLONE_FS | CLONE_FILES | CLONE_UNTRACED, 0, 1);
            f.ret(kAllow);
        }
        f.jset(CLONE_THREAD, 1, 0);
        f.ret(trap(kProcess));
        f.jset(CLONE_VM, 1, 0);  // a thread shares the memory (the kernel insists; checked anyway)
        f.ret(trap(kProcess));
        f.ret(kAllow);
    });
    forCall(f, SYS_clone3, [&] { f.ret(SECCOMP_RET_ERRNO | ENOSYS); });

    // Signals: to itself only (its own pid, kept across exec; 0 is its own process group).
    const unsigned me = static_cast<unsigned>(self);
    for (long nr : {SYS_kill, SYS_rt_sigqueueinfo, SYS_pidfd_open}) {
        forCall(f, nr, [&] {
            f.load(argLow(0));
            f.jeq(me, 2, 0);
            f.jeq(0, nr == SYS_pidfd_open ? 0 : 1, 0);
            f.ret(trap(kSignal));
            f.ret(kAllow);
        });
    }
    for (long nr : {SYS_tgkill, SYS_rt_tgsigqueueinfo}) {
        forCall(f, nr, [&] {
            f.load(argLow(0));
            f.jeq(me, 1, 0);
            f.ret(trap(kSignal));
            f.ret(kAllow);
        });
    }
    forCall(f, SYS_tkill, [&] {  // a thread id of its own is not known here: its main thread only
        f.load(argLow(0));
        f.jeq(me, 1, 0);
        f.ret(trap(kSignal));
        f.ret(kAllow);
    });

    // personality: asking (0xffffffff) is allowed, changing it is not.
    forCall(f, SYS_personality, [&] {
        f.load(argLow(0));
        f.jeq(0xffffffffu, 1, 0);
        f.ret(trap(kKernel));
        f.ret(kAllow);
    });

    // The open-files limit keeps descriptor 1000 out of reach: it may not be raised.
    forCall(f, SYS_setrlimit, [&] {
        f.load(argLow(0));
        f.jeq(RLIMIT_NOFILE, 0, 1);
        f.ret(trap(kLimit));
        f.ret(kAllow);
    });
    // prlimit64 with a new limit: its own process only, and never the open-files limit.
    forCall(f, SYS_prlimit64, [&] {
        f.load(argLow(2));
        f.jeq(0, 0, 2);
        f.load(argHigh(2));
        f.jeq(0, 7, 0);  // only asking: allowed
        f.load(argLow(0));
        f.jeq(me, 2, 0);
        f.jeq(0, 1, 0);
        f.ret(trap(kSignal));
        f.load(argLow(1));
        f.jeq(RLIMIT_NOFILE, 0, 1);
        f.ret(trap(kLimit));
        f.ret(kAllow);
    });

    if (o.sanitizer) {
        forCall(f, SYS_ptrace, [&] { f.ret(kAllow); });
    }

    struct Refused {
        long nr;
        Tag tag;
    };
    const Refused refused[] = {
        {SYS_fork, kProcess}, {SYS_vfork, kProcess}, {SYS_execve, kProcess}, {SYS_ptrace, kProcess},
        {SYS_process_vm_readv, kProcess}, {SYS_process_vm_writev, kProcess}, {SYS_kcmp, kProcess},
        {SYS_pidfd_getfd, kProcess},
        {SYS_socket, kNetwork}, {SYS_socketpair, kNetwork},
        {SYS_unshare, kNamespace}, {SYS_setns, kNamespace}, {SYS_mount, kNamespace}, {SYS_umount2, kNamespace},
        {SYS_pivot_root, kNamespace}, {SYS_chroot, kNamespace}, {SYS_open_tree, kNamespace},
        {SYS_move_mount, kNamespace}, {SYS_fsopen, kNamespace}, {SYS_fsconfig, kNamespace},
        {SYS_fsmount, kNamespace}, {SYS_fspick, kNamespace}, {SYS_mount_setattr, kNamespace},
        {SYS_memfd_create, kMemory}, {447 /* memfd_secret */, kMemory}, {SYS_shmget, kMemory},
        {SYS_shmat, kMemory}, {SYS_shmctl, kMemory}, {SYS_shmdt, kMemory}, {SYS_msgget, kMemory},
        {SYS_msgsnd, kMemory}, {SYS_mq_open, kMemory}, {SYS_mq_timedsend, kMemory},
        {SYS_io_uring_setup, kKernel}, {SYS_io_uring_enter, kKernel}, {SYS_io_uring_register, kKernel},
        {SYS_bpf, kKernel}, {SYS_perf_event_open, kKernel}, {SYS_userfaultfd, kKernel}, {SYS_keyctl, kKernel},
        {SYS_add_key, kKernel}, {SYS_request_key, kKernel}, {SYS_init_module, kKernel},
        {SYS_finit_module, kKernel}, {SYS_delete_module, kKernel}, {SYS_kexec_load, kKernel},
        {SYS_kexec_file_load, kKernel}, {SYS_reboot, kKernel}, {SYS_swapon, kKernel}, {SYS_swapoff, kKernel},
        {SYS_syslog, kKernel}, {SYS_acct, kKernel}, {SYS_settimeofday, kKernel}, {SYS_clock_settime, kKernel},
        {SYS_clock_adjtime, kKernel}, {SYS_adjtimex, kKernel}, {SYS_iopl, kKernel}, {SYS_ioperm, kKernel},
        {SYS_quotactl, kKernel}, {SYS_lookup_dcookie, kKernel}, {SYS_fanotify_init, kKernel},
        {SYS_name_to_handle_at, kKernel}, {SYS_open_by_handle_at, kKernel},
    };
    for (const Refused& r : refused) {
        f.load(kNr);
        f.jeq(static_cast<unsigned>(r.nr), 0, 1);
        f.ret(trap(r.tag));
    }
    f.ret(kAllow);
    return std::move(f.program());
}

// ---- Limits -----------------------------------------------------------------------------------------

void setLimit(int resource, rlim_t soft, rlim_t hard, const char* name) {
    rlimit current{};
    if (getrlimit(resource, &current) != 0) failErrno(std::string("getrlimit ") + name);
    // Never above what is in force already (an unprivileged launcher cannot raise a hard limit).
    if (current.rlim_max != RLIM_INFINITY && hard > current.rlim_max) hard = current.rlim_max;
    if (soft > hard) soft = hard;
    const rlimit wanted{soft, hard};
    if (setrlimit(resource, &wanted) != 0) failErrno(std::string("setrlimit ") + name);
}

void joinCgroup(const std::string& dir) {
    const std::string path = dir + "/cgroup.procs";
    const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) failErrno("cannot join the cgroup " + dir);
    const std::string pid = std::to_string(getpid()) + "\n";
    if (write(fd, pid.data(), pid.size()) != static_cast<ssize_t>(pid.size())) failErrno("cannot join the cgroup " + dir);
    close(fd);
}

void dropUser() {
    if (geteuid() != 0) return;  // not root: nothing to give up
    if (setgroups(0, nullptr) != 0) failErrno("setgroups");
    if (setresgid(kNobody, kNobody, kNobody) != 0) failErrno("setresgid");
    if (setresuid(kNobody, kNobody, kNobody) != 0) failErrno("setresuid");
    if (setuid(0) == 0) fail("could not give up root");
}

Options parse(int argc, char** argv) {
    Options o;
    int i = 1;
    auto value = [&](const char* name) -> const char* {
        if (i + 1 >= argc) fail(std::string(name) + " needs a value");
        return argv[++i];
    };
    auto number = [&](const char* name) -> long long {
        const char* text = value(name);
        char* end = nullptr;
        errno = 0;
        const long long n = std::strtoll(text, &end, 10);
        if (errno || end == text || *end || n <= 0) fail(std::string(name) + ": expects a positive whole number, got '" + text + "'");
        return n;
    };
    for (; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--") {
            ++i;
            break;
        } else if (a == "--cgroup") {
            o.cgroups.push_back(value("--cgroup"));
        } else if (a == "--cpu") {
            o.cpu = static_cast<long>(number("--cpu"));
        } else if (a == "--file-bytes") {
            o.fileBytes = number("--file-bytes");
        } else if (a == "--sanitizer") {
            o.sanitizer = true;
        } else if (a == "--drop-user") {
            o.dropUser = true;
        } else if (a == "--chdir") {
            o.chdirTo = value("--chdir");
        } else if (a == "--join-only") {
            o.joinOnly = true;
        } else {
            fail("unknown option '" + a + "' (usage: gpl-launch [--cgroup DIR]... [--cpu S] [--file-bytes N] "
                 "[--sanitizer] [--drop-user] [--chdir DIR] [--join-only] -- PROGRAM ARGS...)");
        }
    }
    if (i >= argc) fail("no program to run (usage: gpl-launch [options] -- PROGRAM ARGS...)");
    o.program = argv + i;
    return o;
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    for (const std::string& dir : o.cgroups) joinCgroup(dir);
    if (o.joinOnly) {
        execv(o.program[0], o.program);
        failErrno(std::string("cannot run ") + o.program[0]);
    }

    if (o.cpu > 0) setLimit(RLIMIT_CPU, static_cast<rlim_t>(o.cpu), static_cast<rlim_t>(o.cpu) + 1, "RLIMIT_CPU");
    if (o.fileBytes > 0) setLimit(RLIMIT_FSIZE, static_cast<rlim_t>(o.fileBytes), static_cast<rlim_t>(o.fileBytes), "RLIMIT_FSIZE");
    setLimit(RLIMIT_CORE, 0, 0, "RLIMIT_CORE");
    setLimit(RLIMIT_STACK, kStackBytes, kStackBytes, "RLIMIT_STACK");
    // The program as descriptor 1000, close-on-exec: gone once the program runs. Opened before
    // giving up root, so that the program need not be readable by nobody (only executable).
    rlimit files{};
    getrlimit(RLIMIT_NOFILE, &files);
    if (files.rlim_cur <= static_cast<rlim_t>(kProgramFd) && files.rlim_max > static_cast<rlim_t>(kProgramFd)) {
        files.rlim_cur = kProgramFd + 1;
        setrlimit(RLIMIT_NOFILE, &files);
    }
    const int fd = open(o.program[0], O_RDONLY | O_CLOEXEC);
    if (fd < 0) failErrno(std::string("cannot open ") + o.program[0]);
    if (fd != kProgramFd) {
        if (dup3(fd, kProgramFd, O_CLOEXEC) != kProgramFd) failErrno("dup3 to descriptor 1000");
        close(fd);
    }
    setLimit(RLIMIT_NOFILE, kOpenFiles, kOpenFiles, "RLIMIT_NOFILE");

    if (!o.chdirTo.empty() && chdir(o.chdirTo.c_str()) != 0) failErrno("cannot change to " + o.chdirTo);
    if (o.dropUser) dropUser();

    const bool nullPath = kernelTakesNullPath();
    const char* path = nullPath ? nullptr : emptyPathAtRandom();
    std::vector<sock_filter> program = buildFilter(o, getpid(), path, nullPath);
    const sock_fprog filter{static_cast<unsigned short>(program.size()), program.data()};
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) failErrno("PR_SET_NO_NEW_PRIVS");
    if (syscall(SYS_seccomp, SECCOMP_SET_MODE_FILTER, 0, &filter) != 0) failErrno("installing the system-call filter");

    extern char** environ;
    errno = static_cast<int>(-gpl_launch_execveat(kProgramFd, path, o.program, environ, AT_EMPTY_PATH));
    failErrno(std::string("cannot run ") + o.program[0]);
}
