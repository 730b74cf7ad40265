#pragma once

#include "deform/quality.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

// Writes "quality": {...} with the field names of docs/scenarios.md.
void write_quality(json::JsonWriter& json, const deform::QualityReport& q);

}  // namespace dfm::cli
