#include <doctest/doctest.h>

#include <atomic>
#include <vector>

#include "solver/thread_pool.hpp"

using namespace dfm::solver;

TEST_CASE("solver: thread pool runs every task exactly once") {
    for (const std::size_t threads : {1u, 2u, 4u}) {
        ThreadPool pool(threads);
        CHECK(pool.thread_count() == threads);
        for (const std::size_t count : {0u, 1u, 3u, 100u}) {
            CAPTURE(threads);
            CAPTURE(count);
            std::vector<std::atomic<int>> calls(count);
            for (int round = 0; round < 3; ++round)
                pool.run(count, [&](std::size_t i) { calls[i].fetch_add(1); });
            for (std::size_t i = 0; i < count; ++i) CHECK(calls[i].load() == 3);
        }
    }
}

TEST_CASE("solver: run_tasks without a pool runs inline, in order") {
    std::vector<std::size_t> order;
    run_tasks(nullptr, 5, [&](std::size_t i) { order.push_back(i); });
    CHECK(order == std::vector<std::size_t>{0, 1, 2, 3, 4});
}
