#pragma once

#include "dualform/dualform.h"
#include "json/json_writer.hpp"

namespace dfm::cli {

// Writes "quality": {...} with the field names of docs/scenarios.md.
void write_quality(json::JsonWriter& json, const dfm_quality& q);

}  // namespace dfm::cli
