// libFuzzer target for the edit scenario parser (docs/scenarios.md): any bytes
// give a scenario or a located error, never a crash, hang or leak.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz/scenario_contract.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    dfm::cli::Scenario scenario;
    const dfm::ToolStatus status = dfm::cli::parse_scenario(text, "fuzz.json", scenario);
    if (!dfm::test::scenario_contract_holds(status, scenario, "fuzz.json")) std::abort();
    return 0;
}
