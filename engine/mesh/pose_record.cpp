#include <nlohmann/json.hpp>

#include "mesh/skin_pose.hpp"

namespace dfm::mesh {

std::string pose_record(const Skin& skin, const SkinPose& pose) {
    nlohmann::json record = nlohmann::json::object();
    if (pose.animation >= 0 && static_cast<std::size_t>(pose.animation) < skin.animations.size()) {
        record["animation"] = skin.animations[pose.animation].name;
        record["animation_index"] = pose.animation;
        record["time"] = pose.time;
    } else {
        nlohmann::json matrices = nlohmann::json::array();
        for (const glm::dmat4& m : pose.joint_world) {
            nlohmann::json column_major = nlohmann::json::array();
            for (int c = 0; c < 4; ++c) {
                for (int r = 0; r < 4; ++r) column_major.push_back(m[c][r]);
            }
            matrices.push_back(std::move(column_major));
        }
        record["joint_matrices"] = std::move(matrices);
    }
    if (!skin.morph_targets.empty()) record["morph_weights"] = pose.morph_weights;
    // Names come from the file, which need not be UTF-8.
    return nlohmann::json{{"dualform_pose", record}}.dump(-1, ' ', false,
                                                          nlohmann::json::error_handler_t::replace);
}

}  // namespace dfm::mesh
