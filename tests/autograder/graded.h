// Graded tests: a GoogleTest test with points and a hint a student can act on. They are compiled
// into the checker, gpl-checker, which links no student code: a hook a test calls is a request to
// the submission's engine in the grader's sandbox (tests/grading/submission.h), so what a test
// expects, and whether it passed, is decided here alone. The grader (tools/grade.py) reads the
// tests from `gpl-checker --grader-manifest` and runs each in its own pair of processes.
//
//   GRADED_TEST(Worksheet1, Name, points, "hint" [, option...]) { ... }
//
// Options, declared next to the test:
//   grading::timeLimit(20)          seconds the test may run, wall clock and CPU time alike (the
//                                   grader's default otherwise)
//   grading::memoryLimit(2048)      MiB of resident memory the test may use (default 1024)
//   grading::threadLimit(4)         threads the test may run at once (default 8)
//   grading::fileLimit(128)         MiB the test may write to one file (default 64)
//   grading::dependsOn("OtherTest") not run (scores zero, "not run: depends on ...") when that
//                                   test of the same suite fails; "Suite.Test" names another suite
//   grading::hidden()               graded, but left out of student releases and shown on
//                                   Gradescope only as the grader is configured (hidden or after
//                                   the grades are published). A file holding a hidden test holds
//                                   hidden tests only (./lab release leaves the whole file out).
#pragma once

#include <gtest/gtest.h>

#include "../grading/protocol.h"

#include <functional>
#include <string>
#include <vector>

namespace gpl {
class PhysicsEngine;
}

namespace gpl::grading {

struct GradedTest {
    std::string name;  ///< "Suite.Test", as GoogleTest names it
    int worksheet;     ///< taken from the suite name "WorksheetN"
    double points;
    std::string hint;                    ///< shown when the test fails
    double timeLimit = 0.0;              ///< s; 0: the grader's default
    double memoryLimit = 0.0;            ///< MiB; 0: the grader's default
    double threadLimit = 0.0;            ///< threads; 0: the grader's default
    double fileLimit = 0.0;              ///< MiB; 0: the grader's default
    std::vector<std::string> dependsOn;  ///< "Suite.Test" names
    bool hidden = false;
};

/// An option of GRADED_TEST: changes the test's declaration.
struct Option {
    enum class Kind { TimeLimit, MemoryLimit, ThreadLimit, FileLimit, DependsOn, Hidden } kind;
    double value = 0.0;  ///< s, MiB or a count, as the kind says
    const char* test = nullptr;
};

inline Option timeLimit(double seconds) { return {Option::Kind::TimeLimit, seconds, nullptr}; }
inline Option memoryLimit(double mebibytes) { return {Option::Kind::MemoryLimit, mebibytes, nullptr}; }
inline Option threadLimit(int threads) { return {Option::Kind::ThreadLimit, double(threads), nullptr}; }
inline Option fileLimit(double mebibytes) { return {Option::Kind::FileLimit, mebibytes, nullptr}; }
inline Option dependsOn(const char* test) { return {Option::Kind::DependsOn, 0.0, test}; }
inline Option hidden() { return {Option::Kind::Hidden, 0.0, nullptr}; }

/// Steps `engine` n times, as n calls of engine.step() would, with one request to the submission's
/// engine for many steps at once; after step k (1..n) calls each(k), which reads the engine (never
/// changes it). A failure in each() (an EXPECT or an ASSERT) ends the run after that step, as an
/// ASSERT in a loop of step() would end the loop. A body no longer finite, or a hook's exception,
/// throws as step() does. For long runs checked after every step.
void steps(PhysicsEngine& engine, int n, const std::function<void(int)>& each);

/// positionVerlet or velocityVerlet, as graded tests call them.
using IntegratorKernel = void (*)(ParticleState&, const AccelerationFunction&, double);

/// Takes n steps of h with the kernel from `state` under `force`, as n calls of kernel(state, force,
/// h) would, with one request to the submission's engine for many steps (it evaluates the force
/// itself); after step k (1..n) calls each(k), which reads `state`; a failure in it ends the run.
void integratorSteps(IntegratorKernel kernel, ParticleState& state, const LinearForce& force, double h, int n,
                     const std::function<void(int)>& each);

/// Takes n steps of h with integrateRotation() of `body`, as n calls of integrateRotation(body, h)
/// would, with one request for many steps; after step k (1..n) calls each(k), which reads `body`; a
/// failure in it ends the run.
void rotationSteps(Body& body, double h, int n, const std::function<void(int)>& each);

/// Registers a graded test; returns true so it can initialise a static.
bool registerTest(const char* suite, const char* name, double points, const char* hint,
                  const std::vector<Option>& options = {});
const std::vector<GradedTest>& gradedTests();

template <class... Options>
bool registerGraded(const char* suite, const char* name, double points, const char* hint, Options... options) {
    return registerTest(suite, name, points, hint, {options...});
}

}  // namespace gpl::grading

/// GRADED_TEST(Worksheet1, Name, points, "hint", options...) { ... } is a TEST_F of the fixture Worksheet1.
#define GRADED_TEST(Fixture, Name, Points, ...)                               \
    [[maybe_unused]] static const bool gpl_graded_##Fixture##_##Name =        \
        ::gpl::grading::registerGraded(#Fixture, #Name, Points, __VA_ARGS__); \
    TEST_F(Fixture, Name)
