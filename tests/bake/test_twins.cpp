// Twins (src/bake/stages.hpp, find_twins): receivers with the same position and normal cast the
// same rays, so a chunk traces one of them and copies its row to the others. Loaders that split
// vertices at seams give real assets many; here leaky_room (overlapping panels, parts through the
// floor) is split the way a Collada or OBJ file arrives, every triangle corner its own vertex.
#include "twins.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <utility>
#include <vector>

namespace shprt {
namespace {

// Every triangle corner its own vertex, with the corner's position, normal and albedo.
Mesh split_corners(const Mesh& welded) {
    Mesh m;
    m.source = welded.source + ", every corner its own vertex";
    for (const auto& tri : welded.triangles) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const std::uint32_t v : tri) {
            m.positions.push_back(welded.positions[v]);
            m.normals.push_back(welded.normals[v]);
            m.albedo.push_back(welded.albedo[v]);
        }
        m.triangles.push_back({base, base + 1, base + 2});
    }
    return m;
}

// The largest difference between a split bake's rows and its welded source's, over the largest
// coefficient: the same rays give the same sums, up to the rounding of GEMMs over other chunks
// (about 1e-6 here).
double worst_difference(const TransferSet& split, const TransferSet& welded, const Mesh& source) {
    double diff = 0, scale = 0;
    std::size_t corner = 0;
    for (const auto& tri : source.triangles)
        for (const std::uint32_t v : tri) {
            const float *a = split.receiver(corner++), *b = welded.receiver(v);
            for (std::size_t i = 0; i < split.layout.floats_per_receiver(); ++i) {
                diff = std::max(diff, std::fabs(double(a[i]) - double(b[i])));
                scale = std::max(scale, std::fabs(double(b[i])));
            }
        }
    return diff / scale;
}

// Bakes of receivers [first, first + count) of `mesh` (shards) give `whole`'s rows, byte for
// byte, and so do one and two threads (`one` and `two` are the whole mesh's bakes).
using Range = std::pair<std::size_t, std::size_t>;
void expect_the_same_bytes(const Mesh& mesh, const BakeOptions& options, const TransferSet& one,
                           const TransferSet& two, std::initializer_list<Range> ranges) {
    ASSERT_EQ(one.coeffs.size(), two.coeffs.size());
    EXPECT_EQ(std::memcmp(one.coeffs.data(), two.coeffs.data(), one.coeffs.size() * sizeof(float)),
              0)
        << "one and two threads";
    const std::size_t row = one.layout.floats_per_receiver();
    for (const auto& [first, count] : ranges) {
        const TransferSet part = bake(mesh, vertex_receivers(mesh).range(first, count), options);
        EXPECT_EQ(std::memcmp(part.coeffs.data(), one.coeffs.data() + first * row,
                              count * row * sizeof(float)),
                  0)
            << "receivers [" << first << ", " << first + count << ")";
    }
}

TEST(Twins, ASplitMeshCastsTheRaysOfItsDistinctVerticesAndGetsTheirRows) {
    const Mesh welded = make_builtin("leaky_room");
    const Mesh split = split_corners(welded);
    const std::size_t V = split.vertex_count();
    BakeOptions o;
    o.K = 16;
    o.samples = 256;
    o.threads = 2;
    const TransferSet a = bake(split, o), b = bake(welded, o);
    const std::vector<bool> copied = test::twin_vertices(split, o.samples);
    const auto traced = std::uint64_t(std::count(copied.begin(), copied.end(), false));
    std::printf("[ twins ] %s: %zu vertices, %llu traced (%zu welded), %llu rays\n",
                split.source.c_str(), V, (unsigned long long)traced, welded.vertex_count(),
                (unsigned long long)a.stats.rays_cast);
    EXPECT_EQ(a.stats.rays_cast, traced * o.samples) << "only the first of each chunk's twins";
    EXPECT_LT(traced, V * 2 / 3) << "most corners have a twin in their chunk";
    EXPECT_LE(worst_difference(a, b, welded), 1e-5);
}

// Twins in other chunks share the visibility whichever of them needs it first traces
// (SharedVisibility): the same bytes for any thread count, and a range (a shard) gives the whole
// bake's rows, its twins' firsts in other chunks or outside it.
TEST(Twins, TheSameBytesForAnyThreadCountAndRange) {
    const Mesh split = split_corners(make_builtin("leaky_room"));
    BakeOptions one;
    one.K = 16;
    one.samples = 256;
    one.threads = 1;
    BakeOptions two = one;
    two.threads = 2;
    expect_the_same_bytes(split, two, bake(split, one), bake(split, two),
                          {{0, 700}, {700, 777}, {1477, 647}, {1000, 3}});
}

// A real asset: Assimp's Collada duck (assimp-testmodels, scripts/setup), whose loader gives every
// triangle corner its own vertex: 8 500 vertices, 2 290 distinct positions and normals.
TEST(Twins, TheColladaDuckCastsTheRaysOfItsDistinctVerticesOnly) {
    const Mesh duck = load_scene("/usr/share/assimp/models/Collada/duck.dae");
    const std::size_t V = duck.vertex_count();
    std::vector<std::uint32_t> first;
    detail::find_twins(duck.positions.data(), duck.normals.data(), V, first);
    std::size_t distinct = 0;
    for (std::size_t v = 0; v < V; ++v) distinct += first[v] == v ? 1 : 0;
    EXPECT_LT(distinct * 3, V) << "the duck's loader splits vertices at its seams";
    BakeOptions o;
    o.K = 16;
    o.samples = 128;
    o.threads = 2;
    const TransferSet t = bake(duck, o);
    EXPECT_EQ(t.stats.rays_cast, std::uint64_t(distinct) * o.samples);
    const std::size_t row = t.layout.floats_per_receiver();
    double worst = 0, scale = 0;
    for (std::size_t v = 0; v < V; ++v)
        for (std::size_t i = 0; i < row; ++i) {
            worst = std::max(worst, std::fabs(double(t.coeffs[v * row + i]) -
                                              double(t.coeffs[first[v] * row + i])));
            scale = std::max(scale, std::fabs(double(t.coeffs[v * row + i])));
        }
    EXPECT_LE(worst, 1e-5 * scale) << "twins' rows differ only by where the GEMM put them";
}

// The rays an error-bounded bake with a local set casts when each (position, normal) traces
// once, as far as the longest prefix any of its receivers took.
std::uint64_t rays_of_distinct_receivers(const Mesh& mesh, const TransferSet& t) {
    std::vector<std::uint32_t> first;
    detail::find_twins(mesh.positions.data(), mesh.normals.data(), mesh.vertex_count(), first);
    std::vector<std::uint32_t> longest(mesh.vertex_count(), 0);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        longest[first[v]] = std::max(longest[first[v]], t.receiver_samples[v]);
    std::uint64_t rays = 0;
    for (const std::uint32_t s : longest) rays += s;
    return rays;
}

// An error-bounded bake traces each segment of a (position, normal) once, also when its twins
// lie in other chunks (SharedVisibility): the duck casts only its distinct receivers' rays, and
// its bytes and rays are the same for one and two threads and for a shard.
TEST(Twins, AnErrorBoundedBakeOfTheColladaDuckTracesEachDistinctReceiverOnce) {
    const Mesh duck = load_scene("/usr/share/assimp/models/Collada/duck.dae");
    BakeOptions one;
    one.K = 16;
    one.target_error = 0.03;
    one.max_samples = 4096;
    one.threads = 1;
    BakeOptions two = one;
    two.threads = 2;
    const TransferSet a = bake(duck, one), b = bake(duck, two);
    ASSERT_EQ(a.receiver_samples.size(), duck.vertex_count());
    std::uint64_t every_receiver = 0;
    for (const std::uint32_t s : a.receiver_samples) every_receiver += s;
    std::printf("[ twins ] duck, E = %.2f: %llu rays, %llu for every receiver\n", one.target_error,
                (unsigned long long)a.stats.rays_cast, (unsigned long long)every_receiver);
    EXPECT_EQ(a.stats.rays_cast, rays_of_distinct_receivers(duck, a));
    EXPECT_EQ(b.stats.rays_cast, a.stats.rays_cast);
    EXPECT_EQ(a.receiver_samples, b.receiver_samples);
    // A shard shares visibility only among its own chunks; a single receiver traces its own
    // rays (its chunk's twins in other chunks are outside the shard): the same bytes.
    expect_the_same_bytes(
        duck, two, a, b,
        {{0, 4000}, {4000, 4500}, {3999, 2}, {17, 1}, {1234, 1}, {5000, 1}, {8499, 1}});
}

TEST(Twins, AnErrorBoundedBakeCopiesTheTwinsStateAndStopsWhereTheWeldedBakeStops) {
    const Mesh welded = make_builtin("leaky_room");
    const Mesh split = split_corners(welded);
    BakeOptions o;
    o.K = 16;
    o.target_error = 0.03;
    o.max_samples = 4096;
    o.threads = 2;
    const TransferSet a = bake(split, o), b = bake(welded, o);
    ASSERT_EQ(a.receiver_samples.size(), split.vertex_count());
    std::size_t corner = 0, differ = 0;
    std::uint64_t welded_rays = 0;  // the split mesh's corners at their welded vertex's prefix
    for (const auto& tri : welded.triangles)
        for (const std::uint32_t v : tri) {
            differ += a.receiver_samples[corner] != b.receiver_samples[v] ? 1 : 0;
            welded_rays += b.receiver_samples[v];
            ++corner;
        }
    EXPECT_EQ(differ, 0u) << "each corner stops at its welded vertex's prefix";
    EXPECT_LT(a.stats.rays_cast, welded_rays * 2 / 3) << "twins are not traced";
    EXPECT_EQ(a.stats.rays_cast, rays_of_distinct_receivers(split, a));
    EXPECT_LE(worst_difference(a, b, welded), 1e-5);
}

}  // namespace
}  // namespace shprt
