#include "mesh/fbx_binary_writer.hpp"

#include <cstring>
#include <new>

#include <zlib.h>

namespace dfm::mesh {

namespace {

template <typename T>
void put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    out.append(b, sizeof v);
}

void put_array(FbxOutNode& node, char type, const void* data, std::size_t count,
               std::size_t width) {
    const std::size_t size = count * width;
    std::string stored;
    std::uint32_t encoding = 0;
    if (size > 128) {
        uLongf bound = compressBound(static_cast<uLong>(size));
        stored.resize(bound);
        if (compress2(reinterpret_cast<Bytef*>(stored.data()), &bound,
                      static_cast<const Bytef*>(data), static_cast<uLong>(size), 1) != Z_OK) {
            throw std::bad_alloc();
        }
        stored.resize(bound);
        encoding = 1;
    } else {
        stored.assign(static_cast<const char*>(data), size);
    }
    node.properties += type;
    put<std::uint32_t>(node.properties, static_cast<std::uint32_t>(count));
    put<std::uint32_t>(node.properties, encoding);
    put<std::uint32_t>(node.properties, static_cast<std::uint32_t>(stored.size()));
    node.properties += stored;
    ++node.property_count;
}

void write_node(const FbxOutNode& node, bool wide, std::string& out) {
    const std::size_t at = out.size();
    const std::size_t header = wide ? 25 : 13;
    out.append(header, '\0');
    out += node.name;
    out += node.properties;
    const auto field = [&](std::size_t i, std::uint64_t v) {
        if (wide) {
            std::memcpy(out.data() + at + 8 * i, &v, 8);
        } else {
            const auto v32 = static_cast<std::uint32_t>(v);
            std::memcpy(out.data() + at + 4 * i, &v32, 4);
        }
    };
    field(1, node.property_count);
    field(2, node.properties.size());
    out[at + header - 1] = static_cast<char>(node.name.size());
    for (const FbxOutNode& child : node.children) write_node(child, wide, out);
    if (!node.children.empty() || node.null_record) out.append(header, '\0');
    field(0, out.size());
}

constexpr std::string_view footer_magic{
    "\xf8\x5a\x8c\x6a\xde\xf5\xd9\x7e\xec\xe9\x0c\xe3\x75\x8f\x29\x0b", 16};

// FBX writers end a file with a 16-byte id, 4 zero bytes, zeros up to the
// next multiple of 16 (16 when already there), the version, 120 zeros and a
// fixed 16-byte magic.
void write_footer(const FbxDocument& doc, std::uint32_t version, std::string& out) {
    const std::string_view tail = std::string_view(doc.bytes).substr(doc.footer);
    const std::size_t fixed = 4 + 120 + footer_magic.size();
    const auto zeros = [&](std::size_t from, std::size_t to) {
        for (std::size_t i = from; i < to; ++i) {
            if (tail[i] != 0) return false;
        }
        return true;
    };
    const bool layout = tail.size() >= 16 + 4 + 1 + fixed && tail.ends_with(footer_magic) &&
                        zeros(16, tail.size() - fixed) &&
                        zeros(tail.size() - fixed + 4, tail.size() - footer_magic.size());
    if (!layout) {
        out += tail;
        return;
    }
    out += tail.substr(0, 16);
    out.append(4, '\0');
    std::size_t pad = ((out.size() + 15) & ~std::size_t{15}) - out.size();
    if (pad == 0) pad = 16;
    out.append(pad, '\0');
    put<std::uint32_t>(out, version);
    out.append(120, '\0');
    out += footer_magic;
}

}  // namespace

FbxOutNode FbxOutNode::named(std::string_view name) {
    FbxOutNode n;
    n.name = std::string(name);
    return n;
}

FbxOutNode& FbxOutNode::add_int32(std::int32_t v) {
    properties += 'I';
    put(properties, v);
    ++property_count;
    return *this;
}

FbxOutNode& FbxOutNode::add_int64(std::int64_t v) {
    properties += 'L';
    put(properties, v);
    ++property_count;
    return *this;
}

FbxOutNode& FbxOutNode::add_double(double v) {
    properties += 'D';
    put(properties, v);
    ++property_count;
    return *this;
}

FbxOutNode& FbxOutNode::add_string(std::string_view v) {
    properties += 'S';
    put<std::uint32_t>(properties, static_cast<std::uint32_t>(v.size()));
    properties += v;
    ++property_count;
    return *this;
}

FbxOutNode& FbxOutNode::add_int32_array(std::span<const std::int32_t> v) {
    put_array(*this, 'i', v.data(), v.size(), 4);
    return *this;
}

FbxOutNode& FbxOutNode::add_double_array(std::span<const double> v) {
    put_array(*this, 'd', v.data(), v.size(), 8);
    return *this;
}

FbxOutNode& FbxOutNode::add_child(std::string_view child_name) {
    children.push_back(named(child_name));
    return children.back();
}

FbxOutNode fbx_out_node(const FbxDocument& doc, std::uint32_t index) {
    const FbxNode& n = doc.nodes[index];
    FbxOutNode out;
    out.name = std::string(n.name);
    const std::size_t first =
        n.property_count > 0 ? doc.property(n, 0).begin - 1 : n.properties_end;
    out.properties = doc.bytes.substr(first, n.properties_end - first);
    out.property_count = n.property_count;
    out.null_record = n.null_record;
    out.children.reserve(n.children.size());
    for (std::uint32_t c : n.children) out.children.push_back(fbx_out_node(doc, c));
    return out;
}

std::vector<FbxOutNode> fbx_out_tree(const FbxDocument& doc) {
    std::vector<FbxOutNode> roots;
    roots.reserve(doc.roots.size());
    for (std::uint32_t r : doc.roots) roots.push_back(fbx_out_node(doc, r));
    return roots;
}

std::string encode_fbx(const FbxDocument& doc, const std::vector<FbxOutNode>& roots,
                       std::uint32_t version) {
    const bool wide = version >= 7500;
    std::string out(fbx_binary_magic);
    put<std::uint32_t>(out, version);
    for (const FbxOutNode& node : roots) write_node(node, wide, out);
    out.append(wide ? 25 : 13, '\0');
    write_footer(doc, version, out);
    return out;
}

}  // namespace dfm::mesh
