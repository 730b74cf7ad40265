#include <algorithm>
#include <string>
#include <vector>

#include "mesh/readers.hpp"
#include "mesh/text_cursor.hpp"

// OFF as Geomview defines it, one record a line: an optional "ST", "C", "N"
// prefix on the keyword announces extra per-vertex values, which are skipped
// like face colours are. "4OFF", "nOFF" and binary OFF are refused.
namespace dfm::mesh {

namespace {

// A record takes at least a character and a line end. The bound is loose on
// purpose: it only stops absurd counts, and leaves real mistakes (a short
// vertex line, a two-vertex face) to the specific messages below.
constexpr std::uint64_t min_record_bytes = 2;
// What reserve() may assume a well-formed vertex line takes ("0 0 0\n"), so
// that what is reserved stays proportional to the file.
constexpr std::uint64_t typical_vertex_bytes = 6;

Status check_keyword(std::string_view keyword, const Where& where) {
    std::string_view k = keyword;
    if (k.starts_with("ST")) k.remove_prefix(2);
    if (k.starts_with('C')) k.remove_prefix(1);
    if (k.starts_with('N')) k.remove_prefix(1);
    if (k.starts_with('4') || k.starts_with('n')) {
        return where.error(Errc::unsupported, "header " + quote_token(keyword) +
                                                  ": 4D and n-dimensional OFF are not supported");
    }
    if (k != "OFF") {
        return where.parse_error("expected an OFF header (OFF, COFF, NOFF, STOFF...), found " +
                                 quote_token(keyword));
    }
    return Status::ok();
}

Status read_count(Tokens& tokens, const char* what, const Where& where, std::uint64_t& count) {
    std::string_view token;
    if (!tokens.next(token)) {
        return where.parse_error(std::string("missing the ") + what + " count");
    }
    std::int64_t value = 0;
    if (const NumberError e = parse_integer(token, value); e != NumberError::none) {
        return where.parse_error(std::string(what) + " count " + quote_token(token) + " is " +
                                 std::string(describe_number_error(e)));
    }
    if (value < 0) {
        return where.parse_error(std::string(what) + " count " + std::to_string(value) +
                                 " is negative");
    }
    count = static_cast<std::uint64_t>(value);
    return Status::ok();
}

}  // namespace

Status read_off(std::string_view text, std::string_view source, MeshBuilder& builder) {
    TextCursor cursor(text, '#');
    std::string_view line;
    if (!cursor.next_line(line)) {
        return Where::line(source, cursor.line()).parse_error("no OFF header: the file is empty");
    }
    Tokens header(line);
    std::string_view keyword;
    header.next(keyword);
    if (Status s = check_keyword(keyword, Where::line(source, cursor.line())); !s) return s;
    std::string_view extra;
    if (Tokens probe = header; probe.next(extra) && extra == "BINARY") {
        return Where::line(source, cursor.line())
            .error(Errc::unsupported, "binary OFF is not supported");
    }

    // The counts may follow the keyword on its line or stand on the next.
    Tokens counts = header;
    if (counts.count_remaining() == 0) {
        if (!cursor.next_line(line)) {
            return Where::line(source, cursor.line())
                .parse_error("truncated: the vertex and face counts are missing");
        }
        counts = Tokens(line);
    }
    const Where counts_at = Where::line(source, cursor.line());
    std::uint64_t nv = 0;
    std::uint64_t nf = 0;
    if (Status s = read_count(counts, "vertex", counts_at, nv); !s) return s;
    if (Status s = read_count(counts, "face", counts_at, nf); !s) return s;

    const std::uint64_t left = cursor.remaining_bytes();
    if (nv > left / min_record_bytes || nf > left / min_record_bytes ||
        (nv + nf) * min_record_bytes > left + 1) {
        return counts_at.parse_error("the header declares " + std::to_string(nv) +
                                     " vertices and " + std::to_string(nf) +
                                     " faces, more than the remaining " + std::to_string(left) +
                                     " bytes can hold (truncated file or wrong counts)");
    }
    builder.reserve(std::min(nv, left / typical_vertex_bytes), std::min(nf, left / 8));

    for (std::uint64_t i = 0; i < nv; ++i) {
        if (!cursor.next_line(line)) {
            return Where::line(source, cursor.line())
                .parse_error("truncated: expected " + std::to_string(nv) +
                             " vertices, the file ends after " + std::to_string(i));
        }
        const Where at = Where::line(source, cursor.line());
        Tokens tokens(line);
        glm::dvec3 p;
        for (int c = 0; c < 3; ++c) {
            std::string_view token;
            if (!tokens.next(token)) {
                return at.parse_error("vertex " + std::to_string(i) +
                                      ": expected 3 coordinates, found " + std::to_string(c));
            }
            if (const NumberError e = parse_double(token, p[c]); e != NumberError::none) {
                return at.parse_error("vertex " + std::to_string(i) + ": coordinate " +
                                      quote_token(token) + " is " +
                                      std::string(describe_number_error(e)));
            }
        }
        if (Status s = builder.add_vertex(p, at); !s) return s;
    }

    std::vector<std::int64_t> corners;
    for (std::uint64_t f = 0; f < nf; ++f) {
        if (!cursor.next_line(line)) {
            return Where::line(source, cursor.line())
                .parse_error("truncated: expected " + std::to_string(nf) +
                             " faces, the file ends after " + std::to_string(f));
        }
        const Where at = Where::line(source, cursor.line());
        const std::string face = "face " + std::to_string(f) + ": ";
        Tokens tokens(line);
        std::string_view token;
        tokens.next(token);
        std::int64_t k = 0;
        if (const NumberError e = parse_integer(token, k); e != NumberError::none) {
            return at.parse_error(face + "vertex count " + quote_token(token) + " is " +
                                  std::string(describe_number_error(e)));
        }
        if (k < 0)
            return at.parse_error(face + "vertex count " + std::to_string(k) + " is negative");
        if (Status s = builder.check_polygon_size(static_cast<std::uint64_t>(k), at); !s) return s;
        const std::size_t available = tokens.count_remaining();
        if (available < static_cast<std::uint64_t>(k)) {
            return at.parse_error(face + "declares " + std::to_string(k) + " vertices but lists " +
                                  std::to_string(available));
        }
        corners.resize(static_cast<std::size_t>(k));
        for (std::int64_t c = 0; c < k; ++c) {
            tokens.next(token);
            if (const NumberError e = parse_integer(token, corners[c]); e != NumberError::none) {
                return at.parse_error(face + "vertex index " + quote_token(token) + " is " +
                                      std::string(describe_number_error(e)));
            }
        }
        if (Status s = builder.add_polygon(corners, at); !s) return s;
    }
    return Status::ok();
}

}  // namespace dfm::mesh
