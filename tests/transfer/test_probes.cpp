// Interpolation of transfer probes (transfer/probes.hpp): exact for a field linear in position,
// invalid probes skipped, points outside clamped, the nearest valid probe when a cell has none.
#include "shprt/core/error.hpp"
#include "shprt/transfer/probes.hpp"

#include <gtest/gtest.h>

namespace shprt {
namespace {

// A 3×2×4 grid of K = 4, one channel, whose element i of probe at position q is i + q·(1, 2, 3).
ProbeGrid linear_grid() {
    ProbeGrid g;
    g.origin = {-1, 0, 2};
    g.spacing = {0.5f, 2, 1};
    g.counts = {3, 2, 4};
    g.K = 2;
    g.matrices.resize(g.count() * 4);
    g.valid.assign(g.count(), 1);
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) {
                const Vec3f q = g.position(x, y, z);
                float* m = g.matrices.data() + g.index(x, y, z) * 4;
                for (int i = 0; i < 4; ++i) m[i] = float(i) + q.x + 2 * q.y + 3 * q.z;
            }
    return g;
}

float field(int i, Vec3f q) { return float(i) + q.x + 2 * q.y + 3 * q.z; }

TEST(Probes, TrilinearIsExactForALinearField) {
    const ProbeGrid g = linear_grid();
    g.validate();
    for (const Vec3f p : {Vec3f{-0.8f, 0.3f, 2.1f}, Vec3f{-0.25f, 1.9f, 4.5f}, Vec3f{0, 2, 5}}) {
        const ProbeSample s = sample_probes(g, p);
        EXPECT_FALSE(s.clamped || s.fallback || s.no_valid);
        for (int i = 0; i < 4; ++i) EXPECT_NEAR(s.matrix[i], field(i, p), 1e-4f);
    }
}

TEST(Probes, InvalidProbesAreSkippedAndTheRestRenormalised) {
    ProbeGrid g = linear_grid();
    // Make probe (1, 0, 0) invalid with a poisoned matrix; a point in its cell must not see it.
    const std::size_t bad = g.index(1, 0, 0);
    g.valid[bad] = 0;
    for (int i = 0; i < 4; ++i) g.matrices[bad * 4 + i] = 1e6f;
    const ProbeSample s = sample_probes(g, {-0.6f, 0.5f, 2.5f});
    EXPECT_FALSE(s.fallback);
    for (int i = 0; i < 4; ++i) {
        EXPECT_LT(s.matrix[i], 100.0f);
        EXPECT_GT(s.matrix[i], 0.0f);
    }
    // At the invalid probe's own position the other probes of its cells carry it.
    const ProbeSample at = sample_probes(g, g.position(1, 0, 0));
    EXPECT_LT(at.matrix[0], 100.0f);
}

TEST(Probes, OutsidePointsAreClampedAndAllInvalidCellsFallBack) {
    ProbeGrid g = linear_grid();
    const ProbeSample out = sample_probes(g, {-5, 1, 3});
    EXPECT_TRUE(out.clamped);
    EXPECT_NEAR(out.matrix[0], field(0, {-1, 1, 3}), 1e-4f);

    // Every probe of the cell at z = 2..3 invalid: the nearest valid one stands in.
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int z = 2; z < 4; ++z) g.valid[g.index(x, y, z)] = 0;
    const ProbeSample fb = sample_probes(g, {-1, 0, 4.9f});
    EXPECT_TRUE(fb.fallback);
    EXPECT_NEAR(fb.matrix[0], field(0, g.position(0, 0, 1)), 1e-4f);

    std::fill(g.valid.begin(), g.valid.end(), std::uint8_t{0});
    const ProbeSample none = sample_probes(g, {0, 0, 3});
    EXPECT_TRUE(none.no_valid);
    EXPECT_EQ(none.matrix[0], 0.0f);
}

TEST(Probes, ValidateNamesWhatIsWrong) {
    ProbeGrid g = linear_grid();
    g.valid.pop_back();
    EXPECT_THROW(g.validate(), Error);
    g = linear_grid();
    g.spacing.y = 0;
    EXPECT_THROW(g.validate(), Error);
    g = linear_grid();
    g.channels = 2;
    EXPECT_THROW(g.validate(), Error);
}

}  // namespace
}  // namespace shprt
