#include "dualform/scenario.hpp"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <new>
#include <sstream>
#include <system_error>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

#include "json/json_reader.hpp"
#include "json/json_writer.hpp"

// Every field the format does not define is an error, so that a misspelt
// optional field ("tolerence") cannot silently fall back to a default. The
// one exception is a top-level "description" or "comment" string, room for
// the note a shared scenario needs.
namespace dfm::cli {

namespace {

using json::append_number;
using json::json_location;
using json::json_printable;
using json::json_type_phrase;
using json::JsonMember;
using json::JsonPosition;
using json::JsonType;
using json::JsonValue;

// Numbers beyond a double are kept, so that the schema's checks name the field.
ToolStatus read_json(std::string_view text, std::string_view source, JsonValue& out) {
    return json::parse_json(text, source, {.keep_huge_numbers = true}, out);
}

using Names = std::initializer_list<std::string_view>;

// 2^32 - 1 is the engine's "no vertex", so indices stop one short of it.
constexpr double max_vertex_index = 4294967294.0;

// A field of the document: its value (nullptr when the field is missing),
// where to point at (the value, or the enclosing object when missing) and
// its path from the top ("handles[1].rotate").
struct Field {
    const JsonValue* value = nullptr;
    JsonPosition at;
    std::string path;
};

std::string member_path(const Field& object, std::string_view key) {
    std::string path = object.path;
    if (!path.empty()) path += '.';
    path += json_printable(key);
    return path;
}

Field member(const Field& object, std::string_view key) {
    Field f;
    f.path = member_path(object, key);
    const JsonMember* m = object.value->find(key);
    f.value = m ? &m->value : nullptr;
    f.at = m ? m->value.at : object.at;
    return f;
}

Field item(const Field& array, std::size_t index) {
    Field f;
    f.value = &array.value->items[index];
    f.at = f.value->at;
    f.path = array.path;
    f.path += '[';
    f.path += std::to_string(index);
    f.path += ']';
    return f;
}

std::string join(Names names, std::string_view last_separator) {
    std::string out;
    std::size_t i = 0;
    for (const std::string_view name : names) {
        if (i > 0) out += i + 1 == names.size() ? last_separator : ", ";
        out += name;
        ++i;
    }
    return out;
}

std::string number_text(double v, bool written_as_integer) {
    std::string out;
    append_number(out, v);
    // "1.0" or "1e2" must not read back as the integer they equal.
    if (!written_as_integer && out.find_first_of(".e") == std::string::npos) out += ".0";
    return out;
}

// What a value is, for "found ..."; scalars show themselves.
std::string describe(const JsonValue& v) {
    switch (v.type) {
        case JsonType::boolean: return v.boolean ? "true" : "false";
        case JsonType::number: return number_text(v.number, v.integer);
        case JsonType::array: {
            if (v.items.empty()) return "an empty array";
            std::string out = "an array of ";
            out += std::to_string(v.items.size());
            out += v.items.size() == 1 ? " value" : " values";
            return out;
        }
        case JsonType::null:
        case JsonType::string:
        case JsonType::object: break;
    }
    return json_type_phrase(v.type);
}

// Whether `a` and `b` are parallel or either is zero, measured on copies
// scaled to a largest component of 1 so that no product overflows.
bool parallel(glm::dvec3 a, glm::dvec3 b) {
    const auto scaled = [](glm::dvec3 v) {
        const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        return m > 0.0 ? v / m : v;
    };
    a = scaled(a);
    b = scaled(b);
    return glm::length(glm::cross(a, b)) <= 1e-9 * glm::length(a) * glm::length(b);
}

class ScenarioReader {
public:
    explicit ScenarioReader(std::string_view source) : source_(source) {}

    ToolStatus scenario(const JsonValue& root, Scenario& out) const {
        const Field top{&root, root.at, ""};
        if (ToolStatus s = object(top, {"mesh", "subdivide", "pose", "roi", "handles", "solver",
                                        "description", "comment"});
            !s) {
            return s;
        }
        for (const std::string_view note : {"description", "comment"}) {
            const Field f = member(top, note);
            if (f.value && f.value->type != JsonType::string) return expected(f, "a string");
        }
        if (ToolStatus s = mesh(member(top, "mesh"), out.mesh); !s) return s;
        if (const Field f = member(top, "subdivide"); f.value) {
            const auto accept = [](const JsonValue& v) {
                return v.integer && v.number >= 0.0 && v.number <= max_subdivisions;
            };
            double v = 0.0;
            if (ToolStatus s = number(f, "an integer from 0 to 3", accept, v); !s) return s;
            out.subdivide = static_cast<int>(v);
        }
        if (const Field f = member(top, "pose"); f.value) {
            if (out.subdivide > 0) {
                return error(f,
                             "a pose cannot be combined with subdivide (a subdivided mesh has "
                             "no skin)");
            }
            if (ToolStatus s = pose(f, out.pose.emplace()); !s) return s;
        }
        if (ToolStatus s = roi(member(top, "roi"), out.roi); !s) return s;
        if (ToolStatus s = handles(member(top, "handles"), out.handles); !s) return s;
        const Field solver_field = member(top, "solver");
        if (!solver_field.value) return ToolStatus::ok();
        return solver(solver_field, out.solver);
    }

    // A camera as a document of its own (`dualform pick --camera`).
    ToolStatus camera_document(const JsonValue& root, dfm_camera& out) const {
        return camera(Field{&root, root.at, ""}, out);
    }

private:
    ToolStatus error(const Field& f, std::string_view what) const {
        return error(f.at, f.path, what);
    }
    ToolStatus error(JsonPosition at, std::string_view path, std::string_view what) const {
        std::string message = json_location(source_, at);
        if (!path.empty()) {
            message += path;
            message += ": ";
        }
        message += what;
        return ToolStatus(DFM_ERROR_PARSE, std::move(message));
    }

    ToolStatus expected(const Field& f, std::string_view what) const {
        std::string message = "expected ";
        message += what;
        message += ", found ";
        message += describe(*f.value);
        return error(f, message);
    }

    // The field is present and of `type`; `what` names what it should be.
    ToolStatus typed(const Field& f, JsonType type, std::string_view what) const {
        if (!f.value) return error(f, "required field is missing");
        if (f.value->type != type) return expected(f, what);
        if (f.value->beyond_double) {
            std::string message = "the number ";
            message += json_printable(f.value->text);
            message += " is beyond the range of a double";
            return error(f, message);
        }
        return ToolStatus::ok();
    }

    // The field is an object whose every member is among `known`.
    ToolStatus object(const Field& f, Names known) const {
        if (ToolStatus s = typed(f, JsonType::object, "an object"); !s) return s;
        for (const JsonMember& m : f.value->members) {
            if (std::find(known.begin(), known.end(), m.key) != known.end()) continue;
            std::string what = "unknown field (expected ";
            what += join(known, " or ");
            what += ')';
            return error(m.at, member_path(f, m.key), what);
        }
        return ToolStatus::ok();
    }

    // Exactly one of `names` is a member of the object `f`; `kind` says
    // what they are ("ROI kind").
    ToolStatus exactly_one(const Field& f, Names names, std::string_view kind,
                           const JsonMember*& out) const {
        out = nullptr;
        for (const JsonMember& m : f.value->members) {
            if (std::find(names.begin(), names.end(), m.key) == names.end()) continue;
            if (out) {
                std::string what = "only one ";
                what += kind;
                what += " is allowed, and ";
                what += out->key;
                what += " is already given";
                return error(m.at, member_path(f, m.key), what);
            }
            out = &m;
        }
        if (out) return ToolStatus::ok();
        std::string what = "expected one ";
        what += kind;
        what += " (";
        what += join(names, " or ");
        what += "), found none";
        return error(f, what);
    }

    // A number that `accept` takes; `what` describes such numbers.
    template <typename Accept>
    ToolStatus number(const Field& f, std::string_view what, Accept accept, double& out) const {
        if (ToolStatus s = typed(f, JsonType::number, what); !s) return s;
        if (!accept(*f.value)) return expected(f, what);
        out = f.value->number;
        return ToolStatus::ok();
    }

    ToolStatus number(const Field& f, double& out) const {
        return number(
            f, "a number", [](const JsonValue&) { return true; }, out);
    }

    ToolStatus positive(const Field& f, double& out) const {
        return number(
            f, "a number greater than 0", [](const JsonValue& v) { return v.number > 0.0; }, out);
    }

    // An integer from 1 to `max`, written without fraction or exponent.
    ToolStatus count(const Field& f, double max, double& out) const {
        std::string what = "a positive integer (at most ";
        what += number_text(max, true);
        what += ')';
        const auto accept = [max](const JsonValue& v) {
            return v.integer && v.number >= 1.0 && v.number <= max;
        };
        return number(f, what, accept, out);
    }

    ToolStatus index(const Field& f, std::uint32_t& out) const {
        const auto accept = [](const JsonValue& v) {
            return v.integer && v.number >= 0.0 && v.number <= max_vertex_index;
        };
        double v = 0.0;
        if (ToolStatus s = number(f, "a vertex index (an integer from 0 to 4294967294)", accept, v);
            !s) {
            return s;
        }
        out = static_cast<std::uint32_t>(v);
        return ToolStatus::ok();
    }

    // A non-empty list of distinct vertex indices.
    ToolStatus index_list(const Field& f, std::vector<std::uint32_t>& out) const {
        if (ToolStatus s = typed(f, JsonType::array, "an array of vertex indices"); !s) return s;
        if (f.value->items.empty()) return expected(f, "at least one vertex index");
        const std::size_t n = f.value->items.size();
        out.resize(n);
        std::unordered_map<std::uint32_t, std::size_t> first_seen;
        first_seen.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            const Field e = item(f, i);
            if (ToolStatus s = index(e, out[i]); !s) return s;
            const auto [it, fresh] = first_seen.emplace(out[i], i);
            if (!fresh) {
                std::string what = "vertex ";
                what += std::to_string(out[i]);
                what += " is listed twice (first at [";
                what += std::to_string(it->second);
                what += "])";
                return error(e, what);
            }
        }
        return ToolStatus::ok();
    }

    template <glm::length_t L>
    ToolStatus vec(const Field& f, glm::vec<L, double>& out) const {
        const char* what =
            L == 2 ? "an array of 2 numbers [x, y]" : "an array of 3 numbers [x, y, z]";
        if (ToolStatus s = typed(f, JsonType::array, what); !s) return s;
        if (f.value->items.size() != static_cast<std::size_t>(L)) return expected(f, what);
        for (glm::length_t i = 0; i < L; ++i) {
            if (ToolStatus s = number(item(f, static_cast<std::size_t>(i)), out[i]); !s) return s;
        }
        return ToolStatus::ok();
    }

    ToolStatus pose(const Field& f, PoseSpec& out) const {
        if (ToolStatus s = object(f, {"animation", "time"}); !s) return s;
        const Field animation = member(f, "animation");
        if (!animation.value) return error(animation, "required field is missing");
        if (animation.value->type == JsonType::string) {
            out.animation_name = animation.value->text;
        } else {
            const auto accept = [](const JsonValue& v) {
                return v.integer && v.number >= 0.0 && v.number <= 4294967295.0;
            };
            double v = 0.0;
            if (ToolStatus s = number(animation, "an animation's name or index", accept, v); !s) {
                return s;
            }
            out.animation_index = static_cast<std::uint32_t>(v);
        }
        return number(member(f, "time"), out.time);
    }

    ToolStatus mesh(const Field& f, std::string& out) const {
        if (ToolStatus s = typed(f, JsonType::string, "a string (a mesh file path or model:NAME)");
            !s) {
            return s;
        }
        out = f.value->text;
        if (out.empty()) return error(f, "expected a mesh file path or model:NAME, found \"\"");
        if (out == "model:") return error(f, "expected a model name after \"model:\"");
        if (out.find('\0') != std::string::npos) {
            return error(f, "a mesh path cannot contain a NUL character");
        }
        return ToolStatus::ok();
    }

    ToolStatus roi(const Field& f, RoiSpec& out) const {
        const Names kinds = {"water_fill", "water_fill_clicks", "ball", "vertices", "all"};
        if (ToolStatus s = object(f, kinds); !s) return s;
        const JsonMember* kind = nullptr;
        if (ToolStatus s = exactly_one(f, kinds, "ROI kind", kind); !s) return s;
        const Field k = member(f, kind->key);
        if (kind->key == "water_fill") {
            out.kind = RoiSpec::Kind::water_fill;
            return water_fill(k, out);
        }
        if (kind->key == "water_fill_clicks") {
            out.kind = RoiSpec::Kind::water_fill_clicks;
            return water_fill_clicks(k, out);
        }
        if (kind->key == "ball") {
            out.kind = RoiSpec::Kind::ball;
            return ball(k, out.ball);
        }
        if (kind->key == "vertices") {
            out.kind = RoiSpec::Kind::vertices;
            return index_list(k, out.vertices);
        }
        out.kind = RoiSpec::Kind::all;
        if (k.value->type != JsonType::boolean || !k.value->boolean) return expected(k, "true");
        return ToolStatus::ok();
    }

    ToolStatus water_fill(const Field& f, RoiSpec& out) const {
        if (ToolStatus s = object(f, {"first", "last"}); !s) return s;
        if (ToolStatus s = index(member(f, "first"), out.first); !s) return s;
        const Field last = member(f, "last");
        if (ToolStatus s = index(last, out.last); !s) return s;
        // The cut plane's normal is the direction from first to last.
        if (out.last == out.first) return error(last, "must differ from first");
        return ToolStatus::ok();
    }

    ToolStatus water_fill_clicks(const Field& f, RoiSpec& out) const {
        if (ToolStatus s = object(f, {"camera", "first", "last"}); !s) return s;
        if (ToolStatus s = camera(member(f, "camera"), out.camera); !s) return s;
        if (ToolStatus s = pixel(member(f, "first"), out.camera, out.first_pixel); !s) return s;
        return pixel(member(f, "last"), out.camera, out.last_pixel);
    }

    ToolStatus pixel(const Field& f, const dfm_camera& camera, glm::dvec2& out) const {
        if (ToolStatus s = vec(f, out); !s) return s;
        const double w = camera.width;
        const double h = camera.height;
        if (out.x < 0.0 || out.x > w || out.y < 0.0 || out.y > h) {
            std::string what = "the pixel lies outside the image, which runs from [0, 0] to [";
            what += number_text(w, true);
            what += ", ";
            what += number_text(h, true);
            what += ']';
            return error(f, what);
        }
        return ToolStatus::ok();
    }

    ToolStatus camera(const Field& f, dfm_camera& out) const {
        if (ToolStatus s = object(f, {"eye", "target", "up", "fov_y_degrees", "width", "height"});
            !s) {
            return s;
        }
        glm::dvec3 eye{0.0};
        glm::dvec3 target_point{0.0};
        glm::dvec3 up_direction{0.0};
        if (ToolStatus s = vec(member(f, "eye"), eye); !s) return s;
        const Field target = member(f, "target");
        if (ToolStatus s = vec(target, target_point); !s) return s;
        if (target_point == eye) return error(target, "must differ from eye");
        const Field up = member(f, "up");
        if (ToolStatus s = vec(up, up_direction); !s) return s;
        for (int k = 0; k < 3; ++k) {
            out.eye[k] = eye[k];
            out.target[k] = target_point[k];
            out.up[k] = up_direction[k];
        }
        if (parallel(up_direction, target_point - eye)) {
            return error(up,
                         "must be non-zero and not parallel to the view direction (target - eye)");
        }
        const auto opening = [](const JsonValue& v) { return v.number > 0.0 && v.number < 180.0; };
        if (ToolStatus s = number(member(f, "fov_y_degrees"),
                                  "an angle in degrees between 0 and 180, both excluded", opening,
                                  out.fov_y_degrees);
            !s) {
            return s;
        }
        double width = 0.0;
        double height = 0.0;
        if (ToolStatus s = count(member(f, "width"), UINT32_MAX, width); !s) return s;
        if (ToolStatus s = count(member(f, "height"), UINT32_MAX, height); !s) return s;
        out.width = static_cast<std::uint32_t>(width);
        out.height = static_cast<std::uint32_t>(height);
        return ToolStatus::ok();
    }

    ToolStatus ball(const Field& f, BallSelection& out) const {
        if (ToolStatus s = object(f, {"center", "radius"}); !s) return s;
        if (ToolStatus s = index(member(f, "center"), out.center); !s) return s;
        return positive(member(f, "radius"), out.radius);
    }

    ToolStatus handles(const Field& f, std::vector<HandleSpec>& out) const {
        if (ToolStatus s = typed(f, JsonType::array, "an array of handle groups"); !s) return s;
        if (f.value->items.empty()) return expected(f, "at least one handle group");
        out.resize(f.value->items.size());
        for (std::size_t i = 0; i < out.size(); ++i) {
            if (ToolStatus s = handle(item(f, i), out[i]); !s) return s;
        }
        return ToolStatus::ok();
    }

    ToolStatus handle(const Field& f, HandleSpec& out) const {
        if (ToolStatus s = object(f, {"vertices", "ball", "translate", "rotate", "targets"}); !s) {
            return s;
        }
        const JsonMember* selection = nullptr;
        if (ToolStatus s = exactly_one(f, {"vertices", "ball"}, "selection", selection); !s)
            return s;
        if (selection->key == "ball") {
            if (ToolStatus s = ball(member(f, "ball"), out.ball.emplace()); !s) return s;
        } else if (ToolStatus s = index_list(member(f, "vertices"), out.vertices); !s) {
            return s;
        }
        if (const Field t = member(f, "translate"); t.value) {
            if (ToolStatus s = vec(t, out.translate.emplace()); !s) return s;
        }
        if (const Field r = member(f, "rotate"); r.value) {
            if (ToolStatus s = rotate(r, out.rotate.emplace()); !s) return s;
        }
        const Field targets_field = member(f, "targets");
        if (!targets_field.value) return ToolStatus::ok();
        if (out.ball) {
            return error(targets_field,
                         "needs a vertices list (one target per vertex), not a ball");
        }
        // Absolute positions leave nothing for a relative motion to do.
        if (out.translate || out.rotate) {
            return error(targets_field, "cannot be combined with translate or rotate");
        }
        return targets(targets_field, out.vertices.size(), out.targets);
    }

    ToolStatus rotate(const Field& f, RotateSpec& out) const {
        if (ToolStatus s = object(f, {"axis", "degrees", "pivot"}); !s) return s;
        const Field axis = member(f, "axis");
        if (ToolStatus s = vec(axis, out.axis); !s) return s;
        if (out.axis == glm::dvec3(0.0)) return error(axis, "must not be the zero vector");
        if (ToolStatus s = number(member(f, "degrees"), out.degrees); !s) return s;
        const Field pivot = member(f, "pivot");
        if (!pivot.value) return ToolStatus::ok();
        if (pivot.value->type == JsonType::string) {
            if (pivot.value->text == "centroid") return ToolStatus::ok();
            std::string what = "expected [x, y, z] or \"centroid\", found \"";
            what += json_printable(pivot.value->text);
            what += '"';
            return error(pivot, what);
        }
        if (pivot.value->type != JsonType::array) {
            return expected(pivot, "[x, y, z] or \"centroid\"");
        }
        out.pivot_is_centroid = false;
        return vec(pivot, out.pivot);
    }

    ToolStatus targets(const Field& f, std::size_t n, std::vector<glm::dvec3>& out) const {
        if (ToolStatus s = typed(f, JsonType::array, "an array of [x, y, z] targets"); !s) return s;
        if (f.value->items.size() != n) {
            std::string what = std::to_string(n);
            what += n == 1 ? " target, one per vertex" : " targets, one per vertex";
            return expected(f, what);
        }
        out.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            if (ToolStatus s = vec(item(f, i), out[i]); !s) return s;
        }
        return ToolStatus::ok();
    }

    ToolStatus solver(const Field& f, SolverSpec& out) const {
        if (ToolStatus s = object(f, {"tolerance", "max_iterations", "handle_weight", "method"});
            !s) {
            return s;
        }
        if (const Field t = member(f, "tolerance"); t.value) {
            if (ToolStatus s = positive(t, out.tolerance.emplace()); !s) return s;
        }
        if (const Field m = member(f, "max_iterations"); m.value) {
            double v = 0.0;
            if (ToolStatus s = count(m, INT_MAX, v); !s) return s;
            out.max_iterations = static_cast<int>(v);
        }
        if (const Field w = member(f, "handle_weight"); w.value) {
            if (ToolStatus s = positive(w, out.handle_weight.emplace()); !s) return s;
        }
        if (const Field m = member(f, "method"); m.value) {
            if (m.value->type != JsonType::string ||
                (m.value->text != "fitted_rotations" && m.value->text != "paper")) {
                return expected(m, "\"fitted_rotations\" or \"paper\"");
            }
            out.method = m.value->text;
        }
        return ToolStatus::ok();
    }

    std::string_view source_;
};

ToolStatus out_of_memory(std::string_view source) {
    std::string message(source);
    message += ": out of memory while reading the scenario";
    return ToolStatus(DFM_ERROR_OUT_OF_MEMORY, std::move(message));
}

ToolStatus read_scenario_file(const std::filesystem::path& path, std::string& text) {
    const std::string name = path.string();
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (st.type() == std::filesystem::file_type::not_found) {
        return ToolStatus(DFM_ERROR_NOT_FOUND, name + ": no such scenario file");
    }
    if (ec) return ToolStatus(DFM_ERROR_IO, name + ": cannot access: " + ec.message());
    if (std::filesystem::is_directory(st)) {
        return ToolStatus(DFM_ERROR_IO, name + ": is a directory, not a scenario file");
    }
    // A device or pipe could feed bytes forever.
    if (!std::filesystem::is_regular_file(st)) {
        return ToolStatus(DFM_ERROR_IO, name + ": is not a regular file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) return ToolStatus(DFM_ERROR_IO, name + ": cannot open: " + std::strerror(errno));
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
        text.append(buffer, static_cast<std::size_t>(in.gcount()));
    }
    if (in.bad()) return ToolStatus(DFM_ERROR_IO, name + ": read failed");
    return ToolStatus::ok();
}

}  // namespace

ToolStatus parse_scenario(std::string_view text, std::string_view source, Scenario& out) {
    out = Scenario{};
    try {
        JsonValue root;
        if (ToolStatus s = read_json(text, source, root); !s) return s;
        Scenario scenario;
        if (ToolStatus s = ScenarioReader(source).scenario(root, scenario); !s) return s;
        out = std::move(scenario);
        return ToolStatus::ok();
    } catch (const std::bad_alloc&) {
        return out_of_memory(source);
    }
}

ToolStatus parse_camera(std::string_view text, std::string_view source, dfm_camera& out) {
    out = dfm_camera{};
    try {
        JsonValue root;
        if (ToolStatus s = read_json(text, source, root); !s) return s;
        dfm_camera camera{};
        if (ToolStatus s = ScenarioReader(source).camera_document(root, camera); !s) return s;
        out = camera;
        return ToolStatus::ok();
    } catch (const std::bad_alloc&) {
        return out_of_memory(source);
    }
}

ToolStatus read_camera_argument(std::string_view argument, dfm_camera& out) {
    const std::size_t start = argument.find_first_not_of(" \t\r\n");
    if (start != std::string_view::npos && argument[start] == '{') {
        return parse_camera(argument, "--camera", out);
    }
    const std::string path(argument);
    std::ifstream in(path, std::ios::binary);
    if (!in) return ToolStatus(DFM_ERROR_IO, path + ": cannot open: " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) return ToolStatus(DFM_ERROR_IO, path + ": read failed");
    return parse_camera(text.str(), path, out);
}

ToolStatus load_scenario(const std::filesystem::path& path, Scenario& out) {
    out = Scenario{};
    try {
        std::string text;
        if (ToolStatus s = read_scenario_file(path, text); !s) return s;
        Scenario scenario;
        if (ToolStatus s = parse_scenario(text, path.string(), scenario); !s) return s;
        scenario.base_dir = path.parent_path();
        out = std::move(scenario);
        return ToolStatus::ok();
    } catch (const std::bad_alloc&) {
        return out_of_memory(path.string());
    }
}

}  // namespace dfm::cli
