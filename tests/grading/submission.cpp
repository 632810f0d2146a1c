#include "submission.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <new>
#include <optional>
#include <utility>

#include "gpl/engine.h"
#include "gpl/hooks.h"

namespace gpl::grading {
namespace {

int answers = 3;   // what the submission's engine writes
int requests = 4;  // what this process writes to it
bool ended = false;
std::string endedWhy;
std::vector<std::string> lastOpen;

// ---- Status lines for the grader ------------------------------------------------------------------
// The grader learns from here which hook the checker was waiting for: when the engine stopped
// answering ("ended"), and when the grader asks with SIGUSR2 at a limit ("waiting"). This process is
// trusted; what it says names the hook, whatever the submission's own call stack claims.

int statusFd = -1;
std::atomic<int> inFlight{0};  // the Call waited for, 0 for none

void writeStatus(const char* text) {
    if (statusFd >= 0 && write(statusFd, text, std::strlen(text)) < 0) return;
}

// ,"hooks":[...]: the hooks the whole step in flight may run, set before its request.
char stepHooks[1024] = "";

// {"event":"EVENT","call":"NAME"} or "call":null; async-signal-safe (no allocation).
void writeEvent(const char* event, int call) {
    char line[1200] = "{\"event\":\"";
    std::strncat(line, event, 20);
    std::strcat(line, "\",\"call\":");
    if (call > 0 && call < static_cast<int>(Call::End)) {
        std::strcat(line, "\"");
        std::strncat(line, callName(static_cast<Call>(call)), 60);
        std::strcat(line, "\"");
        std::strcat(line, stepHooks);
    } else {
        std::strcat(line, "null");
    }
    std::strcat(line, "}\n");
    writeStatus(line);
}

void onStatusSignal(int) { writeEvent("waiting", inFlight.load()); }

std::string jsonEscaped(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            out += ' ';
        } else {
            out += c;
        }
    }
    return out;
}

}  // namespace

[[noreturn]] void endNow(Call call, const std::string& detail) {
    ended = true;
    endedWhy = detail.empty() ? std::string("the submission's code stopped answering during ") + callName(call)
                              : std::string("the submission's code answered nonsense during ") + callName(call) +
                                    ": " + detail;
    const std::string line = "{\"event\":\"ended\",\"call\":\"" + std::string(callName(call)) + "\"" + stepHooks +
                             ",\"detail\":\"" + jsonEscaped(detail) + "\"}\n";
    writeStatus(line.c_str());
    throw SubmissionEnded(endedWhy);
}

[[noreturn]] void rethrow(Thrown kind, const std::string& what) {
    switch (kind) {
        case Thrown::Simulation: throw SimulationError(what);
        case Thrown::InvalidArgument: throw std::invalid_argument(what);
        case Thrown::OutOfRange: throw std::out_of_range(what);
        case Thrown::BadAlloc: throw std::bad_alloc();
        default: throw std::runtime_error(what);
    }
}

// Only names of hooks count: an engine's answer cannot fill the checker's record with anything else.
namespace {

void record(const std::vector<std::string>& open) {
    lastOpen.clear();
    for (const std::string& hook : open) {
        for (int c = 1; c < static_cast<int>(Call::End); ++c) {
            if (hook == callName(static_cast<Call>(c))) {
                lastOpen.push_back(hook);
                kernelNotImplemented(hook);
                break;
            }
        }
    }
}

}  // namespace

void connectSubmission(const std::string& program) {
    if (const char* path = std::getenv("GPL_CHECKER_STATUS"); path && *path) {
        statusFd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    }
    struct sigaction action {};
    action.sa_handler = onStatusSignal;
    action.sa_flags = SA_RESTART;
    sigemptyset(&action.sa_mask);
    sigaction(SIGUSR2, &action, nullptr);
    signal(SIGPIPE, SIG_IGN);
    if (program.empty()) return;
    // A runner of this process's own (no sandbox): its fds 3 and 4 are the two pipes' other ends.
    int toRunner[2], fromRunner[2];
    if (pipe2(toRunner, O_CLOEXEC) != 0 || pipe2(fromRunner, O_CLOEXEC) != 0) {
        throw std::runtime_error("cannot make the pipes to " + program);
    }
    const pid_t child = fork();
    if (child < 0) throw std::runtime_error("cannot start " + program);
    if (child == 0) {
        // dup2() onto itself keeps close-on-exec: then the flag is cleared instead.
        for (const auto& [fd, target] : {std::pair{toRunner[0], 3}, std::pair{fromRunner[1], 4}}) {
            if (fd == target) {
                fcntl(fd, F_SETFD, 0);
            } else {
                dup2(fd, target);
            }
        }
        execl(program.c_str(), program.c_str(), "--serve", static_cast<char*>(nullptr));
        _exit(127);
    }
    close(toRunner[0]);
    close(fromRunner[1]);
    answers = fromRunner[0];
    requests = toRunner[1];
}

const std::string& request(Call call, const std::string& inputs, const AccelerationFunction* accel,
                           std::size_t particles) {
    if (ended) throw SubmissionEnded(endedWhy);
    inFlight = static_cast<int>(call);
    struct Clear {
        ~Clear() { inFlight = 0; }
    } clear;
    Writer head;
    head.u8(static_cast<std::uint8_t>(Frame::Request));
    head.u8(static_cast<std::uint8_t>(call));
    if (!sendFrame(requests, head.bytes() + inputs)) endNow(call, "");
    static std::string frame;  // its memory kept from one answer to the next
    while (true) {
        bool got = false;
        try {
            got = receiveFrame(answers, frame);
        } catch (const ProtocolError& e) {
            endNow(call, e.what());
        }
        if (!got) endNow(call, "");
        try {
            Reader r(frame);
            const std::uint8_t kind = r.u8();
            if (kind == static_cast<std::uint8_t>(Frame::Answer)) return frame;
            if (kind == static_cast<std::uint8_t>(Frame::Thrown)) {
                const std::uint8_t what = r.u8();
                if (what < 1 || what >= static_cast<std::uint8_t>(Thrown::End)) {
                    throw ProtocolError("an exception of an unknown kind");
                }
                const std::string message = r.text();
                record(r.texts());
                r.end();
                rethrow(static_cast<Thrown>(what), message);
            }
            if (kind == static_cast<std::uint8_t>(Frame::AskAccelerations) && accel) {
                const std::vector<Vec3> x = r.vec3s(), v = r.vec3s();
                r.end();
                // The test's acceleration function sees the particles it was written for, never others.
                if (x.size() != particles || v.size() != particles) {
                    throw ProtocolError("accelerations asked for " + std::to_string(x.size()) + " particles, not " +
                                        std::to_string(particles));
                }
                std::vector<Vec3> a;
                (*accel)(x, v, a);
                Writer w;
                w.u8(static_cast<std::uint8_t>(Frame::Accelerations));
                w.vec3s(a);
                if (!sendFrame(requests, w.bytes())) endNow(call, "");
                continue;
            }
            throw ProtocolError("an answer of an unknown kind");
        } catch (const ProtocolError& e) {
            endNow(call, e.what());
        }
    }
}

const std::vector<std::string>& openHooksOfLastAnswer() { return lastOpen; }

void setStepHooks(const std::vector<std::string>& hooks) {
    std::string list;
    for (const std::string& h : hooks) list += (list.empty() ? "" : ",") + ("\"" + h + "\"");
    list = hooks.empty() ? "" : ",\"hooks\":[" + list + "]";
    if (list.size() >= sizeof stepHooks) list.clear();
    inFlight = 0;  // the signal handler never reads a list half written
    std::memcpy(stepHooks, list.c_str(), list.size() + 1);
}

/// Runs `read` on the answer; a ProtocolError in it ends the submission for this test.
void parseAnswer(Call call, const std::string& answer, const std::function<void(Reader&)>& read) {
    Reader r(answer, 1);
    try {
        read(r);
        record(r.texts());
        r.end();
    } catch (const ProtocolError& e) {
        endNow(call, e.what());
    }
}

}  // namespace gpl::grading
