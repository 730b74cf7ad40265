// dualform_cgal_peer: CGAL's Surface_mesh_deformation (SRE-ARAP, the
// original ARAP or ARAP's spokes and rims) on an edit defined by its vertex
// sets, and the quality figures of docs/benchmarks.md for its result or for
// another engine's (--eval). The figures come from the rest and deformed
// positions alone.
//
//   dualform_cgal_peer --mesh M.off (--roi-file F | --roi-ball V R | --roi-all)
//       (--handles-file F | --handle-ball V R) [--rotate X,Y,Z,DEGREES] [--translate X,Y,Z]
//       [--mode sre|arap|spokes_and_rims] [--iterations N] [--until D]
//       [--out OUT.off] [--eval OTHER.off]
//
// --iterations caps CGAL's iterations; --until D stops them earlier, once
// an iteration moves no vertex by more than D of the diagonal (converged
// ARAP: --mode spokes_and_rims --iterations 1000 --until 1e-9).
//
// Radii and the translation are fractions of the bounding-box diagonal; the
// rotation turns the handles about their rest centroid, before the
// translation (a scenario's "pivot": "centroid"). A
// ball is the set of vertices reachable from V along edges without leaving
// the Euclidean ball (Dualform's scenario rule); the handle ball stays in the
// ROI. Fixed: every vertex outside the ROI and every ROI vertex with a
// neighbour outside it that is not a handle. Prints one JSON line.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Vertex = SurfaceMesh::Vertex_index;
using Vec = Eigen::Vector3d;

struct Ball {
    long center = -1;
    double radius = 0.0;
};

struct Options {
    std::string mesh, roi_file, handles_file, out, eval, mode = "sre";
    Ball roi_ball, handle_ball;
    bool roi_all = false;
    Vec translate = Vec::Zero();
    Vec axis = Vec::UnitZ();
    double degrees = 0.0;
    int iterations = 10;
    double until = 0.0;  // of the diagonal; 0: run every iteration
};

[[noreturn]] void fail(const std::string& message) {
    throw std::runtime_error(message);
}

Vec parse_vector(const std::string& text) {
    std::string t = text;
    std::replace(t.begin(), t.end(), ',', ' ');
    std::istringstream in(t);
    Vec v;
    if (!(in >> v.x() >> v.y() >> v.z())) fail("expected X,Y,Z, got '" + text + "'");
    return v;
}

Options parse_options(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) fail(a + " needs a value");
            return argv[++i];
        };
        auto ball = [&](Ball& b) {
            b.center = std::stol(value());
            b.radius = std::stod(value());
        };
        if (a == "--mesh")
            o.mesh = value();
        else if (a == "--roi-file")
            o.roi_file = value();
        else if (a == "--roi-ball")
            ball(o.roi_ball);
        else if (a == "--roi-all")
            o.roi_all = true;
        else if (a == "--handles-file")
            o.handles_file = value();
        else if (a == "--handle-ball")
            ball(o.handle_ball);
        else if (a == "--translate")
            o.translate = parse_vector(value());
        else if (a == "--rotate") {
            std::string t = value();
            const std::size_t last = t.rfind(',');
            if (last == std::string::npos) fail("--rotate expects X,Y,Z,DEGREES");
            o.axis = parse_vector(t.substr(0, last));
            o.degrees = std::stod(t.substr(last + 1));
            if (!(o.axis.norm() > 0.0)) fail("--rotate: the axis must not be zero");
        } else if (a == "--mode")
            o.mode = value();
        else if (a == "--iterations")
            o.iterations = std::stoi(value());
        else if (a == "--until")
            o.until = std::stod(value());
        else if (a == "--out")
            o.out = value();
        else if (a == "--eval")
            o.eval = value();
        else
            fail("unknown argument " + a);
    }
    if (o.mesh.empty()) fail("--mesh is required");
    if (o.mode != "sre" && o.mode != "arap" && o.mode != "spokes_and_rims")
        fail("--mode is sre, arap or spokes_and_rims");
    if (o.iterations < 1) fail("--iterations must be at least 1");
    if (!(o.until >= 0.0)) fail("--until must not be negative");
    return o;
}

SurfaceMesh read_mesh(const std::string& path) {
    SurfaceMesh m;
    std::ifstream in(path);
    if (!in || !CGAL::IO::read_OFF(in, m) || m.has_garbage()) fail(path + ": not a readable OFF");
    for (auto f : m.faces()) {
        if (m.degree(f) != 3) fail(path + ": not a triangle mesh");
    }
    return m;
}

std::vector<Vec> positions_of(const SurfaceMesh& m) {
    std::vector<Vec> p(m.number_of_vertices());
    for (Vertex v : m.vertices()) {
        const Point& q = m.point(v);
        p[v.idx()] = Vec(q.x(), q.y(), q.z());
    }
    return p;
}

std::vector<char> read_set(const std::string& path, std::size_t n) {
    std::ifstream in(path);
    if (!in) fail(path + ": cannot open");
    std::vector<char> set(n, 0);
    long v = 0;
    while (in >> v) {
        if (v < 0 || static_cast<std::size_t>(v) >= n) fail(path + ": vertex out of range");
        set[static_cast<std::size_t>(v)] = 1;
    }
    if (!in.eof()) fail(path + ": expected vertex indices");
    return set;
}

// Vertices reachable from the centre along edges inside the ball, among
// those `allowed`.
std::vector<char> connected_ball(const SurfaceMesh& m, const std::vector<Vec>& p, Ball b,
                                 double diag, const std::vector<char>& allowed) {
    const std::size_t n = p.size();
    if (b.center < 0 || static_cast<std::size_t>(b.center) >= n) fail("ball centre out of range");
    std::vector<char> in(n, 0);
    const Vec c = p[static_cast<std::size_t>(b.center)];
    std::vector<std::size_t> stack{static_cast<std::size_t>(b.center)};
    in[stack[0]] = 1;
    while (!stack.empty()) {
        const std::size_t v = stack.back();
        stack.pop_back();
        for (Vertex w : CGAL::vertices_around_target(m.halfedge(Vertex(v)), m)) {
            const std::size_t k = w.idx();
            if (in[k] || !allowed[k] || (p[k] - c).norm() > b.radius * diag) continue;
            in[k] = 1;
            stack.push_back(k);
        }
    }
    return in;
}

std::size_t count(const std::vector<char>& set) {
    return static_cast<std::size_t>(std::count(set.begin(), set.end(), 1));
}

struct Edit {
    double diag = 0.0;
    std::vector<char> roi, handle, fixed;
    std::vector<Vec> targets;  // per vertex; meaningful on handles
};

Edit make_edit(const Options& o, const SurfaceMesh& m, const std::vector<Vec>& p) {
    Edit e;
    Vec lo = p[0], hi = p[0];
    for (const Vec& q : p) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
    }
    e.diag = (hi - lo).norm();
    const std::size_t n = p.size();
    const std::vector<char> everything(n, 1);
    if (!o.roi_file.empty())
        e.roi = read_set(o.roi_file, n);
    else if (o.roi_all)
        e.roi = everything;
    else if (o.roi_ball.center >= 0)
        e.roi = connected_ball(m, p, o.roi_ball, e.diag, everything);
    else
        fail("no ROI: --roi-file, --roi-ball or --roi-all");
    if (!o.handles_file.empty())
        e.handle = read_set(o.handles_file, n);
    else if (o.handle_ball.center >= 0)
        e.handle = connected_ball(m, p, o.handle_ball, e.diag, e.roi);
    else
        fail("no handles: --handles-file or --handle-ball");
    e.fixed.assign(n, 0);
    e.targets = p;
    Vec pivot = Vec::Zero();
    for (std::size_t v = 0; v < n; ++v) {
        if (e.handle[v]) pivot += p[v];
    }
    pivot /= std::max<double>(1.0, static_cast<double>(count(e.handle)));
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(o.degrees * std::numbers::pi / 180.0, o.axis.normalized())
            .toRotationMatrix();
    for (std::size_t v = 0; v < n; ++v) {
        if (e.handle[v] && !e.roi[v])
            fail("handle vertex " + std::to_string(v) + " is outside the ROI");
        if (e.handle[v]) e.targets[v] = pivot + turn * (p[v] - pivot) + o.translate * e.diag;
        if (!e.roi[v]) {
            e.fixed[v] = 1;
            continue;
        }
        if (e.handle[v]) continue;
        for (Vertex w : CGAL::vertices_around_target(m.halfedge(Vertex(v)), m)) {
            if (!e.roi[w.idx()]) e.fixed[v] = 1;
        }
    }
    return e;
}

// ---------------------------------------------------------------- figures

struct Figures {
    double handle_error = 0.0, edge_mean = 0.0, edge_max = 0.0, normal_mean = 0.0;
    double normal_max = 0.0, arap = 0.0, fixed_move = 0.0, dual_magnitude = 0.0;
    std::size_t flipped = 0, creased = 0, edges = 0, faces = 0;
};

// The signed angle between the normals of the faces on either side of edge
// a → b, about that edge.
double dihedral(const Vec& a, const Vec& b, const Vec& left, const Vec& right) {
    const Vec edge = b - a;
    const Vec n1 = edge.cross(left - a), n2 = (right - a).cross(edge);
    return std::atan2(n1.cross(n2).dot(edge) / std::max(edge.norm(), 1e-300), n1.dot(n2));
}

// Half the clamped cotangent of the corner at `c`, on the rest shape.
double half_cotangent(const Vec& a, const Vec& b, const Vec& c) {
    const Vec u = a - c, v = b - c;
    const double s = u.cross(v).norm();
    return s > 0.0 ? 0.5 * std::max(0.0, u.dot(v) / s) : 0.0;
}

// Σ_i min_R Σ_j w_ij |(q_i − q_j) − R (p_i − p_j)|² / Σ_i Σ_j w_ij |p_i − p_j|²
// over the ROI vertices i and their neighbours j, w_ij the clamped
// cotangent weight of the rest shape.
double arap_energy(const SurfaceMesh& m, const Edit& e, const std::vector<Vec>& p,
                   const std::vector<Vec>& q) {
    std::vector<double> weight(m.number_of_edges(), 0.0);
    for (auto h : m.halfedges()) {
        if (m.is_border(h)) continue;
        weight[m.edge(h).idx()] += half_cotangent(p[m.source(h).idx()], p[m.target(h).idx()],
                                                  p[m.target(m.next(h)).idx()]);
    }
    double energy = 0.0, scale = 0.0;
    for (Vertex vi : m.vertices()) {
        const std::size_t i = vi.idx();
        if (!e.roi[i]) continue;
        Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
        for (auto h : CGAL::halfedges_around_target(m.halfedge(vi), m)) {
            const std::size_t j = m.source(h).idx();
            const double w = weight[m.edge(h).idx()];
            covariance += w * (q[i] - q[j]) * (p[i] - p[j]).transpose();
            scale += w * (p[i] - p[j]).squaredNorm();
        }
        Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
        d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
        const Eigen::Matrix3d r = svd.matrixU() * d * svd.matrixV().transpose();
        for (auto h : CGAL::halfedges_around_target(m.halfedge(vi), m)) {
            const std::size_t j = m.source(h).idx();
            energy += weight[m.edge(h).idx()] * ((q[i] - q[j]) - r * (p[i] - p[j])).squaredNorm();
        }
    }
    return scale > 0.0 ? energy / scale : 0.0;
}

// Dualform's dual magnitude error (docs/scenarios.md): over the faces that
// touch the ROI and whose three neighbours' centroids span a plane, the
// change of |l_f|, l_f = Σ_j w_j c_j − c_f for the rest weights w of the
// foot of c_f on that plane, from its rest height |h_f|, summed and over
// the sum of |h_f|. The detail a deformation keeps: a rigid motion keeps
// every l_f's length.
double dual_magnitude_error(const SurfaceMesh& m, const Edit& e, const std::vector<Vec>& p,
                            const std::vector<Vec>& q) {
    std::vector<Vec> rest(m.number_of_faces()), now(m.number_of_faces());
    for (auto face : m.faces()) {
        Vec a = Vec::Zero(), b = Vec::Zero();
        for (Vertex v : CGAL::vertices_around_face(m.halfedge(face), m)) {
            a += p[v.idx()];
            b += q[v.idx()];
        }
        rest[face.idx()] = a / 3.0;
        now[face.idx()] = b / 3.0;
    }
    double error = 0.0, sum = 0.0;
    for (auto face : m.faces()) {
        bool touches = false;
        std::size_t ring[3], k = 0;
        for (auto h : CGAL::halfedges_around_face(m.halfedge(face), m)) {
            touches = touches || e.roi[m.target(h).idx()];
            const auto o = m.opposite(h);
            if (k < 3 && !m.is_border(o)) ring[k++] = m.face(o).idx();
        }
        if (!touches || k < 3) continue;
        const std::size_t f = face.idx();
        const Vec cross = (rest[ring[1]] - rest[ring[0]]).cross(rest[ring[2]] - rest[ring[0]]);
        const double scale = (rest[ring[1]] - rest[ring[0]]).squaredNorm() +
                             (rest[ring[2]] - rest[ring[0]]).squaredNorm();
        if (!(scale > 0.0) || !(cross.norm() > 1e-12 * scale)) continue;
        const Vec normal = cross.normalized();
        const double height = (rest[f] - rest[ring[0]]).dot(normal);
        const Vec foot = rest[f] - height * normal;
        const double area2 = cross.dot(normal);
        const double w0 = (rest[ring[1]] - foot).cross(rest[ring[2]] - foot).dot(normal) / area2;
        const double w1 = (rest[ring[2]] - foot).cross(rest[ring[0]] - foot).dot(normal) / area2;
        const Vec l =
            w0 * now[ring[0]] + w1 * now[ring[1]] + (1.0 - w0 - w1) * now[ring[2]] - now[f];
        error += std::abs(l.norm() - std::abs(height));
        sum += std::abs(height);
    }
    return sum > 0.0 ? error / sum : 0.0;
}

Figures measure(const SurfaceMesh& m, const Edit& e, const std::vector<Vec>& p,
                const std::vector<Vec>& q) {
    Figures f;
    for (std::size_t v = 0; v < p.size(); ++v) {
        if (e.handle[v])
            f.handle_error = std::max(f.handle_error, (q[v] - e.targets[v]).norm() / e.diag);
        if (e.fixed[v]) f.fixed_move = std::max(f.fixed_move, (q[v] - p[v]).norm() / e.diag);
    }
    for (auto edge : m.edges()) {
        const std::size_t a = m.vertex(edge, 0).idx(), b = m.vertex(edge, 1).idx();
        if (!e.roi[a] && !e.roi[b]) continue;
        const double before = (p[a] - p[b]).norm(), after = (q[a] - q[b]).norm();
        if (!(before > 0.0) || !(after > 0.0)) continue;
        const double l = std::abs(std::log(after / before));
        f.edge_mean += l;
        f.edge_max = std::max(f.edge_max, l);
        ++f.edges;
    }
    if (f.edges > 0) f.edge_mean /= static_cast<double>(f.edges);
    for (auto face : m.faces()) {
        std::size_t t[3], k = 0;
        bool touches = false;
        for (Vertex v : CGAL::vertices_around_face(m.halfedge(face), m)) {
            t[k++] = v.idx();
            touches = touches || e.roi[v.idx()];
        }
        if (!touches) continue;
        const Vec n0 = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
        const Vec n1 = (q[t[1]] - q[t[0]]).cross(q[t[2]] - q[t[0]]);
        if (!(n0.norm() > 0.0) || !(n1.norm() > 0.0)) continue;
        const double degrees =
            std::atan2(n0.cross(n1).norm(), n0.dot(n1)) * 180.0 / std::numbers::pi;
        f.normal_mean += degrees;
        f.normal_max = std::max(f.normal_max, degrees);
        if (degrees > 90.0) ++f.flipped;
        ++f.faces;
    }
    if (f.faces > 0) f.normal_mean /= static_cast<double>(f.faces);
    // Creases: edges between two ROI vertices whose dihedral angle turned by
    // more than 90° (Dualform's creased_edges).
    for (auto h : m.halfedges()) {
        const auto o = m.opposite(h);
        if (m.is_border(h) || m.is_border(o) || h > o) continue;
        const std::size_t a = m.source(h).idx(), b = m.target(h).idx();
        if (!e.roi[a] || !e.roi[b]) continue;
        const std::size_t c = m.target(m.next(h)).idx(), d = m.target(m.next(o)).idx();
        const double turn =
            std::remainder(dihedral(q[a], q[b], q[c], q[d]) - dihedral(p[a], p[b], p[c], p[d]),
                           2.0 * std::numbers::pi);
        if (std::abs(turn) > 0.5 * std::numbers::pi) ++f.creased;
    }
    f.arap = arap_energy(m, e, p, q);
    f.dual_magnitude = dual_magnitude_error(m, e, p, q);
    return f;
}

// ---------------------------------------------------------------- CGAL

// CGAL's iterations and the last one's largest vertex move / diagonal.
struct Run {
    int iterations = 0;
    double last_update = 0.0;
    double ms = 0.0;
};

// Runs `iterations` of CGAL's deformation from rest, one at a time (each
// call goes on from the last one's positions and rotations, as one call of
// many iterations does), stopping early once an iteration moves no ROI
// vertex by more than `until` of the diagonal.
template <CGAL::Deformation_algorithm_tag Tag>
std::vector<Vec> deform(SurfaceMesh m, const Edit& e, int iterations, double until, Run& run) {
    CGAL::Surface_mesh_deformation<SurfaceMesh, CGAL::Default, CGAL::Default, Tag> deformer(m);
    std::vector<Vertex> handles;
    for (Vertex v : m.vertices()) {
        if (!e.roi[v.idx()]) continue;
        deformer.insert_roi_vertex(v);
        if (e.handle[v.idx()] || e.fixed[v.idx()]) deformer.insert_control_vertex(v);
        if (e.handle[v.idx()]) handles.push_back(v);
    }
    if (!deformer.preprocess()) fail("CGAL could not factor the system");
    for (Vertex v : handles) {
        const Vec& t = e.targets[v.idx()];
        deformer.set_target_position(v, Point(t.x(), t.y(), t.z()));
    }
    const auto start = std::chrono::steady_clock::now();
    if (until <= 0.0) {
        deformer.deform(static_cast<unsigned int>(iterations), 0.0);
        run.iterations = iterations;
    } else {
        std::vector<Vec> last = positions_of(m);
        while (run.iterations < iterations) {
            deformer.deform(1, 0.0);
            ++run.iterations;
            const std::vector<Vec> now = positions_of(m);
            run.last_update = 0.0;
            for (std::size_t v = 0; v < now.size(); ++v) {
                if (e.roi[v])
                    run.last_update = std::max(run.last_update, (now[v] - last[v]).norm() / e.diag);
            }
            last = now;
            if (run.last_update < until) break;
        }
    }
    run.ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return positions_of(m);
}

void write_off(const std::string& path, const SurfaceMesh& m, const std::vector<Vec>& q) {
    std::ofstream out(path);
    if (!out) fail(path + ": cannot write");
    out.precision(17);
    out << "OFF\n" << q.size() << ' ' << m.number_of_faces() << " 0\n";
    for (const Vec& v : q) out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (auto face : m.faces()) {
        out << 3;
        for (Vertex v : CGAL::vertices_around_face(m.halfedge(face), m)) out << ' ' << v.idx();
        out << '\n';
    }
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse_options(argc, argv);
        const SurfaceMesh m = read_mesh(o.mesh);
        const std::vector<Vec> p = positions_of(m);
        const Edit e = make_edit(o, m, p);
        std::vector<Vec> q;
        Run run;
        std::string engine;
        if (!o.eval.empty()) {
            q = positions_of(read_mesh(o.eval));
            if (q.size() != p.size()) fail(o.eval + ": a different vertex count");
            engine = "eval";
        } else if (o.mode == "sre") {
            q = deform<CGAL::SRE_ARAP>(m, e, o.iterations, o.until, run);
            engine = "CGAL SRE_ARAP";
        } else if (o.mode == "arap") {
            q = deform<CGAL::ORIGINAL_ARAP>(m, e, o.iterations, o.until, run);
            engine = "CGAL ORIGINAL_ARAP";
        } else {
            q = deform<CGAL::SPOKES_AND_RIMS>(m, e, o.iterations, o.until, run);
            engine = "CGAL SPOKES_AND_RIMS";
        }
        if (!o.out.empty()) write_off(o.out, m, q);
        const Figures f = measure(m, e, p, q);
        std::printf(
            "{\"engine\":\"%s\",\"iterations\":%d,\"last_update\":%.3g,\"deform_ms\":%.3f,"
            "\"n_roi\":%zu,\"n_handles\":%zu,\"n_fixed_in_roi\":%zu,\"handle_err_max\":%.3g,"
            "\"edge_log_mean\":%.5f,\"edge_log_max\":%.4f,\"normal_dev_mean_deg\":%.3f,"
            "\"normal_dev_max_deg\":%.2f,\"n_flipped\":%zu,\"n_creased\":%zu,\"arap_energy_rel\":%."
            "5g,"
            "\"dual_magnitude_error\":%.5f,\"fixed_disp_max\":%.3g,\"n_roi_edges\":%zu,"
            "\"n_roi_faces\":%zu}\n",
            engine.c_str(), run.iterations, run.last_update, run.ms, count(e.roi), count(e.handle),
            count(e.fixed) - (p.size() - count(e.roi)), f.handle_error, f.edge_mean, f.edge_max,
            f.normal_mean, f.normal_max, f.flipped, f.creased, f.arap, f.dual_magnitude,
            f.fixed_move, f.edges, f.faces);
        return 0;
    } catch (const std::exception& x) {
        std::fprintf(stderr, "dualform_cgal_peer: %s\n", x.what());
        return 2;
    }
}
