#include "graded.h"

#include <execinfo.h>
#include <fcntl.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstddef>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>

namespace gpl::grading {
namespace {

std::vector<GradedTest>& registry() {
    static std::vector<GradedTest> tests;
    return tests;
}

// "Name" means the test of the same suite; "Suite.Name" any test.
std::string qualified(const std::string& suite, const std::string& test) {
    return test.find('.') == std::string::npos ? suite + "." + test : test;
}

// ---- Where a test was when it crashed, ran out of time or broke a limit -------------------------
// When the grader sets GPL_GRADER_TRACE to a file, a crash signal, the SIGUSR1 it sends at a limit
// it watches (time, memory, threads), or the signal the kernel sends at a limit it keeps (CPU time:
// SIGXCPU, file size: SIGXFSZ, a forbidden system call: SIGSYS) writes the call stack there (names
// need the executable's symbols exported, which CMake does for the autograders) and then ends the
// process as the signal would have. The grader reads the innermost student hook from it. Only
// async-signal-safe calls happen in the handler.

int traceFd = -1;
constexpr int kTracedSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGUSR1, SIGXCPU, SIGXFSZ, SIGSYS};

// What a forbidden system call tried, as the filter below tags it (SECCOMP_RET_DATA).
constexpr unsigned kStartsProcess = 1;
constexpr unsigned kOpensNetwork = 2;

void writeText(const char* text) {
    if (write(traceFd, text, std::strlen(text)) < 0) return;  // nothing else to do in a handler
}

void writeTrace(int signal, siginfo_t* info, void*) {
    // The grader's and the CPU limit's signals are sent to the whole process, and any thread may take
    // them; the main thread's stack is the one that leads into the test and its hooks.
    const long mainThread = getpid();
    if ((signal == SIGUSR1 || signal == SIGXCPU) && syscall(SYS_gettid) != mainThread) {
        syscall(SYS_tgkill, mainThread, mainThread, signal);
        return;
    }
    if (signal == SIGSYS && info) {
        writeText(info->si_errno == kOpensNetwork ? "grader: forbidden system call: network\n"
                                                  : "grader: forbidden system call: process\n");
    }
    void* frames[64];
    const int n = backtrace(frames, 64);
    backtrace_symbols_fd(frames, n, traceFd);
    ::signal(signal, SIG_DFL);
    raise(signal);
}

void installTraceHandlers() {
    const char* path = std::getenv("GPL_GRADER_TRACE");
    if (!path || !*path) return;
    traceFd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (traceFd < 0) return;
    void* warmUp[1];
    backtrace(warmUp, 1);  // loads what backtrace() needs now, not inside a signal handler
    // A stack overflow (endless recursion) leaves no stack for the handler: give it its own.
    static char altStack[1 << 16];
    stack_t stack{};
    stack.ss_sp = altStack;
    stack.ss_size = sizeof altStack;
    sigaltstack(&stack, nullptr);
    struct sigaction action {};
    action.sa_sigaction = writeTrace;
    action.sa_flags = SA_ONSTACK | SA_SIGINFO;
    sigemptyset(&action.sa_mask);
    for (int s : kTracedSignals) sigaction(s, &action, nullptr);
}

// ---- What graded code may not do -----------------------------------------------------------------
// When the grader sets GPL_GRADER_SANDBOX, a seccomp filter refuses two kinds of system call before
// any test runs: starting a process (fork, vfork, exec, a clone that is not a thread) and opening a
// socket other than a local one (the network). The call is not made; the kernel raises SIGSYS, and
// the trace says which kind it was. Threads stay allowed (their number is the grader's to watch).
// The runtime's own helpers keep working: the sanitizers' leak checker clones with a shared memory
// and no vfork, which is allowed; posix_spawn (vfork) is not.

constexpr sock_filter statement(unsigned short code, unsigned k) { return {code, 0, 0, k}; }
constexpr sock_filter jump(unsigned short code, unsigned k, unsigned char ifTrue, unsigned char ifFalse) {
    return {code, ifTrue, ifFalse, k};
}

bool installSandboxFilter() {
    constexpr unsigned kAllow = SECCOMP_RET_ALLOW;
    constexpr unsigned kProcess = SECCOMP_RET_TRAP | kStartsProcess;
    constexpr unsigned kNetwork = SECCOMP_RET_TRAP | kOpensNetwork;
    constexpr unsigned kNoClone3 = SECCOMP_RET_ERRNO | ENOSYS;  // the C library then uses clone
    constexpr unsigned kLoadNumber = BPF_LD | BPF_W | BPF_ABS;
    constexpr unsigned kNumber = offsetof(seccomp_data, nr);
    constexpr unsigned kFirstArgument = offsetof(seccomp_data, args);  // its low 32 bits
    constexpr unsigned short kIs = BPF_JMP | BPF_JEQ | BPF_K, kHas = BPF_JMP | BPF_JSET | BPF_K;
    constexpr unsigned short kAtLeast = BPF_JMP | BPF_JGE | BPF_K, kReturn = BPF_RET | BPF_K;
    const sock_filter program[] = {
        // Only this machine's own system-call table; the 32-bit and x32 ones are refused.
        statement(kLoadNumber, offsetof(seccomp_data, arch)),
        jump(kIs, AUDIT_ARCH_X86_64, 1, 0),
        statement(kReturn, kProcess),
        statement(kLoadNumber, kNumber),
        jump(kAtLeast, 0x40000000, 0, 1),
        statement(kReturn, kProcess),
        // clone: a thread, or a shared-memory helper that does not vfork, is allowed.
        jump(kIs, SYS_clone, 0, 6),
        statement(kLoadNumber, kFirstArgument),
        jump(kHas, CLONE_THREAD, 3, 0),
        jump(kHas, CLONE_VM, 0, 1),
        jump(kHas, CLONE_VFORK, 0, 1),
        statement(kReturn, kProcess),
        statement(kReturn, kAllow),
        statement(kLoadNumber, kNumber),
        jump(kIs, SYS_clone3, 0, 1),
        statement(kReturn, kNoClone3),
        // socket: local (AF_UNIX) only.
        jump(kIs, SYS_socket, 0, 4),
        statement(kLoadNumber, kFirstArgument),
        jump(kIs, AF_UNIX, 1, 0),
        statement(kReturn, kNetwork),
        statement(kReturn, kAllow),
        statement(kLoadNumber, kNumber),
        jump(kIs, SYS_fork, 4, 0),
        jump(kIs, SYS_vfork, 3, 0),
        jump(kIs, SYS_execve, 2, 0),
        jump(kIs, SYS_execveat, 1, 0),
        statement(kReturn, kAllow),
        statement(kReturn, kProcess),
    };
    const sock_fprog filter{static_cast<unsigned short>(sizeof program / sizeof program[0]),
                            const_cast<sock_filter*>(program)};
    return prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) == 0 &&
           prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &filter, 0, 0) == 0;
}

// The manifest, or an error naming a declaration the grader could not use.
nlohmann::json manifest(std::string& error) {
    nlohmann::json tests = nlohmann::json::array();
    for (const auto& t : registry()) {
        for (const auto& d : t.dependsOn) {
            const bool known = std::any_of(registry().begin(), registry().end(),
                                           [&](const GradedTest& other) { return other.name == d; });
            if (!known) error = t.name + " depends on " + d + ", which is not a graded test";
            if (d == t.name) error = t.name + " depends on itself";
        }
        tests.push_back({{"name", t.name},
                         {"worksheet", t.worksheet},
                         {"points", t.points},
                         {"hint", t.hint},
                         {"time_limit", t.timeLimit},
                         {"memory_limit", t.memoryLimit},
                         {"thread_limit", t.threadLimit},
                         {"file_limit", t.fileLimit},
                         {"depends_on", t.dependsOn},
                         {"hidden", t.hidden}});
    }
    return tests;
}

}  // namespace

bool registerTest(const char* suite, const char* name, double points, const char* hint,
                  const std::vector<Option>& options) {
    int worksheet = 0;
    for (const char* c = suite; *c; ++c) {
        if (std::isdigit(static_cast<unsigned char>(*c))) worksheet = worksheet * 10 + (*c - '0');
    }
    GradedTest test;
    test.name = std::string(suite) + "." + name;
    test.worksheet = worksheet;
    test.points = points;
    test.hint = hint;
    for (const Option& o : options) {
        switch (o.kind) {
            case Option::Kind::TimeLimit:
                test.timeLimit = o.value;
                break;
            case Option::Kind::MemoryLimit:
                test.memoryLimit = o.value;
                break;
            case Option::Kind::ThreadLimit:
                test.threadLimit = o.value;
                break;
            case Option::Kind::FileLimit:
                test.fileLimit = o.value;
                break;
            case Option::Kind::DependsOn:
                test.dependsOn.push_back(qualified(suite, o.test));
                break;
            case Option::Kind::Hidden:
                test.hidden = true;
                break;
        }
    }
    registry().push_back(test);
    return true;
}

const std::vector<GradedTest>& gradedTests() { return registry(); }

}  // namespace gpl::grading

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--grader-manifest") == 0) {
            std::string error;
            const nlohmann::json tests = gpl::grading::manifest(error);
            if (!error.empty()) {
                std::cerr << "graded tests: " << error << '\n';
                return 1;
            }
            std::cout << tests.dump(2) << '\n';
            return 0;
        }
    }
    gpl::grading::installTraceHandlers();
    const char* sandbox = std::getenv("GPL_GRADER_SANDBOX");
    if (sandbox && *sandbox && !gpl::grading::installSandboxFilter()) {
        std::cerr << "grader: could not install the sandbox's system-call filter: " << std::strerror(errno) << '\n';
        return 3;
    }
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
