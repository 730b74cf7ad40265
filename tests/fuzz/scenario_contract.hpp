#pragma once

#include <string_view>

#include "dualform/scenario.hpp"

// What parse_scenario promises for any text, checked by the fuzz target and
// by the unit test that replays its findings.
namespace dfm::test {

inline bool scenario_contract_holds(const dfm::ToolStatus& status, const cli::Scenario& scenario,
                                    std::string_view source) {
    // An error is located in the source; a scenario has a mesh and a handle.
    if (!status) return std::string_view(status.message()).starts_with(source);
    return !scenario.mesh.empty() && !scenario.handles.empty();
}

}  // namespace dfm::test
