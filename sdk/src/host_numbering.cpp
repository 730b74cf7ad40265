#include "host_numbering.hpp"

#include "vec3_arrays.hpp"

namespace dfm::sdk {

HostNumbering::HostNumbering(const MeshState& state, std::size_t surface_vertices)
    : weld_(state.host.weld && state.host.weld->splits() ? state.host.weld.get() : nullptr),
      surface_vertices_(surface_vertices) {}

std::size_t HostNumbering::host_count() const {
    return weld_ != nullptr ? weld_->host_vertex_count() : surface_vertices_;
}

Status HostNumbering::to_surface(std::uint32_t host, const std::string& what,
                                 std::uint32_t& out) const {
    if (weld_ == nullptr) {
        out = host;
        return Status::ok();
    }
    if (host >= weld_->host_vertex_count()) {
        return Status(Errc::out_of_range, what + ": vertex " + std::to_string(host) +
                                              " is out of range (the mesh has " +
                                              std::to_string(weld_->host_vertex_count()) +
                                              " vertices)");
    }
    out = weld_->surface_of[host];
    return Status::ok();
}

Status HostNumbering::to_surface(std::span<const std::uint32_t> host, const std::string& what,
                                 std::vector<std::uint32_t>& out) const {
    out.resize(host.size());
    for (std::size_t i = 0; i < host.size(); ++i) {
        if (Status s = to_surface(host[i], what + " entry " + std::to_string(i), out[i]); !s) {
            return s;
        }
    }
    return Status::ok();
}

std::uint32_t HostNumbering::to_host(std::uint32_t surface) const {
    return weld_ != nullptr ? weld_->lowest_copy(surface) : surface;
}

void HostNumbering::to_host(std::span<std::uint32_t> vertices) const {
    if (weld_ == nullptr) return;
    for (std::uint32_t& v : vertices) v = weld_->lowest_copy(v);
}

std::uint32_t HostNumbering::to_host_face(std::uint32_t surface_face) const {
    return weld_ != nullptr ? weld_->host_face_of[surface_face] : surface_face;
}

void HostNumbering::write_all(const dfm_vec3_output& out,
                              std::span<const glm::dvec3> surface) const {
    if (weld_ == nullptr) {
        write_vec3_range(out, 0, surface);
        return;
    }
    for (std::size_t h = 0; h < weld_->host_vertex_count(); ++h) {
        write_vec3(out, h, surface[weld_->surface_of[h]]);
    }
}

void HostNumbering::write_one(const dfm_vec3_output& out, std::uint32_t surface,
                              const glm::dvec3& v) const {
    for_copies(surface, [&](std::uint32_t h) { write_vec3(out, h, v); });
}

std::vector<glm::dvec3> HostNumbering::surface_positions(std::span<const glm::dvec3> host) const {
    if (weld_ == nullptr) return {host.begin(), host.end()};
    std::vector<glm::dvec3> out(weld_->surface_vertex_count());
    for (std::uint32_t s = 0; s < out.size(); ++s) out[s] = host[weld_->lowest_copy(s)];
    return out;
}

}  // namespace dfm::sdk
