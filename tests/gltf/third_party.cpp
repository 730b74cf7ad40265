#include "third_party.hpp"

#include <doctest/doctest.h>

#include <cctype>

#include "json/json_reader.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

namespace dfm::test::gltf {

namespace {

std::vector<double> numbers(const json::JsonValue& array) {
    REQUIRE(array.type == json::JsonType::array);
    std::vector<double> out;
    out.reserve(array.items.size());
    for (const json::JsonValue& v : array.items) out.push_back(v.number);
    return out;
}

const json::JsonValue& field(const json::JsonValue& v, std::string_view key) {
    const json::JsonMember* m = v.find(key);
    REQUIRE_MESSAGE(m != nullptr, "blender_read.py wrote no " << std::string(key));
    return m->value;
}

BlenderObject to_object(const json::JsonValue& v) {
    BlenderObject o;
    o.name = field(v, "name").text;
    o.mesh = field(v, "mesh").text;
    o.vertex_count = static_cast<std::size_t>(field(v, "vertex_count").number);
    o.local = numbers(field(v, "local"));
    o.world = numbers(field(v, "world"));
    for (const json::JsonValue& k : field(v, "shape_keys").items)
        o.shape_keys.emplace_back(field(k, "name").text, numbers(field(k, "positions")));
    return o;
}

}  // namespace

std::filesystem::path asset_path(std::string_view name) {
    return std::filesystem::path(DUALFORM_GLTF_ASSETS) / std::string(name);
}

Validation validate(const std::filesystem::path& file) {
    const ProcessResult r =
        run_process(DUALFORM_NODE, {DUALFORM_GLTF_SCRIPTS "/validate.mjs", file.string()});
    return {r.exit_code, r.out + r.err};
}

int validation_errors(const Validation& v) {
    // The counts line: "validate: FILE: N errors, N warnings, ...".
    const std::size_t end = v.report.find(" errors, ");
    std::size_t start = end;
    while (start != std::string::npos && start > 0 &&
           std::isdigit(static_cast<unsigned char>(v.report[start - 1])))
        --start;
    REQUIRE_MESSAGE((end != std::string::npos && start < end), v.report);
    return std::stoi(v.report.substr(start, end - start));
}

std::vector<std::vector<BlenderObject>> blender_read(
    const std::vector<std::filesystem::path>& files, const std::filesystem::path& dir) {
    std::vector<std::string> args{"-b",
                                  "--factory-startup",
                                  "--python-exit-code",
                                  "1",
                                  "--python",
                                  DUALFORM_GLTF_SCRIPTS "/blender_read.py",
                                  "--",
                                  "--axes",
                                  "gltf"};
    for (std::size_t i = 0; i < files.size(); ++i) {
        args.push_back(files[i].string());
        args.push_back((dir / (std::to_string(i) + ".json")).string());
    }
    const ProcessResult r = run_process(DUALFORM_BLENDER, args);
    REQUIRE_MESSAGE(r.exit_code == 0, "Blender failed:\n" << r.out << r.err);
    std::vector<std::vector<BlenderObject>> out;
    for (std::size_t i = 0; i < files.size(); ++i) {
        const std::filesystem::path json_path = dir / (std::to_string(i) + ".json");
        json::JsonValue doc;
        const ToolStatus s = json::parse_json(read_text(json_path), json_path.string(), doc);
        REQUIRE_MESSAGE(s.is_ok(), s.message());
        std::vector<BlenderObject> objects;
        for (const json::JsonValue& o : field(doc, "objects").items)
            objects.push_back(to_object(o));
        out.push_back(std::move(objects));
    }
    return out;
}

const BlenderObject& blender_object(const std::vector<BlenderObject>& objects,
                                    std::string_view name) {
    for (const BlenderObject& o : objects)
        if (o.name == name) return o;
    FAIL("Blender imported no object named " << std::string(name));
    return objects.front();
}

}  // namespace dfm::test::gltf
