#pragma once

// The one place the C API translates between the host's vertex numbering
// (split copies and all: a glTF file's, or a host's seam-split buffers) and
// the surface vertices the engine works on (mesh/seam_weld.hpp). On a mesh
// without split copies every call here is the identity, and out-of-range
// indices pass through to the engine's own checks and messages.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "dualform/dualform.h"
#include "mesh/seam_weld.hpp"
#include "objects.hpp"

namespace dfm::sdk {

class HostNumbering {
public:
    HostNumbering(const MeshState& state, std::size_t surface_vertices);

    bool identity() const { return weld_ == nullptr; }
    std::size_t host_count() const;

    // The surface vertex a host index means; out of range is an error
    // naming `what` ("first vertex", "handle group 0 entry 2").
    Status to_surface(std::uint32_t host, const std::string& what, std::uint32_t& out) const;
    Status to_surface(std::span<const std::uint32_t> host, const std::string& what,
                      std::vector<std::uint32_t>& out) const;

    // What the API returns for a surface vertex: its lowest host index.
    std::uint32_t to_host(std::uint32_t surface) const;
    void to_host(std::span<std::uint32_t> vertices) const;
    std::uint32_t to_host_face(std::uint32_t surface_face) const;

    // Surface values to the host's whole array, each copy its vertex's.
    void write_all(const dfm_vec3_output& out, std::span<const glm::dvec3> surface) const;
    // One surface vertex's value to all its copies.
    void write_one(const dfm_vec3_output& out, std::uint32_t surface, const glm::dvec3& v) const;
    template <class Fn>
    void for_copies(std::uint32_t surface, Fn&& fn) const {
        if (weld_ == nullptr) {
            fn(surface);
            return;
        }
        for (std::uint32_t h : weld_->copies_of(surface)) fn(h);
    }
    // The host's positions (host_count of them) to the surface's: each
    // surface vertex takes its lowest copy's.
    std::vector<glm::dvec3> surface_positions(std::span<const glm::dvec3> host) const;

    const mesh::SeamWeld* weld() const { return weld_; }

private:
    const mesh::SeamWeld* weld_;  // null: the identity
    std::size_t surface_vertices_;
};

}  // namespace dfm::sdk
