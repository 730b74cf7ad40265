#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "deform/deform_session.hpp"
#include "deform/linear_solver.hpp"
#include "deform/normal_system.hpp"
#include "deform/quality.hpp"
#include "deform/rigidity_rows.hpp"
#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "support/real_models.hpp"

using namespace dfm;

namespace {

std::vector<std::uint32_t> all_vertices(const deform::MeshModel& model) {
    std::vector<std::uint32_t> v(model.mesh.vertex_count());
    std::iota(v.begin(), v.end(), 0u);
    return v;
}

}  // namespace

TEST_CASE("cow: A V gives the dual Laplacian coordinates of the rest mesh") {
    const deform::MeshModel model = test::load_real_model("cow");
    std::vector<glm::dvec3> c(model.mesh.face_count());
    dual::compute_centroids(model.mesh, model.mesh.positions, c);
    double worst = 0.0;
    double largest = 0.0;
    for (std::uint32_t f = 0; f < model.mesh.face_count(); ++f) {
        REQUIRE(model.dual.has_row[f]);
        const dual::DualRow row = dual::dual_row(model.mesh, model.dual, f);
        glm::dvec3 av(0.0);
        for (std::uint32_t k = 0; k < row.size; ++k) {
            av += row.coefficients[k] * model.mesh.positions[row.vertices[k]];
        }
        const glm::dvec3 l = -model.dual.heights[f] * dual::ring_normal(model.dual, c, f);
        worst = std::max(worst, glm::length(av - l));
        largest = std::max(largest, glm::length(l));
    }
    CHECK(worst <= 1e-12 * largest);
}

TEST_CASE("cow: the dual Laplacian and one fixed vertex rebuild the mesh") {
    const deform::MeshModel model = test::load_real_model("cow");
    deform::UnknownMap unknowns;
    unknowns.unknown_of_vertex.assign(model.mesh.vertex_count(), mesh::no_index);
    for (std::uint32_t v = 1; v < model.mesh.vertex_count(); ++v) {
        unknowns.unknown_of_vertex[v] = static_cast<std::uint32_t>(unknowns.count());
        unknowns.vertex_of_unknown.push_back(v);
    }
    const deform::SystemRows rows = deform::collect_rows(model, unknowns);
    double epsilon = 0.0;
    solver::CsrMatrix n =
        deform::assemble_normal_matrix(rows, unknowns.count(), {}, 1.0, 0.0, epsilon);
    CHECK(epsilon == 0.0);
    std::vector<double> rhs(3 * unknowns.count(), 0.0);
    for (std::size_t r = 0; r < rows.size(); ++r) {
        // b = l_rest - A_fixed p_fixed, with l_rest = -h n = A V_rest: the
        // unknowns' part of A V_rest.
        glm::dvec3 b(0.0);
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            const deform::RowEntry& e = rows.entries[p];
            if (e.unknown != mesh::no_index) b += e.coefficient * model.mesh.positions[e.vertex];
        }
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            const deform::RowEntry& e = rows.entries[p];
            if (e.unknown != mesh::no_index) {
                for (int c = 0; c < 3; ++c) rhs[3 * e.unknown + c] += e.coefficient * b[c];
            }
        }
    }
    deform::LinearSolver solver;
    REQUIRE(solver.setup(std::move(n), solver::PreconditionerKind::cholesky).is_ok());
    std::vector<double> x(rhs.size(), 0.0);  // start far away: everything at the origin
    std::size_t iterations = 0;
    REQUIRE(solver
                .solve(rhs, x, 1e-12 * model.diagonal, deform::LinearSolver::Accuracy::verified,
                       iterations)
                .is_ok());
    double worst = 0.0;
    for (std::size_t i = 0; i < unknowns.count(); ++i) {
        const glm::dvec3 p(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
        worst =
            std::max(worst, glm::length(p - model.mesh.positions[unknowns.vertex_of_unknown[i]]));
    }
    CHECK(worst < 1e-8 * model.diagonal);
}

namespace {

// The fitted method's rows of A after the dual rows, written out here from
// their definition (docs/method.md): for each dual row's face f and each
// k, the dual edge between the vertices opposite f's k-th shared edge,
// w/3 (v_c − v_d), then f's k-th edge, w 0.95 l̄/l (v_a − v_b); only rows
// that touch an unknown.
void append_rigidity_rows(const deform::MeshModel& model, const deform::UnknownMap& unknowns,
                          double weight, deform::SystemRows& rows) {
    const mesh::Mesh& mesh = model.mesh;
    double mean_edge = 0.0;
    for (const auto& e : model.topology.edges)
        mean_edge += glm::length(mesh.positions[e[0]] - mesh.positions[e[1]]);
    mean_edge /= static_cast<double>(model.topology.edges.size());
    auto opposite = [](const mesh::Triangle& t, const mesh::Triangle& other) {
        for (std::uint32_t v : t)
            if (v != other[0] && v != other[1] && v != other[2]) return v;
        return mesh::no_index;
    };
    auto add = [&](std::uint32_t c, std::uint32_t d, double scale, std::uint32_t f) {
        const std::uint32_t uc = unknowns.unknown_of_vertex[c];
        const std::uint32_t ud = unknowns.unknown_of_vertex[d];
        if (uc == mesh::no_index && ud == mesh::no_index) return;
        rows.faces.push_back(f);
        rows.entries.push_back({c, uc, weight * scale});
        rows.entries.push_back({d, ud, -weight * scale});
        rows.entry_offsets.push_back(static_cast<std::uint32_t>(rows.entries.size()));
    };
    const std::size_t dual_rows = rows.size();
    for (std::size_t r = 0; r < dual_rows; ++r) {
        const std::uint32_t f = rows.faces[r];
        const mesh::Triangle& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const mesh::Triangle& n = mesh.triangles[model.dual.neighbors[f][k]];
            const std::uint32_t c = opposite(t, n);
            const std::uint32_t d = opposite(n, t);
            if (c != mesh::no_index && d != mesh::no_index) add(c, d, 1.0 / 3.0, f);
            const std::uint32_t a = t[k];
            const std::uint32_t b = t[(k + 1) % 3];
            const double length = glm::length(mesh.positions[a] - mesh.positions[b]);
            if (length > 0.0) add(a, b, 0.95 * mean_edge / length, f);
        }
    }
}

}  // namespace

TEST_CASE("cow: the normal matrix is AᵀA + w²H + εI, each entry summed in A's row order") {
    // The fitted method's rows (dual and rigidity rows) of the front leg's
    // ball, the first vertices as soft handles: every entry must be the
    // bits of the sum taken row by row of A, the diagonal starting from its
    // handle and ε terms, and the pattern exactly the nonzero pairs; both
    // from the rows listed (assemble_normal_matrix) and from the stencils
    // alone (RotationFrames::assemble_normal_matrix); normal_pattern gives
    // the same pattern from the dual rows alone.
    const deform::MeshModel model = test::load_real_model("cow");
    const std::vector<std::uint32_t> roi = test::ball_around(model, 771, 0.2);
    deform::UnknownMap unknowns;
    unknowns.unknown_of_vertex.assign(model.mesh.vertex_count(), mesh::no_index);
    for (std::uint32_t v : roi) {
        unknowns.unknown_of_vertex[v] = static_cast<std::uint32_t>(unknowns.count());
        unknowns.vertex_of_unknown.push_back(v);
    }
    deform::SystemRows rows = deform::collect_rows(model, unknowns);
    const std::size_t dual_rows = rows.size();
    deform::RotationFrames frames;
    frames.build(model, unknowns, rows, deform::coarse_clusters(model, rows));
    // The pattern the factor's analysis starts from, before any value.
    const solver::CsrMatrix pattern = deform::normal_pattern(rows, unknowns.count());
    append_rigidity_rows(model, unknowns, deform::balanced_rigidity_weight(unknowns.count()), rows);
    REQUIRE(rows.size() > dual_rows);
    CHECK(frames.rigidity_rows() == rows.size() - dual_rows);
    const std::vector<std::uint32_t> soft = {0, 1, 2, 2};
    const double weight = 3.0;
    double listed_epsilon = 0.0;
    const solver::CsrMatrix listed =
        deform::assemble_normal_matrix(rows, unknowns.count(), soft, weight, 1e-6, listed_epsilon);
    double epsilon = 0.0;
    const solver::CsrMatrix from_stencils =
        frames.assemble_normal_matrix(unknowns.count(), soft, weight, 1e-6, epsilon);
    CHECK(epsilon > 0.0);
    CHECK(std::memcmp(&epsilon, &listed_epsilon, sizeof epsilon) == 0);

    std::map<std::pair<std::uint32_t, std::uint32_t>, double> expected;
    std::vector<double> handle(unknowns.count(), 0.0);
    for (std::uint32_t u : soft) handle[u] += weight * weight;
    for (std::uint32_t i = 0; i < unknowns.count(); ++i) expected[{i, i}] = handle[i] + epsilon;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            for (std::uint32_t q = rows.entry_offsets[r]; q < rows.entry_offsets[r + 1]; ++q) {
                const deform::RowEntry& a = rows.entries[p];
                const deform::RowEntry& b = rows.entries[q];
                if (a.unknown == mesh::no_index || b.unknown == mesh::no_index) continue;
                expected[{a.unknown, b.unknown}] += a.coefficient * b.coefficient;
            }
        }
    }
    CHECK(pattern.row_offsets == from_stencils.row_offsets);
    CHECK(pattern.col_indices == from_stencils.col_indices);
    CHECK(pattern.values.empty());
    for (const solver::CsrMatrix* n : {&listed, &from_stencils}) {
        REQUIRE(n->rows == unknowns.count());
        REQUIRE(n->nonzeros() == expected.size());
        std::size_t mismatches = 0;
        auto e = expected.begin();
        for (std::uint32_t i = 0; i < n->rows; ++i) {
            for (std::size_t k = n->row_offsets[i]; k < n->row_offsets[i + 1]; ++k, ++e) {
                const bool same = e->first == std::pair(i, n->col_indices[k]) &&
                                  std::memcmp(&e->second, &n->values[k], sizeof(double)) == 0;
                mismatches += same ? 0 : 1;
            }
        }
        CHECK(mismatches == 0);
    }
}

TEST_CASE("cow: zero handle motion returns the rest mesh, outside the ROI is bit-identical") {
    const deform::MeshModel model = test::load_real_model("cow");
    const std::vector<std::uint32_t> roi = test::ball_around(model, 771, 0.2);
    const std::vector<std::vector<std::uint32_t>> groups = {test::ball_around(model, 771, 0.03)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, s).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    CHECK(r.converged);
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        CHECK(glm::length(s->positions()[v] - model.mesh.positions[v]) < 1e-9 * model.diagonal);
    }

    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    for (glm::dvec3& t : targets) t += glm::dvec3(0.08, 0.03, 0.0) * model.diagonal;
    REQUIRE(s->set_targets(targets).is_ok());
    REQUIRE(s->solve(r).is_ok());
    CHECK(r.converged);
    std::vector<std::uint8_t> in_roi(model.mesh.vertex_count(), 0);
    for (std::uint32_t v : roi) in_roi[v] = 1;
    std::size_t outside = 0;
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (in_roi[v]) continue;
        ++outside;
        CHECK(s->positions()[v] == model.mesh.positions[v]);
    }
    CHECK(outside > 2000);
    const deform::QualityReport q =
        deform::measure_quality(model, s->positions(), in_roi, s->handle_vertices(), s->targets());
    CHECK(q.max_fixed_move == 0.0);
    CHECK(q.max_handle_error < 1e-3);
    CHECK(q.flipped_faces == 0);
}

TEST_CASE("cow: rotating both ends of the whole mesh by 45 degrees gives the rotated cow") {
    const deform::MeshModel model = test::load_real_model("cow");
    // The snout and the tail tip, at opposite ends of the cow.
    std::uint32_t lo = 0;
    std::uint32_t hi = 0;
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (model.mesh.positions[v].x < model.mesh.positions[lo].x) lo = v;
        if (model.mesh.positions[v].x > model.mesh.positions[hi].x) hi = v;
    }
    const std::vector<std::vector<std::uint32_t>> groups = {test::ball_around(model, lo, 0.05),
                                                            test::ball_around(model, hi, 0.05)};
    const glm::dmat4 rot =
        glm::rotate(glm::dmat4(1.0), glm::radians(45.0), glm::normalize(glm::dvec3(0.3, 1.0, 0.2)));
    auto rotated = [&](const glm::dvec3& p) { return glm::dvec3(rot * glm::dvec4(p, 1.0)); };
    deform::DeformSettings settings;
    settings.tolerance = 1e-8;
    settings.max_iterations = 300;
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, all_vertices(model), groups, settings, s).is_ok());
    std::vector<glm::dvec3> targets;
    for (std::uint32_t v : s->handle_vertices())
        targets.push_back(rotated(model.mesh.positions[v]));
    REQUIRE(s->set_targets(targets).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    double worst = 0.0;
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        worst = std::max(worst, glm::length(s->positions()[v] - rotated(model.mesh.positions[v])));
    }
    CAPTURE(r.iterations);
    CHECK(r.converged);
    CHECK(worst < 1e-4 * model.diagonal);
}

TEST_CASE("cow with a hole cut in it: finite everywhere, handles met") {
    deform::MeshModel cow = test::load_real_model("cow");
    // Remove every face around the flank vertex 1500 and its ring.
    const std::vector<std::uint32_t> hole = test::ball_around(cow, 1500, 0.04);
    std::vector<std::uint8_t> cut(cow.mesh.vertex_count(), 0);
    for (std::uint32_t v : hole) cut[v] = 1;
    mesh::Mesh m = cow.mesh;
    std::erase_if(m.triangles,
                  [&](const mesh::Triangle& t) { return cut[t[0]] && cut[t[1]] && cut[t[2]]; });
    REQUIRE(m.face_count() < cow.mesh.face_count());
    const deform::MeshModel model = deform::build_mesh_model(std::move(m));
    CHECK(model.dual.boundary_faces > 0);
    const std::vector<std::uint32_t> roi = test::ball_around(model, 1500, 0.3);
    std::uint32_t far = roi.front();
    for (std::uint32_t v : roi) {
        if (!cut[v] &&
            glm::length(model.mesh.positions[v] - model.mesh.positions[1500]) >
                glm::length(model.mesh.positions[far] - model.mesh.positions[1500]) &&
            glm::length(model.mesh.positions[v] - model.mesh.positions[1500]) <
                0.2 * model.diagonal) {
            far = v;
        }
    }
    const std::vector<std::vector<std::uint32_t>> groups = {{far}};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, s).is_ok());
    const glm::dvec3 target =
        model.mesh.positions[far] + glm::dvec3(0.0, 0.05, 0.0) * model.diagonal;
    REQUIRE(s->set_targets(std::span(&target, 1)).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    for (const glm::dvec3& p : s->positions()) {
        REQUIRE(std::isfinite(p.x + p.y + p.z));
    }
    CHECK(glm::length(s->positions()[far] - target) < 1e-2 * model.diagonal);
}
