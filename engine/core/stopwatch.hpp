#pragma once

#include <chrono>

namespace dfm {

// Milliseconds of wall time since `since`, for the set-up and solve reports.
inline double ms_since(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
        .count();
}

}  // namespace dfm
