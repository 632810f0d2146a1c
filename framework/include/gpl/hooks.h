// Hooks that are not written yet. A student hook that is a pure kernel (no engine at hand) reports
// itself here from its stub; the engine, the runner, the viewer and the grader read the record.
#pragma once

#include <string>
#include <vector>

namespace gpl {

/// Called by the stub of a kernel hook: records the hook and prints "not implemented: <hook>" once
/// per process. Whether a hook is written is a property of the code that is linked, so the record
/// is per process.
void kernelNotImplemented(const std::string& hook);
/// Kernel hooks whose stubs have run in this process, sorted.
std::vector<std::string> kernelsNotImplemented();

}  // namespace gpl
