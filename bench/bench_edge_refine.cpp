// Study 6 of issue 39 (bench/RESULTS.md, "Edge refinement"): does refining each receiver's
// directions only at its visibility edges reach 1 % luminance error on the room in fewer rays
// than the nested prefixes of the error-bounded bake?
//
// The local Sobol set of Smax = 2^14 directions (seed 1) is a (0,m,2)-net in its square (u, v)
// (sh/sampler.hpp): cut the square into 2^k cells, 2^⌈k/2⌉ along u by 2^⌊k/2⌋ along v (the
// net's elementary intervals), and each cell holds exactly one of the first 2^k directions, its
// representative. A cell of level k splits into two of level k + 1 (along u and v in turn): one
// keeps the representative, the other's is one new direction. The estimator, per receiver:
//   trace the 2^k0 cells of level k0; then level by level split every cell whose representative
//   disagrees (blocked / visible) with that of a cell within `ring` cells of it at its level
//   (the finest traced one covering it), tracing the new representatives, up to level kmax;
//   ĉ = Σ over visible leaves of the cell's exact table, T_k[c] = Σ (π/Smax)·Y over the Smax
//   directions in the cell (the whole set projected, each cell's visibility taken from its
//   representative), or c_open − Σ over blocked leaves, whichever has fewer leaves.
// Optionally (`rare`) a receiver that saw fewer than `rare` visible or blocked rays at k0 starts
// from level k0 + boost with every cell traced: small openings and blockers.
//
// Two parts:
//  * --replay: every receiver traces all Smax directions once; the estimator is replayed on
//    those bits for many (k0, kmax, ring), counting the rays it would cast. Luminance only, with
//    the light evaluated on a 4096 × 2048 equirect table (bilinear), with the cell tables and
//    with each leaf's representative point-sampled (π·area·f), against the plain prefixes.
//  * live (always): a few settings traced for real, projected on the cell tables, rotated to
//    world: wall time (cell tables, trace, refinement, projection, rotation; 2 threads; the BVH
//    built outside, as for the bakes it is compared with), luminance error, and each receiver's
//    true error ‖ĉ − c‖/‖c_open‖ against a local Sobol bake of 16384, seed 7919 — next to plain
//    local Sobol bakes of 2048, 4096 and 8192.
//
//     build/bench/bench_edge_refine [--replay] [--reps 3] [--reference-cache F]
#include "bake/stages.hpp"
#include "room_study.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/host.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

namespace shprt {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kLevels = 14;
constexpr std::uint32_t kSmax = 1u << kLevels;
constexpr double kPiD = 3.14159265358979323846;
constexpr int K = 256;

int bits_u(int k) { return (k + 1) / 2; }
int bits_v(int k) { return k / 2; }
std::uint32_t cell_id(int k, std::uint32_t i, std::uint32_t j) { return (i << bits_v(k)) | j; }

// The net's cells: rep[k][cell] is the direction of the first 2^k in the cell.
struct Net {
    std::vector<std::uint32_t> a, b;  // the scrambled Sobol words of every direction
    std::vector<std::vector<std::uint32_t>> rep;
    std::uint32_t cell(int k, std::uint32_t s) const {
        const std::uint32_t i = bits_u(k) ? a[s] >> (32 - bits_u(k)) : 0u;
        return cell_id(k, i, bits_v(k) ? b[s] >> (32 - bits_v(k)) : 0u);
    }
    // The parent (level k − 1) of cell c of level k.
    static std::uint32_t parent(int k, std::uint32_t c) {
        const std::uint32_t i = c >> bits_v(k), j = c & ((1u << bits_v(k)) - 1);
        return bits_u(k) > bits_u(k - 1) ? cell_id(k - 1, i >> 1, j) : cell_id(k - 1, i, j >> 1);
    }
};

Net make_net(std::uint64_t seed) {
    Net n;
    n.a.resize(kSmax), n.b.resize(kSmax);
    for (std::uint32_t s = 0; s < kSmax; ++s)
        n.a[s] = sobol_scrambled_u32(seed, s, 0), n.b[s] = sobol_scrambled_u32(seed, s, 1);
    n.rep.resize(kLevels + 1);
    for (int k = 0; k <= kLevels; ++k) {
        n.rep[k].assign(1u << k, ~0u);
        for (std::uint32_t s = 0; s < (1u << k); ++s) {
            const std::uint32_t c = n.cell(k, s);
            if (n.rep[k][c] != ~0u) {
                std::printf("the set is not a (0,m,2)-net at level %d\n", k);
                std::exit(1);
            }
            n.rep[k][c] = s;
        }
    }
    return n;
}

// Sums over each level's cells, from a value per direction of the Smax set (`width` values each):
// out[k][c·width + q] = Σ value[s·width + q] over the directions s in cell c of level k.
std::vector<std::vector<double>> cell_sums(const Net& net, const double* value, int width,
                                           int levels_down_to = 0) {
    std::vector<std::vector<double>> out(kLevels + 1);
    const std::size_t w = std::size_t(width);
    out[kLevels].assign(kSmax * w, 0.0);
    for (std::uint32_t s = 0; s < kSmax; ++s)
        std::copy(value + s * w, value + (s + 1) * w,
                  out[kLevels].begin() + std::ptrdiff_t(net.cell(kLevels, s) * w));
    for (int k = kLevels; k > levels_down_to; --k) {
        out[k - 1].assign((std::size_t(1) << (k - 1)) * w, 0.0);
        for (std::uint32_t c = 0; c < (1u << k); ++c) {
            double* p = out[k - 1].data() + Net::parent(k, c) * w;
            const double* q = out[k].data() + c * w;
            for (std::size_t x = 0; x < w; ++x) p[x] += q[x];
        }
    }
    return out;
}

// The exact cell tables T_k[c] (K floats each) of the Smax set's basis table, levels ≤ kmax.
std::vector<std::vector<float>> cell_tables(const Net& net, const DirectionSet& set, int kmax) {
    std::vector<double> y(std::size_t(kSmax) * K);
    tbb::parallel_for(std::uint32_t(0), kSmax, [&](std::uint32_t s) {
        double* o = y.data() + std::size_t(s) * K;
        sh_eval_k(K, double(set.dirs[3 * s]), double(set.dirs[3 * s + 1]),
                  double(set.dirs[3 * s + 2]), o);
        for (int q = 0; q < K; ++q) o[q] *= kPiD / kSmax;
    });
    const std::vector<std::vector<double>> sums = cell_sums(net, y.data(), K);
    std::vector<std::vector<float>> tables(std::size_t(kmax) + 1);
    for (int k = 0; k <= kmax; ++k) tables[k].assign(sums[k].begin(), sums[k].end());
    return tables;
}

struct Setting {
    int k0, kmax, ring;
    std::uint32_t rare = 0;  // a receiver with fewer visible (or blocked) rays at k0 …
    int boost = 0;           // … starts at level k0 + boost, every cell traced
};

struct RefineScratch {
    std::vector<std::uint8_t> traced, bit;  // per direction of the Smax set
    std::vector<std::uint32_t> touched, active, split, fresh;
    std::vector<std::uint8_t> out;
};

// One receiver's refinement (see the top). trace(indices, count, blocked) casts directions;
// leaf(k, cell, blocked) receives the final cells. Returns the rays.
template <class Trace, class Leaf>
std::uint64_t refine_receiver(const Net& net, const Setting& set, RefineScratch& st, Trace&& trace,
                              Leaf&& leaf) {
    if (st.traced.empty()) st.traced.assign(kSmax, 0), st.bit.assign(kSmax, 0);
    std::uint64_t rays = 0;
    auto cast = [&](const std::vector<std::uint32_t>& idx) {
        st.out.resize(idx.size());
        trace(idx.data(), idx.size(), st.out.data());
        for (std::size_t i = 0; i < idx.size(); ++i)
            st.traced[idx[i]] = 1, st.bit[idx[i]] = st.out[i], st.touched.push_back(idx[i]);
        rays += idx.size();
    };
    auto trace_prefix = [&](std::uint32_t from, std::uint32_t to) {
        st.fresh.clear();
        for (std::uint32_t s = from; s < to; ++s) st.fresh.push_back(s);
        if (!st.fresh.empty()) cast(st.fresh);
    };
    int k0 = set.k0;
    trace_prefix(0, 1u << k0);
    if (set.rare > 0) {
        std::uint32_t blocked = 0;
        for (std::uint32_t s = 0; s < (1u << k0); ++s) blocked += st.bit[s];
        if (std::min(blocked, (1u << k0) - blocked) < set.rare) {
            const int kb = std::min(set.kmax, k0 + set.boost);
            trace_prefix(1u << k0, 1u << kb);
            k0 = kb;
        }
    }
    st.active.resize(1u << k0);
    for (std::uint32_t c = 0; c < (1u << k0); ++c) st.active[c] = c;
    // The visibility of the finest traced cell covering cell (i, j) of level k.
    auto region = [&](int k, std::uint32_t i, std::uint32_t j) {
        for (int l = k;; --l) {
            const std::uint32_t s =
                net.rep[l][cell_id(l, i >> (bits_u(k) - bits_u(l)), j >> (bits_v(k) - bits_v(l)))];
            if (st.traced[s]) return st.bit[s];
        }
    };
    for (int k = k0; k <= set.kmax; ++k) {
        st.split.clear();
        const std::uint32_t nu = 1u << bits_u(k), nv = 1u << bits_v(k);
        for (const std::uint32_t c : st.active) {
            const std::uint8_t b = st.bit[net.rep[k][c]];
            const std::uint32_t i = c >> bits_v(k), j = c & (nv - 1);
            bool split = false;
            for (int di = -set.ring; di <= set.ring && !split && k < set.kmax; ++di) {
                const long ii = long(i) + di;
                if (ii < 0 || ii >= long(nu)) continue;  // u does not wrap; v (the azimuth) does
                for (int dj = -set.ring; dj <= set.ring && !split; ++dj)
                    split =
                        region(k, std::uint32_t(ii), std::uint32_t(long(j) + dj) & (nv - 1)) != b;
            }
            if (split)
                st.split.push_back(c);
            else
                leaf(k, c, b);
        }
        st.active.clear();
        st.fresh.clear();
        const bool along_u = bits_u(k + 1) > bits_u(k);
        for (const std::uint32_t c : st.split) {
            const std::uint32_t i = c >> bits_v(k), j = c & (nv - 1);
            for (std::uint32_t h = 0; h < 2; ++h) {
                const std::uint32_t child =
                    along_u ? cell_id(k + 1, 2 * i + h, j) : cell_id(k + 1, i, 2 * j + h);
                st.active.push_back(child);
                const std::uint32_t s = net.rep[k + 1][child];
                if (!st.traced[s]) st.fresh.push_back(s);
            }
        }
        if (!st.fresh.empty()) cast(st.fresh);
    }
    for (const std::uint32_t s : st.touched) st.traced[s] = 0;
    st.touched.clear();
    return rays;
}

// The band-limited light's luminance at a world direction: a 4096 × 2048 equirect table in
// (θ from +z, φ), bilinear (the replay's; the live part projects exactly).
struct LightTable {
    static constexpr int W = 4096, H = 2048;
    std::vector<float> f;
    explicit LightTable(const std::vector<double>& lum) : f(std::size_t(W) * H) {
        tbb::parallel_for(0, H, [&](int y) {
            double sh[K];
            for (int x = 0; x < W; ++x) {
                const double th = kPiD * y / (H - 1), ph = 2 * kPiD * x / W;
                sh_eval_k(K, std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th),
                          sh);
                double e = 0;
                for (int i = 0; i < K; ++i) e += sh[i] * lum[std::size_t(i)];
                f[std::size_t(y) * W + std::size_t(x)] = float(e);
            }
        });
    }
    double at(Vec3f d) const {
        const double th = std::acos(std::clamp(double(d.z), -1.0, 1.0));
        double ph = std::atan2(double(d.y), double(d.x));
        if (ph < 0) ph += 2 * kPiD;
        const double x = ph / (2 * kPiD) * W, y = th / kPiD * (H - 1);
        const int x0 = std::min(int(x), W - 1), y0 = std::min(int(y), H - 2);
        const double fx = x - x0, fy = y - y0;
        auto g = [&](int xi, int yi) {
            return double(f[std::size_t(yi) * W + std::size_t(xi % W)]);
        };
        return (1 - fy) * ((1 - fx) * g(x0, y0) + fx * g(x0 + 1, y0)) +
               fy * ((1 - fx) * g(x0, y0 + 1) + fx * g(x0 + 1, y0 + 1));
    }
};

struct Room {
    Mesh mesh;
    std::unique_ptr<Tracer> tracer;
    ShLight light;
    std::vector<double> lum, ref;  // the light's luminance coefficients; reference luminance
    Net net;
    DirectionSet set;
    double error(const std::vector<double>& y) const {
        return 100 * room_study::relative_rms(y, ref);
    }
};

void replay(const Room& r) {
    const std::size_t V = r.mesh.vertex_count();
    const LightTable table(r.lum);
    std::vector<std::uint8_t> blocked(V * kSmax);
    std::vector<float> f(V * kSmax);  // the light at each receiver's directions
    const auto start = Clock::now();
    tbb::parallel_for(std::size_t(0), V, [&](std::size_t v) {
        const Vec3f p = r.mesh.positions[v], n = r.mesh.normals[v];
        const LocalAxes ax = local_axes(n);
        std::vector<Vec3f> dirs(kSmax);
        for (std::uint32_t s = 0; s < kSmax; ++s) {
            const float* d = r.set.dirs.data() + 3 * std::size_t(s);
            dirs[s] = to_world(ax, Vec3f{d[0], d[1], d[2]});
            f[v * kSmax + s] = float(table.at(dirs[s]));
        }
        r.tracer->occluded(offset_ray_origin(p, n), dirs.data(), int(kSmax), 0.0f,
                           __builtin_huge_valf(), blocked.data() + v * kSmax);
    });
    std::printf("\nreplay: %zu receivers x %u directions traced in %.1f s\n\n", V, kSmax,
                std::chrono::duration<double>(Clock::now() - start).count());
    // Each receiver's cell sums of π/Smax·f.
    auto sums_of = [&](std::size_t v) {
        std::vector<double> w(kSmax);
        for (std::uint32_t s = 0; s < kSmax; ++s) w[s] = kPiD / kSmax * f[v * kSmax + s];
        return cell_sums(r.net, w.data(), 1);
    };
    std::printf("| plain S | Mrays | point-sampled %% | cell tables %% |\n|---:|---:|---:|---:|\n");
    for (int k = 8; k <= kLevels; ++k) {
        std::vector<double> point(V), cells(V);
        tbb::parallel_for(std::size_t(0), V, [&](std::size_t v) {
            const auto sums = sums_of(v);
            for (std::uint32_t s = 0; s < (1u << k); ++s) {
                if (blocked[v * kSmax + s]) continue;
                point[v] += kPiD / double(1u << k) * f[v * kSmax + s];
                cells[v] += sums[std::size_t(k)][r.net.cell(k, s)];
            }
        });
        std::printf("| %u | %.1f | %.3f | %.3f |\n", 1u << k, double(1u << k) * double(V) * 1e-6,
                    r.error(point), r.error(cells));
    }
    std::printf(
        "\n| k0 | kmax | ring | Mrays | point-sampled %% | cell tables %% |\n"
        "|---:|---:|---:|---:|---:|---:|\n");
    for (int k0 : {7, 8})
        for (int kmax : {12, 13, 14})
            for (int ring : {1, 2}) {
                std::vector<double> point(V), cells(V);
                std::vector<std::uint64_t> rays(V);
                tbb::parallel_for(std::size_t(0), V, [&](std::size_t v) {
                    thread_local RefineScratch st;
                    const auto sums = sums_of(v);
                    const std::uint8_t* bl = blocked.data() + v * kSmax;
                    rays[v] = refine_receiver(
                        r.net, Setting{k0, kmax, ring}, st,
                        [&](const std::uint32_t* idx, std::size_t n, std::uint8_t* out) {
                            for (std::size_t i = 0; i < n; ++i) out[i] = bl[idx[i]];
                        },
                        [&](int k, std::uint32_t c, std::uint8_t b) {
                            if (b) return;
                            cells[v] += sums[k][c];
                            point[v] += kPiD / double(1u << k) * f[v * kSmax + r.net.rep[k][c]];
                        });
                });
                double total = 0;
                for (const std::uint64_t x : rays) total += double(x);
                std::printf("| %d | %d | %d | %.2f | %.3f | %.3f |\n", k0, kmax, ring, total * 1e-6,
                            r.error(point), r.error(cells));
                std::fflush(stdout);
            }
}

struct Live {
    std::vector<float> world;  // V × K
    std::uint64_t rays = 0, leaves = 0;
    double wall = 0, table_s = 0, trace_s = 0, project_s = 0;  // trace, project: thread-seconds
};

Live live_bake(const Room& r, const Setting& cfg) {
    const std::size_t V = r.mesh.vertex_count();
    Live out;
    const auto t0 = Clock::now();
    const std::vector<std::vector<float>> T = cell_tables(r.net, r.set, cfg.kmax);
    const auto t1 = Clock::now();
    std::vector<float> local(V * K);
    out.world.resize(V * K);
    std::atomic<std::uint64_t> rays{0}, leaves{0};
    std::mutex mu;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, V, 64), [&](const auto& range) {
        RefineScratch st;
        std::vector<Vec3f> dirs;
        struct Leaf {
            int k;
            std::uint32_t c;
            std::uint8_t blocked;
        };
        std::vector<Leaf> ls;
        std::uint64_t n_rays = 0, n_leaves = 0;
        double trace_s = 0, project_s = 0;
        for (std::size_t v = range.begin(); v < range.end(); ++v) {
            const Vec3f n = r.mesh.normals[v];
            const LocalAxes ax = local_axes(n);
            const Vec3f o = offset_ray_origin(r.mesh.positions[v], n);
            ls.clear();
            n_rays += refine_receiver(
                r.net, cfg, st,
                [&](const std::uint32_t* idx, std::size_t count, std::uint8_t* blocked) {
                    const auto a = Clock::now();
                    dirs.resize(count);
                    for (std::size_t q = 0; q < count; ++q) {
                        const float* d = r.set.dirs.data() + 3 * std::size_t(idx[q]);
                        dirs[q] = to_world(ax, Vec3f{d[0], d[1], d[2]});
                    }
                    r.tracer->occluded(o, dirs.data(), int(count), 0.0f, __builtin_huge_valf(),
                                       blocked);
                    trace_s += std::chrono::duration<double>(Clock::now() - a).count();
                },
                [&](int k, std::uint32_t c, std::uint8_t b) {
                    ls.push_back({k, c, b});
                });
            const auto a = Clock::now();
            std::size_t n_blocked = 0;
            for (const Leaf& l : ls) n_blocked += l.blocked;
            const bool complement = 2 * n_blocked < ls.size();  // c_open − Σ blocked leaves
            float* row = local.data() + v * K;
            if (complement) std::copy(T[0].begin(), T[0].begin() + K, row);
            for (const Leaf& l : ls) {
                if (bool(l.blocked) != complement) continue;
                const float* t = T[std::size_t(l.k)].data() + std::size_t(l.c) * K;
                const float sign = complement ? -1.0f : 1.0f;
                for (int q = 0; q < K; ++q) row[q] += sign * t[q];
            }
            n_leaves += complement ? n_blocked : ls.size() - n_blocked;
            project_s += std::chrono::duration<double>(Clock::now() - a).count();
        }
        rays += n_rays, leaves += n_leaves;
        const std::lock_guard<std::mutex> lock(mu);
        out.trace_s += trace_s, out.project_s += project_s;
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, V, 256), [&](const auto& range) {
        detail::rotate_rows_to_world(r.mesh.normals.data() + range.begin(), range.size(), K, K,
                                     false, local.data() + range.begin() * K,
                                     out.world.data() + range.begin() * K);
    });
    out.wall = std::chrono::duration<double>(Clock::now() - t0).count();
    out.table_s = std::chrono::duration<double>(t1 - t0).count();
    out.rays = rays, out.leaves = leaves;
    return out;
}

struct Tail {
    double mean, p99, max;
    std::size_t worst;
};

Tail tail(const std::vector<double>& e) {
    std::vector<double> sorted = e;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0;
    for (const double x : e) mean += x / double(e.size());
    return {mean, sorted[e.size() * 99 / 100], sorted.back(),
            std::size_t(std::max_element(e.begin(), e.end()) - e.begin())};
}

void live(const Room& r, int reps) {
    BakeOptions o;
    o.K = K, o.seed = 7919, o.threads = 2, o.sampler = SamplerKind::sobol;
    o.direction_frame = DirectionFrame::local;
    o.samples = kSmax;
    const std::vector<float> cref =
        bake_with_tracer(r.mesh, o, bake_direction_set(o), *r.tracer).coeffs;
    const double c00_open = open_hemisphere_transfer(K, HemisphereDensity::cosine)[0];
    std::printf(
        "\nlive, K = %d, 2 threads, min wall of %d runs; true error against a local Sobol bake of "
        "%u (seed 7919); β: visible fraction c00/c00,open of the worst receiver (reference → "
        "got)\n\n"
        "| estimator | Mrays | wall s | of it: cell tables s | trace thread-s | project "
        "thread-s | luminance %% | true error: mean | p99 | max | worst β |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
        K, reps, kSmax);
    std::string worst_lists;  // printed after the table: each estimator's six worst receivers
    auto print = [&](const std::string& name, const std::vector<float>& w, double rays, double wall,
                     const std::string& split) {
        const std::vector<double> e = room_study::true_errors(w, cref, K);
        const Tail t = tail(e);
        std::vector<std::size_t> order(e.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::partial_sort(order.begin(), order.begin() + 6, order.end(),
                          [&](std::size_t a, std::size_t b) { return e[a] > e[b]; });
        worst_lists += fmt::format("\n{}: the six worst receivers\n", name);
        for (int q = 0; q < 6; ++q) {
            const std::size_t v = order[std::size_t(q)];
            const Vec3f p = r.mesh.positions[v], n = r.mesh.normals[v];
            worst_lists += fmt::format(
                "  {}: error {:.4f}, β {:.3f} → {:.3f}, at ({:.3f}, {:.3f}, {:.3f}), normal "
                "({:.2f}, {:.2f}, {:.2f})\n",
                v, e[v], double(cref[v * K]) / c00_open, double(w[v * K]) / c00_open, p.x, p.y, p.z,
                n.x, n.y, n.z);
        }
        std::printf("| %s | %.1f | %.3f | %s | %.3f %% | %.4f | %.4f | %.4f | %.3f → %.3f |\n",
                    name.c_str(), rays * 1e-6, wall, split.c_str(),
                    r.error(room_study::luminance(w, K, r.light)), t.mean, t.p99, t.max,
                    double(cref[t.worst * K]) / c00_open, double(w[t.worst * K]) / c00_open);
        std::fflush(stdout);
    };
    for (const std::uint32_t S : {2048u, 4096u, 8192u}) {
        o.seed = 1, o.samples = S;
        double best = 1e30;
        TransferSet t;
        for (int rep = 0; rep < reps; ++rep) {
            const auto a = Clock::now();
            t = bake_with_tracer(r.mesh, o, bake_direction_set(o), *r.tracer);
            best = std::min(best, std::chrono::duration<double>(Clock::now() - a).count());
        }
        print(fmt::format("plain local Sobol S = {}", S), t.coeffs, double(t.stats.rays_cast), best,
              "– | – | –");
    }
    const Setting settings[] = {{8, 12, 1}, {8, 12, 2},        {8, 13, 2},
                                {7, 13, 2}, {8, 12, 2, 16, 2}, {8, 13, 2, 16, 2}};
    for (const Setting& s : settings) {
        Live best;
        best.wall = 1e30;
        for (int rep = 0; rep < reps; ++rep) {
            Live l = live_bake(r, s);
            if (l.wall < best.wall) best = std::move(l);
        }
        const std::string name =
            fmt::format("refine k0 {} kmax {} ring {}{}", s.k0, s.kmax, s.ring,
                        s.rare ? fmt::format(", rare {} boost {}", s.rare, s.boost) : "");
        print(name, best.world, double(best.rays), best.wall,
              fmt::format("{:.3f} | {:.3f} | {:.3f}", best.table_s, best.trace_s, best.project_s));
    }
    std::printf("%s", worst_lists.c_str());
}

}  // namespace
}  // namespace shprt

int main(int argc, char** argv) {
    using namespace shprt;
    std::string cache = "/tmp/bench_local_directions_reference.bin";
    bool do_replay = false;
    int reps = 3;
    CLI::App app{"Edge refinement in the local set's cells (issue 39, bench/RESULTS.md)"};
    app.add_option("--reference-cache", cache,
                   "the reference luminance (bench_local_directions' cache)");
    app.add_flag("--replay", do_replay, "also the replay sweep on fully traced bits");
    app.add_option("--reps", reps, "runs per live setting, min wall time (default 3)");
    CLI11_PARSE(app, argc, argv);

    Room r;
    r.mesh = make_builtin("room");
    r.tracer = make_embree_tracer(r.mesh);
    r.light = room_study::light(K);
    r.lum = room_study::luminance_light(r.light);
    std::printf("bench_edge_refine: builtin:room (%zu vertices), K = %d, light: %s\nhost: %s\n",
                r.mesh.vertex_count(), K, room_study::kLightName, host_cpu().c_str());
    r.ref = room_study::reference_luminance(r.mesh, *r.tracer, r.light, K, 65536, 2, cache);
    r.net = make_net(1);
    r.set = make_local_direction_set(SamplerKind::sobol, 1, kSmax, HemisphereDensity::cosine);
    if (do_replay) replay(r);
    live(r, reps);
    return 0;
}
