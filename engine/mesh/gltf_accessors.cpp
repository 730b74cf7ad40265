#include "mesh/gltf_accessors.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace dfm::mesh {

namespace {

std::string accessor_name(int index, const std::string& what) {
    return what + " (accessor " + std::to_string(index) + ")";
}

int component_size(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

double read_component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto v = static_cast<std::int8_t>(*p);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0 : *p;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            std::int16_t v;
            std::memcpy(&v, p, sizeof v);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p, sizeof v);
            return normalized ? v / 65535.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            std::uint32_t v;
            std::memcpy(&v, p, sizeof v);
            return v;
        }
        default: {
            float v;
            std::memcpy(&v, p, sizeof v);
            return v;
        }
    }
}

// The bytes [view offset + offset, + (count - 1) * stride + element) of a
// buffer view, checked; `data` points at the first.
struct Span {
    const unsigned char* data = nullptr;
    std::size_t buffer_offset = 0;
    std::size_t stride = 0;
    int buffer = -1;
};

Status locate(const tinygltf::Model& model, int view_index, std::uint64_t offset,
              std::uint64_t count, std::uint64_t element, std::uint64_t stride_override,
              const std::string& what, Span& out) {
    if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
        return Status(Errc::out_of_range, what + ": buffer view " + std::to_string(view_index) +
                                              " does not exist (the file has " +
                                              std::to_string(model.bufferViews.size()) + ")");
    }
    const tinygltf::BufferView& view = model.bufferViews[view_index];
    const std::string vname = what + ": buffer view " + std::to_string(view_index);
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        return Status(Errc::out_of_range, vname + " names buffer " + std::to_string(view.buffer) +
                                              ", which does not exist (the file has " +
                                              std::to_string(model.buffers.size()) + ")");
    }
    const std::uint64_t size = model.buffers[view.buffer].data.size();
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset) {
        return Status(Errc::out_of_range,
                      vname + " (bytes " + std::to_string(view.byteOffset) + " + " +
                          std::to_string(view.byteLength) + ") runs past the end of buffer " +
                          std::to_string(view.buffer) + " (" + std::to_string(size) + " bytes)");
    }
    const std::uint64_t stride =
        stride_override != 0 ? stride_override : (view.byteStride != 0 ? view.byteStride : element);
    if (stride < element) {
        return Status(Errc::parse_error, vname + ": byteStride " + std::to_string(stride) +
                                             " is smaller than one element (" +
                                             std::to_string(element) + " bytes)");
    }
    if (count > view.byteLength || offset > view.byteLength ||
        (count > 0 && (count - 1) * stride + element > view.byteLength - offset)) {
        return Status(Errc::out_of_range, what + ": " + std::to_string(count) + " elements of " +
                                              std::to_string(element) + " bytes every " +
                                              std::to_string(stride) + " from byte " +
                                              std::to_string(offset) + " run past the end of " +
                                              "buffer view " + std::to_string(view_index) + " (" +
                                              std::to_string(view.byteLength) + " bytes)");
    }
    out.buffer = view.buffer;
    out.buffer_offset = view.byteOffset + offset;
    out.stride = stride;
    out.data = model.buffers[view.buffer].data.data() + out.buffer_offset;
    return Status::ok();
}

int type_components(int type) {
    return tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(type));
}

}  // namespace

Status check_accessor_shape(const tinygltf::Model& model, int index, int type,
                            const std::string& what) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        return Status(Errc::out_of_range, accessor_name(index, what) +
                                              " does not exist (the file has " +
                                              std::to_string(model.accessors.size()) + ")");
    }
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.type != type) {
        return Status(Errc::unsupported, accessor_name(index, what) + " has " +
                                             std::to_string(type_components(a.type)) +
                                             " components per element, " +
                                             std::to_string(type_components(type)) + " expected");
    }
    if (component_size(a.componentType) == 0) {
        return Status(Errc::parse_error, accessor_name(index, what) + ": unknown component type " +
                                             std::to_string(a.componentType));
    }
    return Status::ok();
}

Status read_accessor(const tinygltf::Model& model, int index, int components,
                     const std::string& what, std::vector<double>& out) {
    out.clear();
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        return Status(Errc::out_of_range, accessor_name(index, what) +
                                              " does not exist (the file has " +
                                              std::to_string(model.accessors.size()) + ")");
    }
    const tinygltf::Accessor& a = model.accessors[index];
    const std::string name = accessor_name(index, what);
    const int csize = component_size(a.componentType);
    if (csize == 0) {
        return Status(Errc::parse_error,
                      name + ": unknown component type " + std::to_string(a.componentType));
    }
    if (type_components(a.type) != components) {
        return Status(Errc::unsupported, name + " has " + std::to_string(type_components(a.type)) +
                                             " components per element, " +
                                             std::to_string(components) + " expected");
    }
    const std::uint64_t element = static_cast<std::uint64_t>(csize) * components;
    // Sizes are checked against the bytes behind them before anything is
    // allocated, so a huge declared count costs nothing.
    if (a.bufferView >= 0) {
        Span span;
        if (Status s = locate(model, a.bufferView, a.byteOffset, a.count, element, 0, name, span);
            !s) {
            return s;
        }
        out.resize(a.count * components);
        for (std::size_t e = 0; e < a.count; ++e) {
            const unsigned char* p = span.data + e * span.stride;
            for (int c = 0; c < components; ++c) {
                out[e * components + c] =
                    read_component(p + c * csize, a.componentType, a.normalized);
            }
        }
    } else if (!a.sparse.isSparse) {
        return Status(Errc::parse_error, name + " has neither a buffer view nor sparse values");
    } else if (a.count > (std::uint64_t{1} << 28)) {
        return Status(Errc::out_of_range, name + ": " + std::to_string(a.count) +
                                              " elements of zeros, more than Dualform loads");
    } else {
        out.assign(a.count * components, 0.0);
    }
    if (!a.sparse.isSparse) return Status::ok();
    if (a.sparse.count < 1 || static_cast<std::uint64_t>(a.sparse.count) > a.count) {
        return Status(Errc::parse_error, name + ": sparse count " + std::to_string(a.sparse.count) +
                                             " is not between 1 and the accessor's count " +
                                             std::to_string(a.count));
    }
    const int itype = a.sparse.indices.componentType;
    if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return Status(Errc::parse_error, name + ": sparse indices have component type " +
                                             std::to_string(itype) + ", not an unsigned integer");
    }
    const auto n = static_cast<std::uint64_t>(a.sparse.count);
    Span indices, values;
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0) {
        return Status(Errc::parse_error, name + ": a sparse byteOffset is negative");
    }
    if (Status s =
            locate(model, a.sparse.indices.bufferView,
                   static_cast<std::uint64_t>(a.sparse.indices.byteOffset), n,
                   component_size(itype), component_size(itype), name + " sparse indices", indices);
        !s) {
        return s;
    }
    if (Status s = locate(model, a.sparse.values.bufferView,
                          static_cast<std::uint64_t>(a.sparse.values.byteOffset), n, element,
                          element, name + " sparse values", values);
        !s) {
        return s;
    }
    for (std::uint64_t k = 0; k < n; ++k) {
        const auto target = static_cast<std::uint64_t>(
            read_component(indices.data + k * indices.stride, itype, false));
        if (target >= a.count) {
            return Status(Errc::out_of_range, name + ": sparse index " + std::to_string(k) +
                                                  " names element " + std::to_string(target) +
                                                  " of " + std::to_string(a.count));
        }
        for (int c = 0; c < components; ++c) {
            out[target * components + c] = read_component(
                values.data + k * values.stride + c * csize, a.componentType, a.normalized);
        }
    }
    return Status::ok();
}

namespace {

void mark(std::vector<std::vector<bool>>& claimed, const Span& span, std::uint64_t count,
          std::uint64_t element) {
    std::vector<bool>& bytes = claimed[span.buffer];
    for (std::uint64_t e = 0; e < count; ++e) {
        const std::size_t start = span.buffer_offset + e * span.stride;
        std::fill(bytes.begin() + start, bytes.begin() + start + element, true);
    }
}

void mark_view(const tinygltf::Model& model, std::vector<std::vector<bool>>& claimed, int view) {
    if (view < 0 || static_cast<std::size_t>(view) >= model.bufferViews.size()) return;
    Span span;
    const tinygltf::BufferView& v = model.bufferViews[view];
    if (v.byteLength == 0) return;
    if (!locate(model, view, 0, 1, v.byteLength, v.byteLength, "", span)) return;
    mark(claimed, span, 1, v.byteLength);
}

}  // namespace

std::vector<std::vector<bool>> claimed_bytes(const tinygltf::Model& model,
                                             const std::vector<bool>& rewritten) {
    std::vector<std::vector<bool>> claimed(model.buffers.size());
    for (std::size_t b = 0; b < model.buffers.size(); ++b) {
        claimed[b].assign(model.buffers[b].data.size(), false);
    }
    std::vector<bool> used_view(model.bufferViews.size(), false);
    const auto use = [&](int view) {
        if (view >= 0 && static_cast<std::size_t>(view) < used_view.size()) used_view[view] = true;
    };
    for (std::size_t i = 0; i < model.accessors.size(); ++i) {
        const tinygltf::Accessor& a = model.accessors[i];
        use(a.bufferView);
        if (a.sparse.isSparse) {
            use(a.sparse.indices.bufferView);
            use(a.sparse.values.bufferView);
        }
        const bool skip = i < rewritten.size() && rewritten[i];
        const int csize = component_size(a.componentType);
        const int comps = type_components(a.type);
        if (skip || csize == 0 || comps <= 0) continue;
        const std::uint64_t element = static_cast<std::uint64_t>(csize) * comps;
        Span span;
        if (a.bufferView >= 0 &&
            locate(model, a.bufferView, a.byteOffset, a.count, element, 0, "", span)) {
            mark(claimed, span, a.count, element);
        }
        if (a.sparse.isSparse) {
            mark_view(model, claimed, a.sparse.indices.bufferView);
            mark_view(model, claimed, a.sparse.values.bufferView);
        }
    }
    for (const tinygltf::Image& image : model.images) mark_view(model, claimed, image.bufferView);
    for (std::size_t v = 0; v < used_view.size(); ++v) {
        if (!used_view[v]) mark_view(model, claimed, static_cast<int>(v));
    }
    return claimed;
}

GltfSlot slot_of(const tinygltf::Model& model, int index,
                 const std::vector<std::vector<bool>>& claimed) {
    GltfSlot slot;
    slot.accessor = index;
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) return slot;
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.sparse.isSparse || a.bufferView < 0 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        return slot;
    }
    const std::uint64_t element = 4ull * type_components(a.type);
    Span span;
    if (!locate(model, a.bufferView, a.byteOffset, a.count, element, 0, "", span)) return slot;
    const std::vector<bool>& bytes = claimed[span.buffer];
    for (std::uint64_t e = 0; e < a.count; ++e) {
        const std::size_t start = span.buffer_offset + e * span.stride;
        for (std::uint64_t k = 0; k < element; ++k) {
            if (bytes[start + k]) return slot;
        }
    }
    slot.in_place = true;
    slot.buffer = span.buffer;
    slot.offset = span.buffer_offset;
    slot.stride = span.stride;
    return slot;
}

}  // namespace dfm::mesh
