// The library reads no environment variable and no user database: the
// models folder comes only from dfm_context_desc.models_directory, whatever
// DUALFORM_MODELS and HOME say.

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "dualform/dualform.h"
#include "sdk_fixture.hpp"
#include "support/test_files.hpp"

namespace {

// Sets a variable for one scope and puts the old value back after it.
class ScopedVariable {
public:
    ScopedVariable(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedVariable() {
        if (old_) {
            setenv(name_, old_->c_str(), 1);
        } else {
            unsetenv(name_);
        }
    }
    ScopedVariable(const ScopedVariable&) = delete;
    ScopedVariable& operator=(const ScopedVariable&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

// A tetrahedron, or with `extra` a fifth vertex lifted off it, so that the
// vertex count tells which folder a model came from.
void write_model(const std::filesystem::path& folder, bool extra) {
    std::filesystem::create_directories(folder);
    dfm::test::write_text(folder / "shape.off",
                          extra ? "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 2 2\n"
                                  "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n"
                                : "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                  "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
}

std::size_t vertex_count(dfm_mesh* mesh) {
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    return info.vertex_count;
}

}  // namespace

TEST_CASE(
    "environment: model:NAME comes from the descriptor's folder, never DUALFORM_MODELS or HOME") {
    const std::filesystem::path root = dfm::test::scratch_dir("sdk_environment");
    write_model(root / "from-variable", false);
    write_model(root / "home" / ".cache" / "dualform" / "models", false);
    write_model(root / "from-descriptor", true);
    const ScopedVariable models("DUALFORM_MODELS", (root / "from-variable").string());
    const ScopedVariable home("HOME", (root / "home").string());

    dfm_context* bare = nullptr;
    REQUIRE(dfm_context_create(nullptr, &bare) == DFM_OK);
    dfm_mesh* mesh = nullptr;
    CHECK(dfm_mesh_load(bare, "model:shape", &mesh) == DFM_ERROR_NOT_FOUND);
    CHECK(mesh == nullptr);
    CHECK(dfm::test::message_has("models_directory"));
    dfm_context_destroy(bare);

    const std::string folder = (root / "from-descriptor").string();
    dfm_context_desc desc = {};
    desc.models_directory = folder.c_str();
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    REQUIRE_MESSAGE(dfm_mesh_load(context, "model:shape", &mesh) == DFM_OK,
                    dfm::test::last_error());
    CHECK(vertex_count(mesh) == 5);
    dfm_mesh_destroy(mesh);

    // The descriptor's string is copied: the host may free it at once.
    write_model(root / "missing", false);
    std::filesystem::remove(root / "missing" / "shape.off");
    const std::string empty = (root / "missing").string();
    desc.models_directory = empty.c_str();
    dfm_context* other = nullptr;
    REQUIRE(dfm_context_create(&desc, &other) == DFM_OK);
    desc.models_directory = nullptr;
    CHECK(dfm_mesh_load(other, "model:shape", &mesh) == DFM_ERROR_NOT_FOUND);
    CHECK(dfm::test::message_has("missing"));
    dfm_context_destroy(other);
    dfm_context_destroy(context);
}
