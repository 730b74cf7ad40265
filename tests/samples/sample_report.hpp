#pragma once

#include "json/json_reader.hpp"

namespace dfm::test {

// A sample's JSON report: the number at `key` of `object`, or at
// `key`.`field`; a missing one fails the test, naming it.
double number_at(const json::JsonValue& object, const char* key, const char* field = nullptr);

}  // namespace dfm::test
