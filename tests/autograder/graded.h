// Graded tests: a GoogleTest test with points and a hint a student can act on. The grader
// (tools/grade.py) reads them from `autograder --grader-manifest` and runs each test in its own
// process.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace gpl::grading {

struct GradedTest {
    std::string name;  ///< "Suite.Test", as GoogleTest names it
    int worksheet;     ///< taken from the suite name "WorksheetN"
    double points;
    std::string hint;  ///< shown when the test fails
};

/// Registers a graded test; returns true so it can initialise a static.
bool registerTest(const char* suite, const char* name, double points, const char* hint);
const std::vector<GradedTest>& gradedTests();

}  // namespace gpl::grading

/// GRADED_TEST(Worksheet1, Name, points, "hint") { ... } is a TEST_F of the fixture Worksheet1.
#define GRADED_TEST(Fixture, Name, Points, Hint)                       \
    [[maybe_unused]] static const bool gpl_graded_##Fixture##_##Name = \
        ::gpl::grading::registerTest(#Fixture, #Name, Points, Hint);   \
    TEST_F(Fixture, Name)
