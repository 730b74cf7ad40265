#include "support/fbx_trees.hpp"

#include <doctest/doctest.h>

#include "mesh/load.hpp"

namespace dfm::test {

namespace {

std::string_view own_bytes(const mesh::FbxDocument& doc, const mesh::FbxNode& n) {
    const std::size_t first =
        n.property_count > 0 ? doc.property(n, 0).begin - 1 : n.properties_end;
    return std::string_view(doc.bytes).substr(first, n.properties_end - first);
}

void walk(const mesh::FbxDocument& before, const std::vector<std::uint32_t>& a,
          const mesh::FbxDocument& after, const std::vector<std::uint32_t>& b,
          const std::string& prefix, TreeDifference& out) {
    for (std::size_t i = 0; i < a.size() || i < b.size(); ++i) {
        if (i >= b.size()) {
            out.missing.push_back(prefix + std::string(before.nodes[a[i]].name));
            continue;
        }
        const mesh::FbxNode& y = after.nodes[b[i]];
        if (i >= a.size()) {
            out.added.push_back(prefix + std::string(y.name));
            continue;
        }
        const mesh::FbxNode& x = before.nodes[a[i]];
        const std::string path = prefix + std::string(x.name);
        if (x.name != y.name || own_bytes(before, x) != own_bytes(after, y) ||
            x.null_record != y.null_record) {
            out.changed.push_back(path);
        }
        walk(before, x.children, after, y.children, path + "/", out);
    }
}

}  // namespace

TreeDifference compare_trees(const mesh::FbxDocument& before, const mesh::FbxDocument& after) {
    TreeDifference out;
    walk(before, before.roots, after, after.roots, "", out);
    return out;
}

mesh::FbxDocument parse_fbx_file(const std::string& path) {
    std::string bytes;
    const Status read = mesh::read_file_bytes(path, bytes);
    REQUIRE_MESSAGE(read.is_ok(), read.message());
    mesh::FbxDocument doc;
    const Status s = mesh::parse_fbx(std::move(bytes), path, doc);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return doc;
}

}  // namespace dfm::test
