#pragma once

#include "deform/quality.hpp"
#include "dualform/dualform.h"
#include "json/json_writer.hpp"

namespace dfm::cli {

// Writes "quality": {...} with the field names of docs/scenarios.md.
void write_quality(json::JsonWriter& json, const dfm_quality& q);
// The same from the engine's figures (for the benchmarks of internals).
void write_quality(json::JsonWriter& json, const deform::QualityReport& q);

}  // namespace dfm::cli
