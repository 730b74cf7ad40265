#include "dualform/edit_report.hpp"

namespace dfm::cli {

void write_quality(json::JsonWriter& json, const dfm_quality& q) {
    json.key("quality").begin_object();
    json.field("max_handle_error", q.max_handle_error);
    json.field("mean_abs_log_edge", q.mean_abs_log_edge);
    json.field("max_abs_log_edge", q.max_abs_log_edge);
    json.field("mean_normal_change_deg", q.mean_normal_change_deg);
    json.field("max_fixed_move", q.max_fixed_move);
    json.field("dual_magnitude_error", q.dual_magnitude_error);
    json.field("flipped_faces", q.flipped_faces);
    json.field("creased_edges", q.creased_edges);
    json.end_object();
}

}  // namespace dfm::cli
