#include "sample_report.hpp"

#include <doctest/doctest.h>

namespace dfm::test {

double number_at(const json::JsonValue& object, const char* key, const char* field) {
    const json::JsonMember* member = object.find(key);
    REQUIRE_MESSAGE(member != nullptr, key);
    if (field == nullptr) return member->value.number;
    const json::JsonMember* inner = member->value.find(field);
    REQUIRE_MESSAGE(inner != nullptr, key << "." << field);
    return inner->value.number;
}

}  // namespace dfm::test
