#include "pick/embree_scene.hpp"

#include <cmath>
#include <limits>
#include <new>
#include <string>

#include <embree3/rtcore.h>

namespace dfm::pick {

namespace {

bool finite(const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

Status check_positions(std::span<const glm::dvec3> positions) {
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (!finite(positions[v])) {
            return Status(Errc::invalid_argument,
                          "pick scene: vertex " + std::to_string(v) + " has a non-finite position");
        }
    }
    return Status::ok();
}

void copy_to_floats(std::span<const glm::dvec3> positions, float* out) {
    for (const glm::dvec3& p : positions) {
        *out++ = static_cast<float>(p.x);
        *out++ = static_cast<float>(p.y);
        *out++ = static_cast<float>(p.z);
    }
}

}  // namespace

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;  // kept for refits
    std::vector<glm::dvec3> positions;
    std::vector<mesh::Triangle> triangles;
    // What Embree's error callback said since the last check.
    Errc error_code = Errc::ok;
    std::string error;

    ~Impl() {
        if (geometry) rtcReleaseGeometry(geometry);
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    static void on_error(void* user, RTCError code, const char* message) {
        auto* self = static_cast<Impl*>(user);
        if (self->error_code != Errc::ok) return;  // the first error explains the rest
        self->error_code = code == RTC_ERROR_OUT_OF_MEMORY     ? Errc::out_of_memory
                           : code == RTC_ERROR_UNSUPPORTED_CPU ? Errc::unsupported
                                                               : Errc::invalid_argument;
        self->error = message ? message : "unknown error";
        self->error += " (Embree error code ";
        self->error += std::to_string(static_cast<int>(code));
        self->error += ')';
    }

    // The callback's first error since the last check, naming the step.
    Status take_error(const char* step) {
        if (error_code == Errc::ok) return Status::ok();
        std::string message = "pick scene: Embree failed to ";
        message += step;
        message += ": ";
        message += error;
        Status s(error_code, std::move(message));
        error_code = Errc::ok;
        error.clear();
        return s;
    }
};

EmbreeScene::EmbreeScene() = default;
EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

Status EmbreeScene::create(std::span<const glm::dvec3> positions,
                           std::span<const mesh::Triangle> triangles, EmbreeScene& out,
                           unsigned thread_count) {
    out.impl_.reset();
    if (Status s = check_positions(positions); !s) return s;
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        for (std::uint32_t v : triangles[f]) {
            if (v >= positions.size()) {
                return Status(Errc::out_of_range,
                              "pick scene: face " + std::to_string(f) + " names vertex " +
                                  std::to_string(v) + " (the mesh has " +
                                  std::to_string(positions.size()) + " vertices)");
            }
        }
    }
    try {
        auto impl = std::make_unique<Impl>();
        impl->positions.assign(positions.begin(), positions.end());
        impl->triangles.assign(triangles.begin(), triangles.end());
        const std::string config =
            thread_count == 0 ? std::string() : "threads=" + std::to_string(thread_count);
        impl->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
        if (!impl->device) {
            return Status(Errc::unsupported,
                          "pick scene: Embree cannot create a device (error code " +
                              std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
        }
        rtcSetDeviceErrorFunction(impl->device, &Impl::on_error, impl.get());
        impl->scene = rtcNewScene(impl->device);
        // Robust traversal: a pick aimed at a shared edge must not slip
        // through the crack between two float triangles. Embree only refits
        // in its two-level (dynamic) builder, which it picks for a dynamic
        // scene of low build quality; the mesh's own BVH is still built with
        // SAH once, and the refit build quality below then keeps it.
        if (impl->scene) {
            rtcSetSceneFlags(impl->scene, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST);
            rtcSetSceneBuildQuality(impl->scene, RTC_BUILD_QUALITY_LOW);
        }
        impl->geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (Status s = impl->take_error("create the scene"); !s) return s;
        rtcSetGeometryBuildQuality(impl->geometry, RTC_BUILD_QUALITY_REFIT);
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(impl->geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), positions.size()));
        auto* indices = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(impl->geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), triangles.size()));
        if (Status s = impl->take_error("allocate the buffers"); !s) return s;
        if (!vertices || !indices) {
            return Status(Errc::out_of_memory, "pick scene: Embree returned no buffer");
        }
        copy_to_floats(positions, vertices);
        for (const mesh::Triangle& t : triangles) {
            *indices++ = t[0];
            *indices++ = t[1];
            *indices++ = t[2];
        }
        rtcCommitGeometry(impl->geometry);
        rtcAttachGeometry(impl->scene, impl->geometry);
        rtcCommitScene(impl->scene);
        if (Status s = impl->take_error("build the scene"); !s) return s;
        out.impl_ = std::move(impl);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "pick scene: out of memory for " +
                                               std::to_string(triangles.size()) + " faces");
    }
}

Status EmbreeScene::refit(std::span<const glm::dvec3> positions) {
    if (!impl_) return Status(Errc::invalid_argument, "pick scene: refit on an empty scene");
    if (positions.size() != impl_->positions.size()) {
        return Status(Errc::invalid_argument,
                      "pick scene: refit with " + std::to_string(positions.size()) +
                          " positions, but the scene has " +
                          std::to_string(impl_->positions.size()) + " vertices");
    }
    if (Status s = check_positions(positions); !s) return s;
    auto* vertices =
        static_cast<float*>(rtcGetGeometryBufferData(impl_->geometry, RTC_BUFFER_TYPE_VERTEX, 0));
    if (Status s = impl_->take_error("map the vertex buffer"); !s) return s;
    copy_to_floats(positions, vertices);
    impl_->positions.assign(positions.begin(), positions.end());
    rtcUpdateGeometryBuffer(impl_->geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(impl_->geometry);
    rtcCommitScene(impl_->scene);
    return impl_->take_error("refit the scene");
}

std::span<const glm::dvec3> EmbreeScene::positions() const {
    return impl_ ? std::span<const glm::dvec3>(impl_->positions) : std::span<const glm::dvec3>();
}

std::span<const mesh::Triangle> EmbreeScene::triangles() const {
    return impl_ ? std::span<const mesh::Triangle>(impl_->triangles)
                 : std::span<const mesh::Triangle>();
}

bool EmbreeScene::intersect(const Ray& ray, SceneHit& out) const {
    if (!impl_) return false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(ray.origin.x);
    rh.ray.org_y = static_cast<float>(ray.origin.y);
    rh.ray.org_z = static_cast<float>(ray.origin.z);
    rh.ray.dir_x = static_cast<float>(ray.direction.x);
    rh.ray.dir_y = static_cast<float>(ray.direction.y);
    rh.ray.dir_z = static_cast<float>(ray.direction.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    out.face = rh.hit.primID;
    out.distance = rh.ray.tfar;
    out.u = rh.hit.u;
    out.v = rh.hit.v;
    return true;
}

}  // namespace dfm::pick
