#include "graded.h"

#include <cctype>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>

namespace gpl::grading {

std::vector<GradedTest>& registry() {
    static std::vector<GradedTest> tests;
    return tests;
}

bool registerTest(const char* suite, const char* name, double points, const char* hint) {
    int worksheet = 0;
    for (const char* c = suite; *c; ++c) {
        if (std::isdigit(static_cast<unsigned char>(*c))) worksheet = worksheet * 10 + (*c - '0');
    }
    registry().push_back({std::string(suite) + "." + name, worksheet, points, hint});
    return true;
}

const std::vector<GradedTest>& gradedTests() { return registry(); }

}  // namespace gpl::grading

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--grader-manifest") == 0) {
            nlohmann::json tests = nlohmann::json::array();
            for (const auto& t : gpl::grading::gradedTests()) {
                tests.push_back({{"name", t.name}, {"worksheet", t.worksheet}, {"points", t.points}, {"hint", t.hint}});
            }
            std::cout << tests.dump(2) << '\n';
            return 0;
        }
    }
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
