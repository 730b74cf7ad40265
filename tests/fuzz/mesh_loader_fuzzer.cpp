// libFuzzer target for one mesh loader, chosen at build time by
// DUALFORM_FUZZ_FORMAT (off, obj, ply, gltf: JSON or GLB by the magic, or fbx:
// binary or ASCII by the magic, through the pre-scan and Assimp): parse_mesh must take any
// bytes without crashing, hanging or leaking, and keep its contract.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz/load_contract.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace dfm::mesh;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    Mesh mesh;
    LoadReport report;
    const dfm::Status status =
        parse_mesh(bytes, FileFormat::DUALFORM_FUZZ_FORMAT, "fuzz", mesh, &report);
    // A broken contract is a finding the sanitizers cannot see.
    if (!dfm::test::load_contract_holds(status, mesh, report, "fuzz")) std::abort();
    return 0;
}
