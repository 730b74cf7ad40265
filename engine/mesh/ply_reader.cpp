#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "mesh/ply_header.hpp"
#include "mesh/readers.hpp"
#include "mesh/text_cursor.hpp"

// PLY in ascii and both binary byte orders. The "vertex" element gives x, y,
// z (any numeric type); the "face" element gives "vertex_indices" (or
// "vertex_index"), a list of any integer types. Every other element and
// property is read past and dropped.
namespace dfm::mesh {

namespace {

using ply::Element;
using ply::Encoding;
using ply::Property;
using ply::Scalar;

// Where a property's values go while a record is read.
enum class Role { skip, x, y, z, face_indices };

struct ElementPlan {
    const Element* element = nullptr;
    std::vector<Role> roles;
    bool is_vertex = false;
    bool is_face = false;
};

Status plan_elements(const ply::Header& header, std::string_view source,
                     std::vector<ElementPlan>& plans) {
    bool seen_vertex = false;
    for (const Element& e : header.elements) {
        const Where at = Where::line(source, e.line);
        ElementPlan plan;
        plan.element = &e;
        plan.is_vertex = e.name == "vertex";
        plan.is_face = e.name == "face";
        if (plan.is_face && !seen_vertex) {
            return at.error(Errc::unsupported, "element 'face' comes before element 'vertex'");
        }
        bool has[3] = {false, false, false};
        bool has_indices = false;
        for (const Property& p : e.properties) {
            Role role = Role::skip;
            if (plan.is_vertex && (p.name == "x" || p.name == "y" || p.name == "z")) {
                if (p.is_list) {
                    return at.parse_error("vertex property '" + p.name + "' must not be a list");
                }
                const int axis = p.name[0] - 'x';
                role = static_cast<Role>(static_cast<int>(Role::x) + axis);
                has[axis] = true;
            } else if (plan.is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) {
                if (!p.is_list || !ply::scalar_is_integer(p.type)) {
                    return at.parse_error("face property '" + p.name +
                                          "' must be a list of integers");
                }
                if (has_indices) {
                    return at.parse_error(
                        "element 'face' has both vertex_indices and vertex_index");
                }
                role = Role::face_indices;
                has_indices = true;
            }
            plan.roles.push_back(role);
        }
        if (plan.is_vertex) {
            seen_vertex = true;
            for (int axis = 0; axis < 3; ++axis) {
                if (!has[axis]) {
                    return at.parse_error(std::string("element 'vertex' has no '") +
                                          static_cast<char>('x' + axis) + "' property");
                }
            }
        }
        if (plan.is_face && !has_indices && e.count > 0) {
            return at.parse_error("element 'face' has no 'vertex_indices' list");
        }
        plans.push_back(std::move(plan));
    }
    if (!seen_vertex) {
        return Where::line(source, header.body_first_line - 1)
            .parse_error("header declares no 'vertex' element");
    }
    return Status::ok();
}

// The fewest bytes one record of `e` can take, so declared counts can be
// checked against the input's size before anything is allocated.
std::uint64_t min_record_bytes(const Element& e, Encoding encoding) {
    std::uint64_t n = 0;
    for (const Property& p : e.properties) {
        if (encoding == Encoding::ascii) {
            n += 2;  // a digit and a separator
        } else {
            n += ply::scalar_size(p.is_list ? p.count_type : p.type);
        }
    }
    return n;
}

Status check_declared_sizes(const ply::Header& header, std::string_view source,
                            std::uint64_t available) {
    std::uint64_t needed = 0;
    for (const Element& e : header.elements) {
        const std::uint64_t per = min_record_bytes(e, header.encoding);
        if (per == 0) continue;  // no properties: its records hold nothing to read
        if (e.count > (available + 1) / per || needed + e.count * per > available + 1) {
            return Where::line(source, e.line)
                .parse_error("element '" + e.name + "' declares " + std::to_string(e.count) +
                             " records, more than the " + std::to_string(available) +
                             " bytes after the header can hold (truncated file or wrong count)");
        }
        needed += e.count * per;
    }
    return Status::ok();
}

// Reads one scalar at a time from the body, as text or as bytes.
class ValueSource {
public:
    ValueSource(std::string_view body, std::size_t body_offset, const ply::Header& header,
                std::string_view source)
        : body_(body),
          body_offset_(body_offset),
          encoding_(header.encoding),
          source_(source),
          text_(body, '\0', header.body_first_line) {}

    // Where the next value starts.
    Where where() {
        if (encoding_ == Encoding::ascii) {
            text_.skip_blanks();
            return Where::line(source_, text_.upcoming_line());
        }
        return Where::byte(source_, body_offset_ + pos_);
    }

    Status read(Scalar type, double& value, std::string_view what) {
        if (encoding_ == Encoding::ascii) return read_text(type, value, what);
        return read_binary(type, value, what);
    }

private:
    Status read_text(Scalar type, double& value, std::string_view what) {
        std::string_view token;
        const bool found = text_.next_token(token);
        const Where at = Where::line(source_, text_.line());
        if (!found) return at.parse_error(std::string(what) + ": truncated, the file ends here");
        if (ply::scalar_is_integer(type)) {
            std::int64_t i = 0;
            if (const NumberError e = parse_integer(token, i); e != NumberError::none) {
                return at.parse_error(std::string(what) + ": " + quote_token(token) + " is " +
                                      std::string(describe_number_error(e)));
            }
            value = static_cast<double>(i);
            return Status::ok();
        }
        if (const NumberError e = parse_double(token, value); e != NumberError::none) {
            return at.parse_error(std::string(what) + ": " + quote_token(token) + " is " +
                                  std::string(describe_number_error(e)));
        }
        return Status::ok();
    }

    Status read_binary(Scalar type, double& value, std::string_view what) {
        const std::size_t size = ply::scalar_size(type);
        if (body_.size() - pos_ < size) {
            return where().parse_error(std::string(what) + ": truncated, the file ends here");
        }
        unsigned char raw[8];
        std::memcpy(raw, body_.data() + pos_, size);
        const bool swap =
            (encoding_ == Encoding::binary_big_endian) != (std::endian::native == std::endian::big);
        if (swap) {
            for (std::size_t i = 0; i < size / 2; ++i) std::swap(raw[i], raw[size - 1 - i]);
        }
        pos_ += size;
        value = decode(type, raw);
        return Status::ok();
    }

    static double decode(Scalar type, const unsigned char* raw) {
        switch (type) {
            case Scalar::int8: return load<std::int8_t>(raw);
            case Scalar::uint8: return load<std::uint8_t>(raw);
            case Scalar::int16: return load<std::int16_t>(raw);
            case Scalar::uint16: return load<std::uint16_t>(raw);
            case Scalar::int32: return load<std::int32_t>(raw);
            case Scalar::uint32: return load<std::uint32_t>(raw);
            case Scalar::float32: return load<float>(raw);
            case Scalar::float64: return load<double>(raw);
        }
        return 0.0;
    }

    template <typename T>
    static double load(const unsigned char* raw) {
        T v;
        std::memcpy(&v, raw, sizeof v);
        return static_cast<double>(v);
    }

    std::string_view body_;
    std::size_t body_offset_;
    Encoding encoding_;
    std::string_view source_;
    TextCursor text_;
    std::size_t pos_ = 0;
};

// Clamped so an absurd value stays out of range instead of overflowing.
std::int64_t index_from(double v) {
    constexpr double limit = 9.0e18;
    if (v >= limit) return std::numeric_limits<std::int64_t>::max();
    if (v <= -limit) return std::numeric_limits<std::int64_t>::min();
    return static_cast<std::int64_t>(v);
}

Status read_list_count(ValueSource& in, const Property& p, const std::string& what,
                       std::uint64_t& count) {
    const Where at = in.where();
    double c = 0.0;
    if (Status s = in.read(p.count_type, c, what + " list count"); !s) return s;
    if (c < 0) {
        return at.parse_error(what + ": list count " + std::to_string(static_cast<long long>(c)) +
                              " is negative");
    }
    count = static_cast<std::uint64_t>(c);
    return Status::ok();
}

Status read_element(ValueSource& in, const ElementPlan& plan, MeshBuilder& builder,
                    std::vector<std::int64_t>& corners) {
    const Element& e = *plan.element;
    if (e.properties.empty()) return Status::ok();
    for (std::uint64_t r = 0; r < e.count; ++r) {
        const Where record_at = in.where();
        const std::string what = e.name + " " + std::to_string(r);
        glm::dvec3 p(0.0);
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& prop = e.properties[k];
            const Role role = plan.roles[k];
            const std::string prop_what = what + " property '" + prop.name + "'";
            if (!prop.is_list) {
                double v = 0.0;
                if (Status s = in.read(prop.type, v, prop_what); !s) return s;
                if (role != Role::skip) p[static_cast<int>(role) - static_cast<int>(Role::x)] = v;
                continue;
            }
            const Where count_at = in.where();
            std::uint64_t count = 0;
            if (Status s = read_list_count(in, prop, prop_what, count); !s) return s;
            if (role == Role::face_indices) {
                if (Status s = builder.check_polygon_size(count, count_at); !s) return s;
            }
            corners.clear();
            for (std::uint64_t i = 0; i < count; ++i) {
                double v = 0.0;
                if (Status s = in.read(prop.type, v, prop_what); !s) return s;
                if (role == Role::face_indices) corners.push_back(index_from(v));
            }
            if (role == Role::face_indices) {
                if (Status s = builder.add_polygon(corners, record_at); !s) return s;
            }
        }
        if (plan.is_vertex) {
            if (Status s = builder.add_vertex(p, record_at); !s) return s;
        }
    }
    return Status::ok();
}

}  // namespace

Status read_ply(std::string_view bytes, std::string_view source, MeshBuilder& builder) {
    ply::Header header;
    if (Status s = ply::parse_header(bytes, source, header); !s) return s;
    std::vector<ElementPlan> plans;
    if (Status s = plan_elements(header, source, plans); !s) return s;
    const std::string_view body = bytes.substr(header.body_offset);
    if (Status s = check_declared_sizes(header, source, body.size()); !s) return s;

    std::uint64_t vertices = 0;
    std::uint64_t faces = 0;
    for (const ElementPlan& plan : plans) {
        if (plan.is_vertex) vertices = plan.element->count;
        if (plan.is_face) faces = plan.element->count;
    }
    // Only a hint: capped so that what is reserved stays proportional to the
    // file however the header's counts were made up.
    builder.reserve(std::min<std::uint64_t>(vertices, body.size() / 6),
                    std::min<std::uint64_t>(faces, body.size() / 8));

    ValueSource in(body, header.body_offset, header, source);
    std::vector<std::int64_t> corners;
    for (const ElementPlan& plan : plans) {
        if (Status s = read_element(in, plan, builder, corners); !s) return s;
    }
    return Status::ok();
}

}  // namespace dfm::mesh
