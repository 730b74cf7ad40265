#include "mesh/ply_header.hpp"

#include "mesh/text_cursor.hpp"
#include "mesh/where.hpp"

namespace dfm::mesh::ply {

std::size_t scalar_size(Scalar type) {
    switch (type) {
        case Scalar::int8:
        case Scalar::uint8: return 1;
        case Scalar::int16:
        case Scalar::uint16: return 2;
        case Scalar::int32:
        case Scalar::uint32:
        case Scalar::float32: return 4;
        case Scalar::float64: return 8;
    }
    return 0;
}

bool scalar_is_integer(Scalar type) {
    return type != Scalar::float32 && type != Scalar::float64;
}

namespace {

std::optional<Scalar> scalar_from_name(std::string_view name) {
    struct Entry {
        std::string_view name;
        Scalar type;
    };
    static constexpr Entry table[] = {
        {"char", Scalar::int8},       {"int8", Scalar::int8},       {"uchar", Scalar::uint8},
        {"uint8", Scalar::uint8},     {"short", Scalar::int16},     {"int16", Scalar::int16},
        {"ushort", Scalar::uint16},   {"uint16", Scalar::uint16},   {"int", Scalar::int32},
        {"int32", Scalar::int32},     {"uint", Scalar::uint32},     {"uint32", Scalar::uint32},
        {"float", Scalar::float32},   {"float32", Scalar::float32}, {"double", Scalar::float64},
        {"float64", Scalar::float64},
    };
    for (const Entry& e : table) {
        if (e.name == name) return e.type;
    }
    return std::nullopt;
}

Status parse_type(Tokens& tokens, const Where& at, const char* role, Scalar& type) {
    std::string_view token;
    if (!tokens.next(token)) {
        return at.parse_error(std::string("property: missing the ") + role + " type");
    }
    const std::optional<Scalar> t = scalar_from_name(token);
    if (!t) {
        return at.parse_error(std::string("property: unknown ") + role + " type " +
                              quote_token(token));
    }
    type = *t;
    return Status::ok();
}

Status parse_property(Tokens& tokens, const Where& at, Element& element) {
    Property prop;
    Tokens probe = tokens;
    std::string_view first;
    probe.next(first);
    if (first == "list") {
        tokens = probe;
        prop.is_list = true;
        if (Status s = parse_type(tokens, at, "list count", prop.count_type); !s) return s;
        if (!scalar_is_integer(prop.count_type)) {
            return at.parse_error("property list: the count type must be an integer type");
        }
        if (Status s = parse_type(tokens, at, "list item", prop.type); !s) return s;
    } else if (Status s = parse_type(tokens, at, "value", prop.type); !s) {
        return s;
    }
    std::string_view name;
    if (!tokens.next(name)) return at.parse_error("property: missing its name");
    for (const Property& p : element.properties) {
        if (p.name == name) {
            return at.parse_error("element '" + element.name + "' declares property " +
                                  quote_token(name) + " twice");
        }
    }
    prop.name = std::string(name);
    element.properties.push_back(std::move(prop));
    return Status::ok();
}

Status parse_element(Tokens& tokens, const Where& at, Header& header, std::uint64_t line) {
    std::string_view name;
    std::string_view count_token;
    if (!tokens.next(name) || !tokens.next(count_token)) {
        return at.parse_error("element: expected a name and a count");
    }
    std::int64_t count = 0;
    if (const NumberError e = parse_integer(count_token, count); e != NumberError::none) {
        return at.parse_error("element '" + std::string(name) + "': count " +
                              quote_token(count_token) + " is " +
                              std::string(describe_number_error(e)));
    }
    if (count < 0) {
        return at.parse_error("element '" + std::string(name) + "': count " +
                              std::to_string(count) + " is negative");
    }
    for (const Element& e : header.elements) {
        if (e.name == name) {
            return at.parse_error("element " + quote_token(name) + " is declared twice");
        }
    }
    header.elements.push_back({std::string(name), static_cast<std::uint64_t>(count), {}, line});
    return Status::ok();
}

Status parse_format(Tokens& tokens, const Where& at, Header& header) {
    std::string_view name;
    std::string_view version;
    if (!tokens.next(name) || !tokens.next(version)) {
        return at.parse_error("format: expected an encoding and a version");
    }
    if (name == "ascii") {
        header.encoding = Encoding::ascii;
    } else if (name == "binary_little_endian") {
        header.encoding = Encoding::binary_little_endian;
    } else if (name == "binary_big_endian") {
        header.encoding = Encoding::binary_big_endian;
    } else {
        return at.parse_error("format: unknown encoding " + quote_token(name));
    }
    if (version != "1.0") {
        return at.error(Errc::unsupported,
                        "format: version " + quote_token(version) + " is not supported (only 1.0)");
    }
    return Status::ok();
}

}  // namespace

Status parse_header(std::string_view bytes, std::string_view source, Header& header) {
    TextCursor cursor(bytes);
    std::string_view line;
    if (!cursor.next_line(line) || line != "ply") {
        return Where::line(source, cursor.line() == 0 ? 1 : cursor.line())
            .parse_error("not a PLY file: the first line must be 'ply'");
    }
    bool have_format = false;
    while (cursor.next_line(line)) {
        const Where at = Where::line(source, cursor.line());
        Tokens tokens(line);
        std::string_view keyword;
        tokens.next(keyword);
        if (keyword == "end_header") {
            if (!have_format) return at.parse_error("header has no 'format' line");
            header.body_offset = cursor.offset();
            header.body_first_line = cursor.line() + 1;
            return Status::ok();
        }
        if (keyword == "format") {
            if (have_format) return at.parse_error("header has two 'format' lines");
            if (Status s = parse_format(tokens, at, header); !s) return s;
            have_format = true;
        } else if (keyword == "element") {
            if (Status s = parse_element(tokens, at, header, cursor.line()); !s) return s;
        } else if (keyword == "property") {
            if (header.elements.empty()) {
                return at.parse_error("property declared before any element");
            }
            if (Status s = parse_property(tokens, at, header.elements.back()); !s) return s;
        } else if (keyword != "comment" && keyword != "obj_info") {
            return at.parse_error("unknown header keyword " + quote_token(keyword));
        }
    }
    return Where::line(source, cursor.line()).parse_error("truncated header: no 'end_header' line");
}

}  // namespace dfm::mesh::ply
