#include "mesh/fbx_values.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include <zlib.h>

namespace dfm::mesh {

static_assert(std::endian::native == std::endian::little,
              "the FBX reader copies little-endian values as they are");

namespace {

template <typename T>
T load(const std::string& b, std::size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}

// Inflates the array's stored bytes. With `out` it must receive exactly
// `expected` bytes; without, the bytes are counted through a small buffer.
Status inflate_array(const FbxDocument& doc, const FbxNode& node, const FbxProperty& p,
                     std::size_t expected, unsigned char* out) {
    const std::size_t stored_at = p.begin + 12;
    const std::size_t stored = p.end - stored_at;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) {
        return doc.error(Errc::out_of_memory, node, "zlib could not start inflating an array");
    }
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(doc.bytes.data() + stored_at));
    z.avail_in = static_cast<uInt>(stored);
    unsigned char scratch[16384];
    std::size_t produced = 0;
    int rc = Z_OK;
    while (rc == Z_OK) {
        unsigned char* to = scratch;
        std::size_t room = sizeof scratch;
        if (out != nullptr) {
            // One byte beyond the expected size tells a stream that is too long.
            if (produced < expected) {
                to = out + produced;
                room = expected - produced;
            } else {
                room = 1;
            }
        }
        z.next_out = to;
        z.avail_out = static_cast<uInt>(std::min<std::size_t>(room, 1u << 30));
        const uInt out_before = z.avail_out;
        const uInt in_before = z.avail_in;
        rc = inflate(&z, Z_NO_FLUSH);
        produced += out_before - z.avail_out;
        if (produced > expected) break;
        // No progress: the stream wants input that is not there.
        if (rc == Z_BUF_ERROR) {
            if (z.avail_out == out_before && z.avail_in == in_before) break;
            rc = Z_OK;
        }
    }
    const std::string message = z.msg != nullptr ? z.msg : "";
    inflateEnd(&z);
    const std::string what = "its array of " + std::to_string(p.count) + " elements (" +
                             std::to_string(expected) + " bytes) ";
    if (produced > expected) {
        return doc.error(Errc::parse_error, node, what + "inflates to more bytes");
    }
    if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_STREAM_ERROR) {
        return doc.error(
            Errc::parse_error, node,
            what + "holds corrupt deflate data" + (message.empty() ? "" : ": " + message));
    }
    if (rc == Z_MEM_ERROR) return doc.error(Errc::out_of_memory, node, "zlib ran out of memory");
    if (rc != Z_STREAM_END) {
        return doc.error(Errc::parse_error, node,
                         what + "is truncated: its deflate stream ends after " +
                             std::to_string(produced) + " bytes");
    }
    if (produced != expected) {
        return doc.error(Errc::parse_error, node,
                         what + "inflates to " + std::to_string(produced) + " bytes");
    }
    return Status::ok();
}

// The raw little-endian bytes of a binary array, inflated where needed.
Status array_bytes(const FbxDocument& doc, const FbxNode& node, const FbxProperty& p,
                   std::string& scratch, const unsigned char*& data) {
    const std::size_t size = std::size_t{p.count} * fbx_array_width(p.type);
    if (p.encoding == 0) {
        data = reinterpret_cast<const unsigned char*>(doc.bytes.data() + p.begin + 12);
        return Status::ok();
    }
    scratch.resize(size);
    if (Status s =
            inflate_array(doc, node, p, size, reinterpret_cast<unsigned char*>(scratch.data()));
        !s) {
        return s;
    }
    data = reinterpret_cast<const unsigned char*>(scratch.data());
    return Status::ok();
}

std::string_view text_of(const FbxDocument& doc, const FbxProperty& p) {
    return std::string_view(doc.bytes).substr(p.begin, p.end - p.begin);
}

bool parse_double(std::string_view t, double& v) {
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && ptr == t.data() + t.size() && !t.empty();
}

bool parse_integer(std::string_view t, std::int64_t& v) {
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && ptr == t.data() + t.size() && !t.empty();
}

// Calls `each(text)` for every value of an ASCII array.
template <typename F>
bool for_each_ascii_value(std::string_view t, F&& each) {
    std::size_t i = 0;
    while (i < t.size()) {
        while (i < t.size() &&
               (t[i] == ',' || t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n')) {
            ++i;
        }
        if (i == t.size()) break;
        std::size_t j = i;
        while (j < t.size() && t[j] != ',' && t[j] != ' ' && t[j] != '\t' && t[j] != '\r' &&
               t[j] != '\n') {
            ++j;
        }
        if (!each(t.substr(i, j - i))) return false;
        i = j;
    }
    return true;
}

// The node's one array property, or null when it holds scalars.
const FbxProperty* array_of(const FbxDocument& doc, const FbxNode& node) {
    if (node.property_count != 1) return nullptr;
    const FbxProperty& p = doc.property(node, 0);
    return (p.type == 'a' || fbx_array_width(p.type) != 0) ? &p : nullptr;
}

template <typename T, typename FromBinary, typename FromText>
Status decode(const FbxDocument& doc, const FbxNode& node, std::vector<T>& out, const char* kind,
              FromBinary from_binary, FromText from_text) {
    out.clear();
    const FbxProperty* array = array_of(doc, node);
    if (array == nullptr) {
        for (std::uint32_t i = 0; i < node.property_count; ++i) {
            T v{};
            if (!from_text(doc, doc.property(node, i), v)) {
                return doc.error(Errc::parse_error, node,
                                 "property " + std::to_string(i) + " is not " + kind);
            }
            out.push_back(v);
        }
        return Status::ok();
    }
    out.reserve(array->count);
    if (array->type == 'a') {
        std::size_t k = 0;
        const bool ok = for_each_ascii_value(text_of(doc, *array), [&](std::string_view t) {
            FbxProperty one;
            one.type = 'n';
            one.begin = static_cast<std::size_t>(t.data() - doc.bytes.data());
            one.end = one.begin + t.size();
            T v{};
            if (!from_text(doc, one, v)) return false;
            out.push_back(v);
            ++k;
            return true;
        });
        if (!ok) {
            return doc.error(Errc::parse_error, node,
                             "array value " + std::to_string(k) + " is not " + kind);
        }
        return Status::ok();
    }
    std::string scratch;
    const unsigned char* data = nullptr;
    if (Status s = array_bytes(doc, node, *array, scratch, data); !s) return s;
    for (std::uint32_t i = 0; i < array->count; ++i) {
        T v{};
        if (!from_binary(array->type, data, i, v)) {
            return doc.error(
                Errc::parse_error, node,
                "its array of type '" + std::string(1, array->type) + "' does not hold " + kind);
        }
        out.push_back(v);
    }
    return Status::ok();
}

}  // namespace

std::optional<double> fbx_number(const FbxDocument& doc, const FbxProperty& p) {
    const std::string& b = doc.bytes;
    switch (p.type) {
        case 'Y': return load<std::int16_t>(b, p.begin);
        case 'C': return b[p.begin] != 0 ? 1.0 : 0.0;
        case 'I': return load<std::int32_t>(b, p.begin);
        case 'F': return load<float>(b, p.begin);
        case 'D': return load<double>(b, p.begin);
        case 'L': return static_cast<double>(load<std::int64_t>(b, p.begin));
        case 'n': {
            double v = 0.0;
            if (parse_double(text_of(doc, p), v)) return v;
            return std::nullopt;
        }
        default: return std::nullopt;
    }
}

std::optional<std::int64_t> fbx_integer(const FbxDocument& doc, const FbxProperty& p) {
    const std::string& b = doc.bytes;
    switch (p.type) {
        case 'Y': return load<std::int16_t>(b, p.begin);
        case 'C': return b[p.begin] != 0 ? 1 : 0;
        case 'I': return load<std::int32_t>(b, p.begin);
        case 'L': return load<std::int64_t>(b, p.begin);
        case 'n': {
            std::int64_t v = 0;
            if (parse_integer(text_of(doc, p), v)) return v;
            return std::nullopt;
        }
        default: return std::nullopt;
    }
}

std::optional<std::string_view> fbx_string(const FbxDocument& doc, const FbxProperty& p) {
    if (p.type == 'S') return std::string_view(doc.bytes).substr(p.begin + 4, p.end - p.begin - 4);
    if (p.type == 's') return text_of(doc, p);
    return std::nullopt;
}

std::string_view fbx_object_name(std::string_view stored) {
    if (const std::size_t sep = stored.find(std::string_view("\0\1", 2));
        sep != std::string_view::npos) {
        return stored.substr(0, sep);
    }
    if (const std::size_t sep = stored.find("::"); sep != std::string_view::npos) {
        return stored.substr(sep + 2);
    }
    return stored;
}

Status fbx_doubles(const FbxDocument& doc, const FbxNode& node, std::vector<double>& out) {
    return decode<double>(
        doc, node, out, "a number",
        [](char type, const unsigned char* d, std::uint32_t i, double& v) {
            switch (type) {
                case 'f': {
                    float f;
                    std::memcpy(&f, d + 4 * std::size_t{i}, 4);
                    v = f;
                    return true;
                }
                case 'd': std::memcpy(&v, d + 8 * std::size_t{i}, 8); return true;
                case 'i': {
                    std::int32_t n;
                    std::memcpy(&n, d + 4 * std::size_t{i}, 4);
                    v = n;
                    return true;
                }
                case 'l': {
                    std::int64_t n;
                    std::memcpy(&n, d + 8 * std::size_t{i}, 8);
                    v = static_cast<double>(n);
                    return true;
                }
                default: v = d[i]; return true;
            }
        },
        [](const FbxDocument& document, const FbxProperty& p, double& v) {
            const std::optional<double> n = fbx_number(document, p);
            if (n) v = *n;
            return n.has_value();
        });
}

Status fbx_integers(const FbxDocument& doc, const FbxNode& node, std::vector<std::int64_t>& out) {
    return decode<std::int64_t>(
        doc, node, out, "an integer",
        [](char type, const unsigned char* d, std::uint32_t i, std::int64_t& v) {
            switch (type) {
                case 'i': {
                    std::int32_t n;
                    std::memcpy(&n, d + 4 * std::size_t{i}, 4);
                    v = n;
                    return true;
                }
                case 'l': std::memcpy(&v, d + 8 * std::size_t{i}, 8); return true;
                case 'b':
                case 'c': v = d[i]; return true;
                default: return false;
            }
        },
        [](const FbxDocument& document, const FbxProperty& p, std::int64_t& v) {
            const std::optional<std::int64_t> n = fbx_integer(document, p);
            if (n) v = *n;
            return n.has_value();
        });
}

std::size_t fbx_value_count(const FbxDocument& doc, const FbxNode& node) {
    const FbxProperty* array = array_of(doc, node);
    return array != nullptr ? array->count : node.property_count;
}

Status fbx_check_array(const FbxDocument& doc, const FbxNode& node, const FbxProperty& p) {
    if (p.encoding != 1 || fbx_array_width(p.type) == 0) return Status::ok();
    return inflate_array(doc, node, p, std::size_t{p.count} * fbx_array_width(p.type), nullptr);
}

}  // namespace dfm::mesh
