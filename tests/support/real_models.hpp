#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "deform/mesh_model.hpp"

namespace dfm::test {

// The model "model:NAME" from the fetched models folder, ready to edit;
// fails the test with the loader's message when it cannot be read.
deform::MeshModel load_real_model(const std::string& name);

// The vertices within `radius` diagonals of `center`, reached along edges.
std::vector<std::uint32_t> ball_around(const deform::MeshModel& model, std::uint32_t center,
                                       double radius);

}  // namespace dfm::test
