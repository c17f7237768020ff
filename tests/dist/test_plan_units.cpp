// The work units of a distributed bake (dist/mpi_bake.hpp plan_units): they tile the range in
// order, follow guided self-scheduling (⌈remaining / 2P⌉, shrinking), respect the smallest and
// largest unit, and depend on their arguments only. No MPI runtime needed.
#include "shprt/core/error.hpp"
#include "shprt/dist/mpi_bake.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdlib>
#include <vector>

namespace shprt::dist {
namespace {

// The units tile [0, count) without a gap or an overlap, in order.
void expect_tiles(const std::vector<WorkUnit>& units, std::size_t count) {
    std::size_t next = 0;
    for (const WorkUnit& u : units) {
        EXPECT_EQ(u.first, next);
        EXPECT_GE(u.count, 1u);
        next = u.first + u.count;
    }
    EXPECT_EQ(next, count);
}

TEST(PlanUnits, TileTheRangeWithShrinkingGuidedUnits) {
    const std::vector<WorkUnit> units = plan_units(10000, 4, 100, 100000);
    expect_tiles(units, 10000);
    // The first unit is a 1/(2P) share, then each is ⌈remaining / 8⌉ until the smallest unit.
    ASSERT_GE(units.size(), 3u);
    EXPECT_EQ(units[0].count, 1250u);
    EXPECT_EQ(units[1].count, (10000u - 1250u + 7u) / 8u);
    for (std::size_t i = 1; i < units.size(); ++i) EXPECT_LE(units[i].count, units[i - 1].count);
    for (std::size_t i = 0; i + 1 < units.size(); ++i) EXPECT_GE(units[i].count, 100u);
    // Few units while much is left: far fewer than count / min_unit.
    EXPECT_LT(units.size(), 40u);
}

TEST(PlanUnits, RespectTheLargestUnitAndSmallRanges) {
    const std::vector<WorkUnit> capped = plan_units(1000000, 2, 10, 5000);
    expect_tiles(capped, 1000000);
    for (const WorkUnit& u : capped) EXPECT_LE(u.count, 5000u);

    // Fewer receivers than the smallest unit: one unit of all of them.
    const std::vector<WorkUnit> one = plan_units(37, 8, 256, 1 << 20);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0], (WorkUnit{0, 37}));
    EXPECT_TRUE(plan_units(0, 3, 1, 1).empty());

    // One rank: halves of what remains.
    const std::vector<WorkUnit> single = plan_units(64, 1, 1, 64);
    expect_tiles(single, 64);
    EXPECT_EQ(single[0].count, 32u);
    EXPECT_EQ(single[1].count, 16u);
}

TEST(PlanUnits, DependOnTheirArgumentsOnly) {
    EXPECT_EQ(plan_units(123457, 7, 64, 9000), plan_units(123457, 7, 64, 9000));
    EXPECT_NE(plan_units(123457, 7, 64, 9000), plan_units(123457, 6, 64, 9000));
}

TEST(PlanUnits, RefuseNonsense) {
    EXPECT_THROW(plan_units(10, 0, 1, 1), Error);
    EXPECT_THROW(plan_units(10, 2, 0, 1), Error);
    EXPECT_THROW(plan_units(10, 2, 1, 0), Error);
}

TEST(LaunchedByMpi, ReadsTheLaunchersEnvironment) {
    // ctest does not run this binary under a launcher; Open MPI's and PMI's variables say one.
    ASSERT_FALSE(launched_by_mpi());
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_RANK", "PMIX_RANK"}) {
        ::setenv(name, "4", 1);
        EXPECT_TRUE(launched_by_mpi()) << name;
        ::unsetenv(name);
        EXPECT_FALSE(launched_by_mpi()) << name;
    }
}

}  // namespace
}  // namespace shprt::dist
