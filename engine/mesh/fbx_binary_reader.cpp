#include <cstring>
#include <new>

#include "mesh/fbx_document.hpp"

// The binary node format: after the 23-byte magic and a 32-bit version, a
// list of node records, each [end offset, property count, property list
// length, name length (1 byte), name, properties, nested list], the nested
// list closed by a null record (all zero header) when present, the top-level
// list too; then a footer. Up to 7.4 the first three header fields are 32-bit
// (13-byte null record), from 7.5 64-bit (25 bytes). All little-endian.
namespace dfm::mesh {

namespace {

constexpr std::size_t version_offset = fbx_binary_magic.size();
constexpr std::size_t first_node = version_offset + 4;

// A deflate stream inflates to at most 1032 times its length; zlib's
// 2-byte header and 4-byte checksum only shrink that.
constexpr std::uint64_t max_inflate_ratio = 1032;

std::uint64_t read_le(const std::string& b, std::size_t at, std::size_t width) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < width; ++i) {
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[at + i])) << (8 * i);
    }
    return v;
}

std::size_t scalar_width(char type) {
    switch (type) {
        case 'Y': return 2;
        case 'C': return 1;
        case 'I':
        case 'F': return 4;
        case 'D':
        case 'L': return 8;
        default: return 0;
    }
}

std::string printable(std::string_view name) {
    std::string out;
    for (char c : name) {
        out += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return out;
}

class BinaryParser {
public:
    explicit BinaryParser(FbxDocument& doc)
        : doc_(doc), b_(doc.bytes), wide_(doc.version >= 7500), header_(wide_ ? 25 : 13) {}

    Status parse() {
        std::size_t at = first_node;
        while (true) {
            bool null_record = false;
            std::uint32_t node = no_index;
            if (Status s = read_node(at, b_.size(), 1, no_index, node, null_record); !s) {
                return s;
            }
            if (null_record) {
                doc_.footer = at + header_;
                return Status::ok();
            }
            doc_.roots.push_back(node);
            at = doc_.nodes[node].end;
        }
    }

private:
    Status error(std::size_t at, const std::string& path, const std::string& what) const {
        return Where::byte(doc_.source, at)
            .parse_error(path.empty() ? what : "node " + path + ": " + what);
    }

    // A node's path for a message, from its parent's (built only then).
    std::string path_of(std::uint32_t parent, std::string_view name) const {
        const std::string own = printable(name);
        return parent == no_index ? own : doc_.path(doc_.nodes[parent]) + "/" + own;
    }

    // Reads the node record at `at`, which must end by `limit`.
    Status read_node(std::size_t at, std::size_t limit, std::size_t depth, std::uint32_t parent,
                     std::uint32_t& out, bool& null_record) {
        null_record = false;
        const auto parent_path = [&] {
            return parent == no_index ? std::string() : doc_.path(doc_.nodes[parent]);
        };
        if (limit - at < header_) {
            if (limit == b_.size()) {
                return error(at, parent_path(),
                             "truncated: the file ends " + std::to_string(limit - at) +
                                 " bytes into a node header of " + std::to_string(header_) +
                                 (parent == no_index ? " (no top-level null record)" : ""));
            }
            return error(at, parent_path(),
                         "a node header of " + std::to_string(header_) +
                             " bytes does not fit before its parent's end at byte " +
                             std::to_string(limit));
        }
        const std::size_t w = wide_ ? 8 : 4;
        const std::uint64_t end = read_le(b_, at, w);
        const std::uint64_t count = read_le(b_, at + w, w);
        const std::uint64_t length = read_le(b_, at + 2 * w, w);
        const std::size_t name_length = static_cast<unsigned char>(b_[at + 3 * w]);
        if (end == 0) {
            if (count != 0 || length != 0 || name_length != 0) {
                return error(at, parent_path(),
                             "a null record (end offset 0) with a non-zero header");
            }
            null_record = true;
            return Status::ok();
        }
        const std::string_view name(b_.data() + at + header_,
                                    std::min<std::size_t>(name_length, limit - at - header_));
        const auto path = [&] { return path_of(parent, name); };
        if (end <= at || end > limit) {
            return error(at, path(),
                         "its record ends at byte " + std::to_string(end) + ", " +
                             (end <= at ? "before it starts"
                                        : "past " +
                                              std::string(limit == b_.size() ? "the end of the file"
                                                                             : "its parent's end") +
                                              " at byte " + std::to_string(limit)));
        }
        if (depth > fbx_max_depth) {
            return error(at, path(),
                         "nodes nest deeper than " + std::to_string(fbx_max_depth) + " levels");
        }
        const std::size_t props_begin = at + header_ + name_length;
        if (props_begin > end || length > end - props_begin) {
            return error(at, path(),
                         "its name and property list (" + std::to_string(length) +
                             " bytes) run past its record's end at byte " + std::to_string(end));
        }
        // Each property takes at least two bytes.
        if (count > length / 2) {
            return error(at, path(),
                         std::to_string(count) + " properties cannot fit in " +
                             std::to_string(length) + " bytes");
        }
        FbxNode node;
        node.name = std::string_view(b_.data() + at + header_, name_length);
        node.parent = parent;
        node.begin = at;
        node.end = static_cast<std::size_t>(end);
        node.properties_end = props_begin + static_cast<std::size_t>(length);
        node.first_property = static_cast<std::uint32_t>(doc_.properties.size());
        node.property_count = static_cast<std::uint32_t>(count);
        std::size_t p = props_begin;
        for (std::uint64_t i = 0; i < count; ++i) {
            if (Status s = read_property(p, node.properties_end, parent, name, i); !s) return s;
        }
        if (p != node.properties_end) {
            return error(p, path(),
                         "its " + std::to_string(count) + " properties end " +
                             std::to_string(node.properties_end - p) +
                             " bytes before the declared property list length");
        }
        const std::uint32_t index = static_cast<std::uint32_t>(doc_.nodes.size());
        doc_.nodes.push_back(std::move(node));
        out = index;
        const std::size_t properties_end = doc_.nodes[index].properties_end;
        const std::size_t record_end = doc_.nodes[index].end;
        if (properties_end == record_end) return Status::ok();
        if (record_end - properties_end < header_) {
            return error(properties_end, path(),
                         std::to_string(record_end - properties_end) +
                             " bytes after its properties, too few for a nested list's null "
                             "record");
        }
        const std::size_t list_end = record_end - header_;
        std::size_t c = properties_end;
        while (c < list_end) {
            std::uint32_t child = no_index;
            bool child_null = false;
            if (Status s = read_node(c, list_end, depth + 1, index, child, child_null); !s) {
                return s;
            }
            if (child_null) {
                return error(c, path(), "a null record inside its nested list, before its end");
            }
            doc_.nodes[index].children.push_back(child);
            c = doc_.nodes[child].end;
        }
        for (std::size_t i = list_end; i < record_end; ++i) {
            if (b_[i] != 0) {
                return error(list_end, path(), "its nested list does not end with a null record");
            }
        }
        doc_.nodes[index].null_record = true;
        return Status::ok();
    }

    Status read_property(std::size_t& p, std::size_t limit, std::uint32_t parent,
                         std::string_view name, std::uint64_t i) {
        const auto path = [&] { return path_of(parent, name); };
        const auto which = [&] { return "property " + std::to_string(i); };
        if (p >= limit) return error(p, path(), which() + ": past the property list's end");
        const char type = b_[p];
        FbxProperty prop;
        prop.type = type;
        prop.begin = p + 1;
        const std::size_t left = limit - prop.begin;
        if (const std::size_t width = scalar_width(type); width != 0) {
            if (left < width) return error(p, path(), which() + ": truncated value");
            prop.end = prop.begin + width;
        } else if (type == 'S' || type == 'R') {
            if (left < 4) return error(p, path(), which() + ": truncated length");
            const std::uint64_t n = read_le(b_, prop.begin, 4);
            if (n > left - 4) {
                return error(p, path(),
                             which() + ": a " + std::to_string(n) + "-byte " +
                                 (type == 'S' ? "string" : "raw value") + " runs past the " +
                                 std::to_string(left - 4) + " bytes left");
            }
            prop.end = prop.begin + 4 + static_cast<std::size_t>(n);
        } else if (const std::size_t width = fbx_array_width(type); width != 0) {
            if (left < 12) return error(p, path(), which() + ": truncated array header");
            const std::uint64_t n = read_le(b_, prop.begin, 4);
            const std::uint64_t encoding = read_le(b_, prop.begin + 4, 4);
            const std::uint64_t stored = read_le(b_, prop.begin + 8, 4);
            if (stored > left - 12) {
                return error(p, path(),
                             which() + ": an array of " + std::to_string(stored) +
                                 " stored bytes runs past the " + std::to_string(left - 12) +
                                 " bytes left");
            }
            const std::uint64_t bytes = n * width;
            if (encoding == 0 && stored != bytes) {
                return error(p, path(),
                             which() + ": an array of " + std::to_string(n) + " elements of " +
                                 std::to_string(width) + " bytes stored in " +
                                 std::to_string(stored) + " bytes");
            }
            if (encoding == 1 && bytes > stored * max_inflate_ratio) {
                return error(p, path(),
                             which() + ": an array of " + std::to_string(n) +
                                 " elements cannot inflate from " + std::to_string(stored) +
                                 " compressed bytes");
            }
            if (encoding > 1) {
                return error(p, path(),
                             which() + ": unknown array encoding " + std::to_string(encoding));
            }
            prop.count = static_cast<std::uint32_t>(n);
            prop.encoding = static_cast<std::uint32_t>(encoding);
            prop.end = prop.begin + 12 + static_cast<std::size_t>(stored);
        } else {
            static constexpr char hex[] = "0123456789abcdef";
            const auto code = static_cast<unsigned char>(type);
            return error(p, path(),
                         which() + ": unknown type code 0x" + hex[code >> 4] + hex[code & 15] +
                             " ('" + printable(std::string_view(&type, 1)) + "')");
        }
        doc_.properties.push_back(prop);
        p = prop.end;
        return Status::ok();
    }

    FbxDocument& doc_;
    const std::string& b_;
    bool wide_;
    std::size_t header_;
};

}  // namespace

Status parse_fbx_binary(std::string bytes, std::string source, FbxDocument& out) {
    out = FbxDocument{};
    out.source = std::move(source);
    out.bytes = std::move(bytes);
    const Where start = Where::byte(out.source, 0);
    if (!out.bytes.starts_with(fbx_binary_magic)) {
        return start.parse_error("not a binary FBX file (no 'Kaydara FBX Binary' magic)");
    }
    if (out.bytes.size() < first_node) {
        return start.parse_error("truncated: the file ends inside its header");
    }
    out.version = static_cast<std::uint32_t>(read_le(out.bytes, version_offset, 4));
    if (out.version < 7100 || out.version >= 8000) {
        return Where::byte(out.source, version_offset)
            .error(Errc::unsupported, "FBX version " + std::to_string(out.version) +
                                          " is not supported (binary FBX 7.1 to 7.7 is read)");
    }
    Status s = BinaryParser(out).parse();
    if (!s) {
        const std::string source_name = std::move(out.source);
        out = FbxDocument{};
        out.source = source_name;
    }
    return s;
}

Status parse_fbx(std::string bytes, std::string source, FbxDocument& out) {
    if (std::string_view(bytes).starts_with(fbx_binary_magic.substr(0, 18))) {
        return parse_fbx_binary(std::move(bytes), std::move(source), out);
    }
    return parse_fbx_ascii(std::move(bytes), std::move(source), out);
}

}  // namespace dfm::mesh
