#pragma once

#include <string>
#include <vector>

#include "mesh/fbx_document.hpp"

// Compares two FBX node trees node by node, for the tests of the FBX writer:
// what an edit changed, what it added, and that nothing else moved.
namespace dfm::test {

struct TreeDifference {
    std::vector<std::string> changed;  // paths of nodes whose own name or properties differ
    std::vector<std::string> added;    // paths of nodes `after` has beyond `before`'s children
    std::vector<std::string> missing;  // paths of nodes of `before` that `after` lacks
};

// Walks both trees in parallel: a node's own bytes are its name and its
// properties exactly as stored (compressed arrays as their stored bytes);
// children are paired in order, and those `after` has beyond `before`'s
// count are "added".
TreeDifference compare_trees(const mesh::FbxDocument& before, const mesh::FbxDocument& after);

// A parsed file; fails the test when it does not parse.
mesh::FbxDocument parse_fbx_file(const std::string& path);

}  // namespace dfm::test
