#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "deform/mesh_model.hpp"

namespace dfm::deform {

// The quality figures of an edit (docs/scenarios.md, "The report"),
// computed from the rest and deformed positions alone, so any engine's
// output can be scored the same way. Lengths are fractions of the rest
// diagonal.
struct QualityReport {
    double max_handle_error = 0.0;
    double mean_abs_log_edge = 0.0;  // over edges with a ROI endpoint
    double max_abs_log_edge = 0.0;
    double mean_normal_change_deg = 0.0;  // over faces with a ROI vertex
    double max_fixed_move = 0.0;          // over vertices outside the ROI; must be 0
    double dual_magnitude_error = 0.0;    // mean | |l_f| - |h_f| | / mean |h_f| over ROI faces
    std::size_t flipped_faces = 0;        // ROI faces whose normal turned more than 90°
    // Edges between two ROI vertices whose dihedral angle turned by more
    // than 90° from rest: the creases of a fold, whatever the rigid motion.
    std::size_t creased_edges = 0;
};

QualityReport measure_quality(const MeshModel& model, std::span<const glm::dvec3> deformed,
                              std::span<const std::uint8_t> in_roi,
                              std::span<const std::uint32_t> handle_vertices,
                              std::span<const glm::dvec3> targets);

}  // namespace dfm::deform
