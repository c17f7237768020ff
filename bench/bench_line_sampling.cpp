// Study 7 of issue 39 (bench/RESULTS.md, "Line sampling"): would line sampling (C. Billen,
// P. Dutré, "Line Sampling for Direct Illumination", EGSR 2016) reach 1 % luminance error on the
// room in less time than the nested prefixes of the local set? Each receiver integrates N arcs of
// its tangent frame exactly in one dimension and samples only the other.
//
//  * Error: the arcs are approximated by a grid of N arcs × M directions (M = 64 and 256; the
//    two agree, so an arc of 64 directions is already almost exact). Two families: meridians (N
//    azimuths φ = 2π(i + 0.37)/N, M directions along each, equally spaced in u = sin²θ, so
//    cosine-weighted) and parallels (N rings in u, M azimuths each). Baked as a caller's local
//    set (weights π/(N·M)), against plain local Sobol bakes: luminance error against the
//    65 536-sample reference and each receiver's true error against a local Sobol bake of
//    16 384 (seed 7919), as in bench_edge_refine.
//  * Cost (--wedge): a meridian is exactly the quarter-plane {o + α·a + β·n : α, β ≥ 0} through the
//    receiver, so its visible part is what the triangles that plane cuts leave uncovered. One
//    naive query per arc on the flat BVH (every node whose box meets the quarter-plane, every
//    cut segment clipped to the quadrant and mapped to its u-interval, the intervals merged),
//    timed against rays on the same BVH, one thread; its visible u-measure checked against
//    `--wedge-rays` rays along the arc.
//
//     build/bench/bench_line_sampling [--max-rays 8192] [--wedge] [--wedge-rays 1024]
#include "room_study.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/host.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/flat_bvh.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

using namespace shprt;
using Clock = std::chrono::steady_clock;

// N lines of M directions each in the local frame: meridians (lines of constant φ) or parallels
// (lines of constant u = sin²θ).
static DirectionSet line_grid(int N, int M, bool meridians) {
    DirectionSet s;
    s.frame = DirectionFrame::local;
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < M; ++j) {
            const double line = meridians ? (i + 0.37) / N : (i + 0.5) / N;
            const double along = meridians ? (j + 0.5) / M : (j + 0.37) / M;
            const double phi = 2 * std::numbers::pi * (meridians ? line : along);
            const double u = meridians ? along : line;
            const double st = std::sqrt(u), ct = std::sqrt(1 - u);
            s.dirs.push_back(float(st * std::cos(phi)));
            s.dirs.push_back(float(st * std::sin(phi)));
            s.dirs.push_back(float(ct));
            s.weights.push_back(float(std::numbers::pi / (double(N) * M)));
        }
    }
    return s;
}

// Every node of the flat BVH whose box `enters` accepts, and every triangle of their leaves
// (given to `leaf` as its three vertices): the naive query of a line. Returns the nodes visited.
template <class Enters, class Leaf>
static std::uint64_t visit_where(const FlatBvhView& bvh, Enters&& enters, Leaf&& leaf) {
    std::uint64_t nodes = 0;
    std::uint32_t stack[kFlatBvhStackSize];
    int sp = 0;
    std::uint32_t ref = 0;
    for (;;) {
        if (!flat_bvh_is_leaf(ref)) {
            Aabb b0, b1;
            std::uint32_t c0, c1;
            flat_bvh_load_node(bvh, ref, b0, b1, c0, c1);
            ++nodes;
            const bool h0 = enters(b0), h1 = enters(b1);
            if (h0 && h1) stack[sp++] = c1;
            if (h0 || h1) {
                ref = h0 ? c0 : c1;
                continue;
            }
        } else {
            const std::uint32_t first = flat_bvh_leaf_first(ref);
            for (std::uint32_t i = first; i < first + flat_bvh_leaf_count(ref); ++i) {
                Vec3f v[3], n;
                flat_bvh_load_triangle(bvh, i, v[0], v[1], v[2], n);
                leaf(v);
            }
        }
        if (sp == 0) return nodes;
        ref = stack[--sp];
    }
}

// The occluded part of one meridian arc, exactly: every triangle the quarter-plane
// {o + α·a + β·n : α, β ≥ 0} cuts occludes the u = sin²θ interval its clipped segment spans.
// Naive traversal: every node whose box meets the quarter-plane. Returns the visible u-measure.
struct WedgeCost {
    std::uint64_t nodes = 0, tris = 0, cuts = 0;
};
static double wedge_visible(const FlatBvhView& bvh, Vec3f o, Vec3f a, Vec3f n, WedgeCost& cost,
                            std::vector<std::pair<double, double>>& iv) {
    const Vec3f p = cross(a, n);
    iv.clear();
    auto box_hit = [&](const Aabb& b) {
        const Vec3f c = (b.lo + b.hi) * 0.5f - o, e = (b.hi - b.lo) * 0.5f;
        auto reach = [&](Vec3f d) {
            return std::abs(d.x) * e.x + std::abs(d.y) * e.y + std::abs(d.z) * e.z;
        };
        return std::abs(dot(p, c)) <= reach(p) && dot(a, c) + reach(a) >= 0 &&
               dot(n, c) + reach(n) >= 0;
    };
    cost.nodes += visit_where(bvh, box_hit, [&](const Vec3f* v) {
        ++cost.tris;
        double d[3], al[3], be[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3f r = v[k] - o;
            d[k] = dot(p, r), al[k] = dot(a, r), be[k] = dot(n, r);
        }
        double pa[2], pb[2];
        int m = 0;
        for (int k = 0; k < 3 && m < 2; ++k) {
            const int j = (k + 1) % 3;
            if ((d[k] < 0) != (d[j] < 0)) {
                const double t = d[k] / (d[k] - d[j]);
                pa[m] = al[k] + t * (al[j] - al[k]), pb[m] = be[k] + t * (be[j] - be[k]);
                ++m;
            }
        }
        if (m < 2) return;
        // Clip the segment to α ≥ 0, β ≥ 0.
        double t0 = 0, t1 = 1;
        const double da = pa[1] - pa[0], db = pb[1] - pb[0];
        auto clip = [&](double s0, double ds) {  // keep s0 + t·ds ≥ 0
            if (ds == 0) return s0 >= 0;
            const double t = -s0 / ds;
            if (ds > 0)
                t0 = std::max(t0, t);
            else
                t1 = std::min(t1, t);
            return t0 < t1;
        };
        if (!clip(pa[0], da) || !clip(pb[0], db)) return;
        auto u_at = [&](double t) {
            const double x = pa[0] + t * da, y = pb[0] + t * db;
            return x * x / std::max(x * x + y * y, 1e-300);
        };
        // Leave out the part within kNear of the origin (the rays' self-hit margin).
        const double kNear = 1e-4;
        const double qa = da * da + db * db, qb = 2 * (pa[0] * da + pb[0] * db),
                     qc = pa[0] * pa[0] + pb[0] * pb[0] - kNear * kNear;
        const double disc = qb * qb - 4 * qa * qc;
        auto add = [&](double s0, double s1) {
            if (s1 <= s0) return;
            const double u0 = u_at(s0), u1 = u_at(s1);
            iv.emplace_back(std::min(u0, u1), std::max(u0, u1));
        };
        if (disc <= 0 || qa == 0) {
            add(t0, t1);
        } else {
            const double r1 = (-qb - std::sqrt(disc)) / (2 * qa),
                         r2 = (-qb + std::sqrt(disc)) / (2 * qa);
            add(t0, std::min(t1, r1));
            add(std::max(t0, r2), t1);
        }
        ++cost.cuts;
    });
    std::sort(iv.begin(), iv.end());
    double covered = 0, lo = 0, hi = -1;
    for (const auto& [x, y] : iv) {
        if (x > hi) {
            if (hi > lo) covered += hi - lo;
            lo = x, hi = y;
        } else
            hi = std::max(hi, y);
    }
    if (hi > lo) covered += hi - lo;
    return 1 - covered;
}

static void wedge_study(const Mesh& mesh, int N, int M, int stride) {
    const FlatBvh bvh = build_flat_bvh(mesh);
    const auto tracer = make_embree_tracer(mesh);
    std::vector<Vec3f> dirs(static_cast<std::size_t>(M));
    std::vector<std::uint8_t> hit(static_cast<std::size_t>(M));
    double embree_s = 0;
    const FlatBvhView view = bvh.view();
    WedgeCost cost;
    std::vector<std::pair<double, double>> iv;
    double diff = 0, wedge_s = 0, ray_s = 0;
    std::size_t arcs = 0, rays = 0, bad = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); v += std::size_t(stride)) {
        const LocalAxes f = local_axes(mesh.normals[v]);
        const Vec3f o = offset_ray_origin(mesh.positions[v], f.n);
        for (int i = 0; i < N; ++i) {
            const double phi = 2 * std::numbers::pi * (i + 0.37) / N;
            const Vec3f a = f.t * float(std::cos(phi)) + f.b * float(std::sin(phi));
            auto t0 = Clock::now();
            const double vis = wedge_visible(view, o, a, f.n, cost, iv);
            auto t1 = Clock::now();
            int seen = 0;
            for (int j = 0; j < M; ++j) {
                const double u = (j + 0.5) / M;
                dirs[std::size_t(j)] = a * float(std::sqrt(u)) + f.n * float(std::sqrt(1 - u));
                seen += bvh_occluded(view, o, dirs[std::size_t(j)], 0.0f, 1e30f) ? 0 : 1;
            }
            auto t2 = Clock::now();
            tracer->occluded(o, dirs.data(), M, 0.0f, 1e30f, hit.data());
            embree_s += std::chrono::duration<double>(Clock::now() - t2).count();
            wedge_s += std::chrono::duration<double>(t1 - t0).count();
            ray_s += std::chrono::duration<double>(t2 - t1).count();
            diff += std::abs(vis - double(seen) / M);
            if (std::abs(vis - double(seen) / M) > 0.05) ++bad;
            ++arcs, rays += std::size_t(M);
        }
    }
    const double n_arcs = double(arcs);
    std::printf(
        "\nwedge queries (naive, flat BVH, 1 thread): %zu arcs (%d per receiver, every %dth "
        "receiver)\n  per arc: %.1f nodes, %.1f triangles tested, %.1f cut; %.2f us; a "
        "flat-BVH ray %.3f us, so an arc costs %.1f of its rays and %.0f Embree rays (%.4f us "
        "each)\n  |visible u-measure − "
        "%d rays along the arc|: mean %.5f; %zu arcs differ by more than 0.05\n",
        arcs, N, stride, double(cost.nodes) / n_arcs, double(cost.tris) / n_arcs,
        double(cost.cuts) / n_arcs, 1e6 * wedge_s / n_arcs, 1e6 * ray_s / double(rays),
        (wedge_s / n_arcs) / (ray_s / double(rays)), wedge_s / embree_s * double(rays) / n_arcs,
        1e6 * embree_s / double(rays), M, diff / n_arcs, bad);
}

// The work of an exact parallel (a ring of constant θ around n): every node whose bounding sphere
// reaches angle θ from n as seen from o, and every triangle whose vertices lie on both sides of
// the cone (the triangles it cuts, but for those around the axis). A lower bound on an exact
// query's work: it counts the cut triangles without computing their φ-intervals.
static void cone_study(const Mesh& mesh, int N, int stride) {
    const FlatBvh bvh = build_flat_bvh(mesh);
    const auto tracer = make_embree_tracer(mesh);
    Vec3f dirs[64];
    std::uint8_t hit[64];
    double embree_s = 0;
    const FlatBvhView view = bvh.view();
    std::uint64_t nodes = 0, tris = 0, cuts = 0;
    double cone_s = 0, ray_s = 0;
    std::size_t rings = 0, rays = 0, blocked = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); v += std::size_t(stride)) {
        const LocalAxes f = local_axes(mesh.normals[v]);
        const Vec3f o = offset_ray_origin(mesh.positions[v], f.n);
        for (int i = 0; i < N; ++i) {
            const double u = (i + 0.5) / N, theta = std::asin(std::sqrt(u));
            const auto t0 = Clock::now();
            auto reaches = [&](const Aabb& b) {
                const Vec3f c = (b.lo + b.hi) * 0.5f - o, e = (b.hi - b.lo) * 0.5f;
                const double r = std::sqrt(double(dot(e, e))), d = std::sqrt(double(dot(c, c)));
                if (d <= r) return true;
                const double h = double(dot(f.n, c));
                if (h + r < 0) return false;
                const double a = std::acos(std::clamp(h / d, -1.0, 1.0)), w = std::asin(r / d);
                return a - w <= theta && theta <= a + w;
            };
            nodes += visit_where(view, reaches, [&](const Vec3f* w) {
                ++tris;
                int below = 0, above = 0;
                for (int k = 0; k < 3; ++k) {
                    const Vec3f r = w[k] - o;
                    const double c = double(dot(f.n, r)) / std::sqrt(double(dot(r, r)));
                    (c > std::cos(theta) ? above : below)++;
                }
                if (above && below) ++cuts;
            });
            const auto t1 = Clock::now();
            // The same ring as 64 rays, for the time of a ray.
            for (int j = 0; j < 64; ++j) {
                const double phi = 2 * std::numbers::pi * (j + 0.37) / 64;
                dirs[j] = f.t * float(std::sin(theta) * std::cos(phi)) +
                          f.b * float(std::sin(theta) * std::sin(phi)) +
                          f.n * float(std::cos(theta));
                blocked += bvh_occluded(view, o, dirs[j], 0.0f, 1e30f) ? 1 : 0;
            }
            const auto t2 = Clock::now();
            tracer->occluded(o, dirs, 64, 0.0f, 1e30f, hit);
            embree_s += std::chrono::duration<double>(Clock::now() - t2).count();
            cone_s += std::chrono::duration<double>(t1 - t0).count();
            ray_s += std::chrono::duration<double>(t2 - t1).count();
            ++rings, rays += 64;
        }
    }
    const double n = double(rings);
    std::printf(
        "\ncone queries (naive, flat BVH, 1 thread): %zu rings (%d per receiver, every %dth "
        "receiver)\n  per ring: %.1f nodes, %.1f triangles tested, %.1f cut; %.2f us; a "
        "flat-BVH ray %.3f us, so a ring costs %.1f of its rays and %.0f Embree rays (%.4f us "
        "each; %.3f of the rays blocked)\n",
        rings, N, stride, double(nodes) / n, double(tris) / n, double(cuts) / n, 1e6 * cone_s / n,
        1e6 * ray_s / double(rays), (cone_s / n) / (ray_s / double(rays)),
        cone_s / embree_s * double(rays) / n, 1e6 * embree_s / double(rays),
        double(blocked) / double(rays));
}

int main(int argc, char** argv) {
    std::size_t max_rays = 8192;
    bool wedge = false, cone = false;
    int wedge_rays = 1024;
    CLI::App app{"Line sampling on the room (issue 39, bench/RESULTS.md)"};
    app.add_option("--max-rays", max_rays, "largest N·M baked (default 8192)");
    app.add_flag("--wedge", wedge, "only the cost of exact meridian queries");
    app.add_flag("--cone", cone, "only the work of exact parallels (a lower bound)");
    app.add_option("--wedge-rays", wedge_rays, "rays along an arc to check a query with");
    CLI11_PARSE(app, argc, argv);

    const int K = 256;
    const Mesh mesh = make_builtin("room");
    std::printf("bench_line_sampling: builtin:room (%zu vertices), K = %d, light: %s\nhost: %s\n",
                mesh.vertex_count(), K, room_study::kLightName, host_cpu().c_str());
    if (cone) {
        cone_study(mesh, 32, 8);
        return 0;
    }
    if (wedge) {
        wedge_study(mesh, 128, wedge_rays, 8);
        return 0;
    }
    const auto tracer = make_embree_tracer(mesh);
    const ShLight light = room_study::light(K);
    const std::vector<double> ref = room_study::reference_luminance(
        mesh, *tracer, light, K, 65536, 2, "/tmp/bench_local_directions_reference.bin");
    BakeOptions o;
    o.K = K, o.seed = 7919, o.threads = 2, o.sampler = SamplerKind::sobol;
    o.direction_frame = DirectionFrame::local;
    o.samples = 16384;
    const std::vector<float> cref =
        bake_with_tracer(mesh, o, bake_direction_set(o), *tracer).coeffs;
    std::printf(
        "\n| set | rays per receiver | wall s | luminance %% | true error: mean | p99 | max "
        "|\n|---|---:|---:|---:|---:|---:|---:|\n");
    auto report = [&](const std::string& name, const DirectionSet& set) {
        const auto a = Clock::now();
        const TransferSet t = bake_with_tracer(mesh, o, set, *tracer);
        const double wall = std::chrono::duration<double>(Clock::now() - a).count();
        std::vector<double> e = room_study::true_errors(t.coeffs, cref, K);
        double mean = 0;
        for (const double x : e) mean += x / double(e.size());
        std::sort(e.begin(), e.end());
        std::printf("| %s | %zu | %.3f | %.3f | %.4f | %.4f | %.4f |\n", name.c_str(), set.size(),
                    wall,
                    100 * room_study::relative_rms(room_study::luminance(t.coeffs, K, light), ref),
                    mean, e[e.size() * 99 / 100], e.back());
        std::fflush(stdout);
    };
    o.seed = 1;
    for (const std::uint32_t S : {1024u, 2048u, 4096u, 8192u}) {
        if (S > max_rays) continue;
        o.samples = S;
        report(fmt::format("local Sobol S = {}", S), bake_direction_set(o));
    }
    for (const bool meridians : {true, false})
        for (const int M : {64, 256, 1024})
            for (const int N : {8, 16, 32, 64, 128}) {
                if (std::size_t(N) * std::size_t(M) > max_rays) continue;
                report(
                    fmt::format("{} N = {}, M = {}", meridians ? "meridians" : "parallels", N, M),
                    line_grid(N, M, meridians));
            }
    return 0;
}
