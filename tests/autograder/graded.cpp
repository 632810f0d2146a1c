#include "graded.h"

#include "../grading/submission.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstddef>
#include <cstdint>
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

namespace gpl::checks {

std::uint32_t runSeed() {
    static const std::uint32_t seed = [] {
        const char* given = std::getenv("GPL_CHECKER_SEED");
        if (!given || !*given) return std::uint32_t{0};
        const auto drawn = static_cast<std::uint32_t>(std::strtoul(given, nullptr, 10));
        std::cout << "gpl-checker: random inputs drawn with GPL_CHECKER_SEED=" << drawn << '\n';
        return drawn;
    }();
    return seed;
}

}  // namespace gpl::checks

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
    // --runner PROGRAM: a variant's gpl-hooks-VARIANT started here, without a sandbox (by hand);
    // the grader instead passes the pipes of one in its sandbox as file descriptors 3 and 4.
    std::string runner;
    for (int i = 1; i < argc; ++i) {
        if (std::strncmp(argv[i], "--runner=", 9) == 0) runner = argv[i] + 9;
    }
    testing::InitGoogleTest(&argc, argv);
    try {
        gpl::grading::connectSubmission(runner);
    } catch (const std::exception& e) {
        std::cerr << "gpl-checker: " << e.what() << '\n';
        return 2;
    }
    return RUN_ALL_TESTS();
}
