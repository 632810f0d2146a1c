#include "gpl/hooks.h"

#include <iostream>
#include <mutex>
#include <set>

namespace gpl {
namespace {

std::mutex& hooksMutex() {
    static std::mutex mutex;
    return mutex;
}
std::set<std::string>& openKernelHooks() {
    static std::set<std::string> hooks;
    return hooks;
}

}  // namespace

void kernelNotImplemented(const std::string& hook) {
    const std::lock_guard<std::mutex> lock(hooksMutex());
    if (openKernelHooks().insert(hook).second) std::cerr << "not implemented: " << hook << '\n';
}

std::vector<std::string> kernelsNotImplemented() {
    const std::lock_guard<std::mutex> lock(hooksMutex());
    return {openKernelHooks().begin(), openKernelHooks().end()};
}

}  // namespace gpl
