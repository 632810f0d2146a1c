// Graded tests: a GoogleTest test with points and a hint a student can act on. The grader
// (tools/grade.py) reads them from `autograder --grader-manifest` and runs each test in its own
// process.
//
//   GRADED_TEST(Worksheet1, Name, points, "hint" [, option...]) { ... }
//
// Options, declared next to the test:
//   grading::timeLimit(20)          seconds the test may run (the grader's default otherwise)
//   grading::dependsOn("OtherTest") not run (scores zero, "not run: depends on ...") when that
//                                   test of the same suite fails; "Suite.Test" names another suite
//   grading::hidden()               graded, but left out of student releases and shown on
//                                   Gradescope only as the grader is configured (hidden or after
//                                   the grades are published). A file holding a hidden test holds
//                                   hidden tests only (./lab release leaves the whole file out).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace gpl::grading {

struct GradedTest {
    std::string name;  ///< "Suite.Test", as GoogleTest names it
    int worksheet;     ///< taken from the suite name "WorksheetN"
    double points;
    std::string hint;                    ///< shown when the test fails
    double timeLimit = 0.0;              ///< s; 0: the grader's default
    std::vector<std::string> dependsOn;  ///< "Suite.Test" names
    bool hidden = false;
};

/// An option of GRADED_TEST: changes the test's declaration.
struct Option {
    enum class Kind { TimeLimit, DependsOn, Hidden } kind;
    double seconds = 0.0;
    const char* test = nullptr;
};

inline Option timeLimit(double seconds) { return {Option::Kind::TimeLimit, seconds, nullptr}; }
inline Option dependsOn(const char* test) { return {Option::Kind::DependsOn, 0.0, test}; }
inline Option hidden() { return {Option::Kind::Hidden, 0.0, nullptr}; }

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
