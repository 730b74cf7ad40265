#include "dualform/edit_report.hpp"

namespace dfm::cli {

void write_quality(json::JsonWriter& json, const deform::QualityReport& q) {
    json.key("quality").begin_object();
    json.key("max_handle_error").value(q.max_handle_error);
    json.key("mean_abs_log_edge").value(q.mean_abs_log_edge);
    json.key("max_abs_log_edge").value(q.max_abs_log_edge);
    json.key("mean_normal_change_deg").value(q.mean_normal_change_deg);
    json.key("max_fixed_move").value(q.max_fixed_move);
    json.key("dual_magnitude_error").value(q.dual_magnitude_error);
    json.key("flipped_faces").value(std::uint64_t{q.flipped_faces});
    json.end_object();
}

}  // namespace dfm::cli
