#include "mesh/fbx_document.hpp"

#include <algorithm>

namespace dfm::mesh {

const FbxNode* FbxDocument::child(std::uint32_t node, std::string_view name) const {
    const std::vector<std::uint32_t>& list = node == no_index ? roots : nodes[node].children;
    for (std::uint32_t c : list) {
        if (nodes[c].name == name) return &nodes[c];
    }
    return nullptr;
}

Where FbxDocument::where(const FbxNode& node) const {
    return binary ? Where::byte(source, node.begin) : Where::line(source, node.line);
}

std::string FbxDocument::path(const FbxNode& node) const {
    std::vector<std::string_view> names;
    for (std::uint32_t at = index_of(node); at != no_index; at = nodes[at].parent) {
        names.push_back(nodes[at].name);
    }
    // A deep path shows its first and last three names.
    const bool elided = names.size() > 8;
    if (elided) names.erase(names.begin() + 3, names.end() - 3);
    std::string out;
    for (auto it = names.rbegin(); it != names.rend(); ++it) {
        if (!out.empty()) out += '/';
        if (elided && it == names.rbegin() + 3) out += ".../";
        for (char c : *it) out += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return out;
}

Status FbxDocument::error(Errc code, const FbxNode& node, std::string_view what) const {
    return where(node).error(code, "node " + path(node) + ": " + std::string(what));
}

std::size_t fbx_array_width(char type) {
    switch (type) {
        case 'f':
        case 'i': return 4;
        case 'd':
        case 'l': return 8;
        case 'b':
        case 'c': return 1;
        default: return 0;
    }
}

bool looks_like_fbx(std::string_view head) {
    if (head.starts_with(fbx_binary_magic.substr(0, 18))) return true;
    // ASCII FBX opens with the comment "; FBX 7.4.0 project file", perhaps
    // after a byte order mark.
    if (head.starts_with("\xEF\xBB\xBF")) head.remove_prefix(3);
    return head.starts_with("; FBX ");
}

}  // namespace dfm::mesh
