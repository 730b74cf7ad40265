#pragma once

#include "deform/quality.hpp"
#include "dualform/json_writer.hpp"

namespace dfm::cli {

// Writes "quality": {...} with the field names of docs/scenarios.md.
void write_quality(JsonWriter& json, const deform::QualityReport& q);

}  // namespace dfm::cli
