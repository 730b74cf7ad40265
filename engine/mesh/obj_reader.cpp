#include <set>
#include <string>
#include <vector>

#include "mesh/readers.hpp"
#include "mesh/text_cursor.hpp"

// Wavefront OBJ: "v" positions and "f" faces in the forms v, v/vt, v//vn and
// v/vt/vn, with 1-based or negative (relative) indices. Texture coordinates
// and normals are checked but not kept; groups, objects, materials, smoothing
// groups, lines and points are skipped. A face may only use vertices defined
// above it.
namespace dfm::mesh {

namespace {

struct ObjCounts {
    std::int64_t positions = 0;
    std::int64_t texcoords = 0;
    std::int64_t normals = 0;
};

// Turns an OBJ reference (1-based, or negative from the end) into a 0-based
// index, or explains why it cannot.
Status resolve(std::string_view token, const char* kind, std::int64_t defined,
               const std::string& face, const Where& at, std::int64_t& index) {
    std::int64_t value = 0;
    if (const NumberError e = parse_integer(token, value); e != NumberError::none) {
        return at.parse_error(face + kind + " index " + quote_token(token) + " is " +
                              std::string(describe_number_error(e)));
    }
    if (value == 0) {
        return at.error(Errc::out_of_range,
                        face + kind + " index 0 is invalid (OBJ counts from 1)");
    }
    index = value > 0 ? value - 1 : defined + value;
    if (index < 0 || index >= defined) {
        return at.error(Errc::out_of_range, face + kind + " index " + std::to_string(value) +
                                                " is out of range (" + std::to_string(defined) +
                                                " defined so far)");
    }
    return Status::ok();
}

Status read_numbers(Tokens& tokens, int count, const char* what, const Where& at, double* out) {
    for (int c = 0; c < count; ++c) {
        std::string_view token;
        if (!tokens.next(token)) {
            return at.parse_error(std::string(what) + ": expected " + std::to_string(count) +
                                  " numbers, found " + std::to_string(c));
        }
        if (const NumberError e = parse_double(token, out[c]); e != NumberError::none) {
            return at.parse_error(std::string(what) + ": " + quote_token(token) + " is " +
                                  std::string(describe_number_error(e)));
        }
    }
    return Status::ok();
}

Status read_face(Tokens& tokens, const ObjCounts& counts, std::size_t face_index, const Where& at,
                 MeshBuilder& builder, std::vector<std::int64_t>& corners) {
    const std::string face = "face " + std::to_string(face_index) + ": ";
    corners.clear();
    std::string_view token;
    while (tokens.next(token)) {
        const std::size_t slash1 = token.find('/');
        std::int64_t v = 0;
        if (Status s = resolve(token.substr(0, slash1), "vertex", counts.positions, face, at, v);
            !s) {
            return s;
        }
        if (slash1 != std::string_view::npos) {
            const std::string_view rest = token.substr(slash1 + 1);
            const std::size_t slash2 = rest.find('/');
            const std::string_view vt = rest.substr(0, slash2);
            std::int64_t unused = 0;
            if (!vt.empty()) {
                if (Status s =
                        resolve(vt, "texture coordinate", counts.texcoords, face, at, unused);
                    !s) {
                    return s;
                }
            }
            if (slash2 != std::string_view::npos) {
                const std::string_view vn = rest.substr(slash2 + 1);
                if (vn.find('/') != std::string_view::npos || (vn.empty() && vt.empty())) {
                    return at.parse_error(face + "malformed corner " + quote_token(token));
                }
                if (!vn.empty()) {
                    if (Status s = resolve(vn, "normal", counts.normals, face, at, unused); !s) {
                        return s;
                    }
                }
            } else if (vt.empty()) {
                return at.parse_error(face + "malformed corner " + quote_token(token));
            }
        }
        corners.push_back(v);
    }
    return builder.add_polygon(corners, at);
}

}  // namespace

Status read_obj(std::string_view text, std::string_view source, MeshBuilder& builder) {
    TextCursor cursor(text, '#');
    ObjCounts counts;
    std::vector<std::int64_t> corners;
    std::set<std::string, std::less<>> unknown_keywords;
    std::string_view line;
    bool any_line = false;
    while (cursor.next_line(line)) {
        any_line = true;
        const Where at = Where::line(source, cursor.line());
        Tokens tokens(line);
        std::string_view keyword;
        tokens.next(keyword);
        if (keyword == "v") {
            glm::dvec3 p;
            const std::string what = "vertex " + std::to_string(counts.positions);
            if (Status s = read_numbers(tokens, 3, what.c_str(), at, &p.x); !s) return s;
            if (Status s = builder.add_vertex(p, at); !s) return s;
            ++counts.positions;
        } else if (keyword == "vt") {
            double uv = 0.0;
            const std::string what = "texture coordinate " + std::to_string(counts.texcoords);
            if (Status s = read_numbers(tokens, 1, what.c_str(), at, &uv); !s) return s;
            ++counts.texcoords;
        } else if (keyword == "vn") {
            glm::dvec3 n;
            const std::string what = "normal " + std::to_string(counts.normals);
            if (Status s = read_numbers(tokens, 3, what.c_str(), at, &n.x); !s) return s;
            ++counts.normals;
        } else if (keyword == "f") {
            if (Status s = read_face(tokens, counts, builder.polygon_count(), at, builder, corners);
                !s) {
                return s;
            }
        } else if (keyword == "g" || keyword == "o" || keyword == "s" || keyword == "usemtl" ||
                   keyword == "mtllib" || keyword == "l" || keyword == "p" || keyword == "vp") {
            continue;
        } else {
            if (unknown_keywords.emplace(keyword).second) {
                builder.warn(at, "unknown keyword " + quote_token(keyword) + " skipped");
            }
        }
    }
    if (!any_line) {
        return Where::line(source, cursor.line()).parse_error("no OBJ data: the file is empty");
    }
    if (counts.positions == 0) {
        return Where::line(source, cursor.line())
            .parse_error("no vertex ('v') lines: not an OBJ mesh");
    }
    return Status::ok();
}

}  // namespace dfm::mesh
