#include "support/test_run.hpp"

#include <cstdio>
#include <string_view>

#include <doctest/doctest.h>

namespace {

unsigned matched_test_cases = 0;

// Keeps how many test cases passed the filters; reports nothing.
struct MatchCounter final : doctest::IReporter {
    explicit MatchCounter(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats& stats) override {
        matched_test_cases = stats.numTestCasesPassingFilters;
    }
    void test_case_start(const doctest::TestCaseData&) override {}
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};

REGISTER_LISTENER("match_counter", 1, MatchCounter);

bool names_test_cases(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg.starts_with("--test-case=") || arg.starts_with("-tc=") ||
            arg.starts_with("--dt-test-case=") || arg.starts_with("--dt-tc=")) {
            return true;
        }
    }
    return false;
}

}  // namespace

int run_test_cases(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int result = context.run();
    if (context.shouldExit() || !names_test_cases(argc, argv)) return result;
    if (matched_test_cases == 0) {
        std::fprintf(stderr, "no test case matches the --test-case filter\n");
        return 1;
    }
    return result;
}
