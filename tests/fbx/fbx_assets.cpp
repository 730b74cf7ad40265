#include "fbx_assets.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <sstream>

#include "json/json_reader.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

namespace dfm::test::fbx {

namespace {

const json::JsonValue& field(const json::JsonValue& v, std::string_view key) {
    const json::JsonMember* m = v.find(key);
    REQUIRE_MESSAGE(m != nullptr, "no field " << std::string(key));
    return m->value;
}

std::vector<glm::dvec3> points(const json::JsonValue& flat) {
    REQUIRE(flat.type == json::JsonType::array);
    REQUIRE(flat.items.size() % 3 == 0);
    std::vector<glm::dvec3> out(flat.items.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = {flat.items[3 * i].number, flat.items[3 * i + 1].number,
                  flat.items[3 * i + 2].number};
    }
    return out;
}

json::JsonValue parse(const std::filesystem::path& path) {
    json::JsonValue doc;
    const ToolStatus s = json::parse_json(read_text(path), path.string(), doc);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return doc;
}

}  // namespace

std::filesystem::path asset(std::string_view file) {
    return std::filesystem::path(DUALFORM_RIGGED_ASSETS) / std::string(file);
}

Loaded load(const std::filesystem::path& path) {
    Loaded l;
    const Status s = mesh::load_host_mesh(path, l.surface, l.host, &l.report);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return l;
}

std::vector<std::uint32_t> match_points(const std::vector<glm::dvec3>& a,
                                        const std::vector<glm::dvec3>& b, double tolerance,
                                        double& worst) {
    std::vector<std::uint32_t> order(b.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t i, std::uint32_t j) { return b[i].x < b[j].x; });
    std::vector<std::uint32_t> out(a.size(), mesh::no_index);
    std::vector<bool> taken(b.size(), false);
    worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        auto it = std::lower_bound(order.begin(), order.end(), a[i].x - tolerance,
                                   [&](std::uint32_t j, double x) { return b[j].x < x; });
        // The nearest one not taken yet: coincident points (a rig's
        // vertices that faces do not connect) pair off in turn.
        double best = tolerance;
        for (; it != order.end() && b[*it].x <= a[i].x + tolerance; ++it) {
            const double d = glm::length(b[*it] - a[i]);
            if (d <= best && !taken[*it]) {
                best = d;
                out[i] = *it;
            }
        }
        REQUIRE_MESSAGE(out[i] != mesh::no_index,
                        "point " << i << " has no match within " << tolerance);
        REQUIRE_MESSAGE(!taken[out[i]], "two points match point " << out[i]);
        taken[out[i]] = true;
        worst = std::max(worst, best);
    }
    return out;
}

EditVertices edit_vertices(const std::vector<glm::dvec3>& host) {
    EditVertices e;
    glm::dvec3 centre(0.0);
    for (std::uint32_t v = 0; v < host.size(); ++v) {
        if (host[v].x > host[e.first].x) e.first = v;
        centre += host[v] / static_cast<double>(host.size());
    }
    const glm::dvec3 cut = host[e.first] + (centre - host[e.first]) / 3.0;
    e.last = e.first == 0 ? 1 : 0;
    for (std::uint32_t v = 0; v < host.size(); ++v) {
        if (host[v] != host[e.first] &&
            glm::length(host[v] - cut) < glm::length(host[e.last] - cut))
            e.last = v;
    }
    return e;
}

std::string edit_scenario(const std::filesystem::path& dir, const std::filesystem::path& mesh,
                          std::uint32_t first, std::uint32_t last, const std::string& pose) {
    std::ostringstream s;
    s << R"({"mesh": ")" << mesh.string() << R"(", )";
    if (!pose.empty()) s << R"("pose": )" << pose << ", ";
    s << R"("roi": {"water_fill": {"first": )" << first << R"(, "last": )" << last
      << R"(}}, "handles": [{"ball": {"center": )" << first
      << R"(, "radius": 0.04}, "translate": [0.0, 0.08, 0.05]}], "solver": )"
      << R"({"tolerance": 1e-10, "max_iterations": 400}})";
    const auto path = dir / (mesh.filename().string() + ".json");
    write_text(path, s.str());
    return path.string();
}

std::string run_cli(const std::vector<std::string>& args) {
    const ProcessResult r = run_process(DUALFORM_CLI, args);
    REQUIRE_MESSAGE(r.exit_code == 0, "dualform failed:\n" << r.out << r.err);
    return r.out;
}

void convert(const std::string& mode, const std::filesystem::path& in,
             const std::filesystem::path& out) {
    const ProcessResult r = run_process("/usr/bin/python3", {DUALFORM_FBX_SCRIPTS "/fbx_convert.py",
                                                             mode, in.string(), out.string()});
    REQUIRE_MESSAGE(r.exit_code == 0, "fbx_convert.py failed:\n" << r.out << r.err);
}

const BlenderObject& BlenderFile::object(std::string_view name) const {
    for (const BlenderObject& o : objects) {
        if (o.name == name) return o;
    }
    FAIL("Blender imported no object named " << std::string(name));
    return objects.front();
}

std::vector<BlenderFile> blender_import(const std::vector<std::filesystem::path>& files,
                                        const std::filesystem::path& scratch, int pose_frame,
                                        const std::string& pose_key) {
    const std::filesystem::path out = scratch / "blender.json";
    std::vector<std::string> args{
        "-b", "--factory-startup", "--python-exit-code",
        "1",  "--python",          DUALFORM_FBX_SCRIPTS "/blender_fbx_read.py",
        "--", out.string()};
    if (pose_frame != 0) {
        args.insert(args.end(), {"--pose", std::to_string(pose_frame), pose_key});
    }
    for (const auto& f : files) args.push_back(f.string());
    const ProcessResult r = run_process(DUALFORM_BLENDER, args);
    REQUIRE_MESSAGE(r.exit_code == 0, "Blender failed:\n" << r.out << r.err);
    const json::JsonValue doc = parse(out);
    std::vector<BlenderFile> result;
    for (const json::JsonValue& f : doc.items) {
        BlenderFile file;
        for (const json::JsonValue& a : field(f, "actions").items) file.actions.push_back(a.text);
        for (const json::JsonValue& o : field(f, "objects").items) {
            BlenderObject obj;
            obj.name = field(o, "name").text;
            obj.type = field(o, "type").text;
            if (obj.type == "MESH") {
                obj.vertices = points(field(o, "vertices"));
                obj.armature = field(o, "armature").text;
                if (pose_frame != 0) obj.posed = points(field(o, "posed"));
                for (const json::JsonValue& k : field(o, "shape_keys").items) {
                    obj.shape_keys.push_back({field(k, "name").text, field(k, "value").number,
                                              points(field(k, "positions"))});
                }
            } else if (obj.type == "ARMATURE") {
                for (const json::JsonValue& b : field(o, "bones").items)
                    obj.bones.push_back(b.text);
            }
            file.objects.push_back(std::move(obj));
        }
        result.push_back(std::move(file));
    }
    return result;
}

std::vector<Frame> blender_frames(std::string_view name, int& fps) {
    const json::JsonValue doc = parse(asset(std::string(name) + ".frames.json"));
    fps = static_cast<int>(field(doc, "fps").number);
    std::vector<Frame> out;
    for (const json::JsonValue& f : field(doc, "frames").items) {
        std::vector<glm::dvec3> positions;
        for (const json::JsonValue& p : field(f, "positions").items) {
            positions.push_back({p.items[0].number, p.items[1].number, p.items[2].number});
        }
        out.push_back({field(f, "animation").text, static_cast<int>(field(f, "frame").number),
                       std::move(positions)});
    }
    return out;
}

}  // namespace dfm::test::fbx
