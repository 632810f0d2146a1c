// The checker's side of the pipe: the submission's engine, reached only through requests.
//
// The checker links the framework and, in place of the student hooks, forwarded_hooks.cpp: each
// hook, called by a graded test or by the framework's own code in the checker, becomes a request to
// the submission's engine (gpl-hooks-VARIANT, in the sandbox), and its answer comes back as the
// hook's outputs. A test reads as it would in one process; what it expects stays here.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocol.h"

namespace gpl::grading {

/// The submission's engine stopped answering (it crashed, was stopped at a limit, or closed the
/// pipe) or answered something that is not an answer. Every later request throws it again.
class SubmissionEnded : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Connects to the submission's engine: the pipes on file descriptors 3 (answers) and 4 (requests)
/// the grader made, or a program this process starts itself (`--runner PROGRAM`, for trying a
/// variant by hand; no sandbox). Status lines go to the file GPL_CHECKER_STATUS names, if any.
void connectSubmission(const std::string& program);

/// Sends a request for `call` with its inputs; serves the integrator kernels' requests for
/// accelerations with `accel` (for exactly `particles` particles, or the answer is nonsense); returns the answer: its kind (one byte), its outputs, and the hooks still open (parseAnswer()
/// reads the last two), valid until the next request. A hook that threw throws here the same kind of exception with its message.
const std::string& request(Call call, const std::string& inputs, const AccelerationFunction* accel = nullptr,
                           std::size_t particles = 0);

/// Reads an answer's outputs with `read`, then the hooks still open it names (recorded as
/// request() does). An answer that does not parse ends the submission for this test.
void parseAnswer(Call call, const std::string& answer, const std::function<void(Reader&)>& read);

/// Ends the submission for this test: it stopped answering (detail empty) or answered nonsense
/// (detail says what); every later request throws SubmissionEnded too.
[[noreturn]] void endNow(Call call, const std::string& detail);
/// Throws the kind of exception a hook threw, with its message.
[[noreturn]] void rethrow(Thrown kind, const std::string& what);

/// The hooks a whole step may run (the stages the checker's engine has active), named in the status
/// lines while a step's request is in flight, so that the grader may take the hook the engine's own
/// call stack names among them, and no other; empty for a kernel's request.
void setStepHooks(const std::vector<std::string>& hooks);

/// The hooks still open that the last answer named.
const std::vector<std::string>& openHooksOfLastAnswer();

}  // namespace gpl::grading
