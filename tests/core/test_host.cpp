// core/host.hpp: the CPU line of benchmark reports, from /proc/cpuinfo's text.
#include "shprt/core/host.hpp"

#include <gtest/gtest.h>

namespace shprt {
namespace {

TEST(Host, DescribesTheFirstProcessorsModelFamilyAndCount) {
    const char* const cpuinfo =
        "processor\t: 0\nvendor_id\t: AuthenticAMD\ncpu family\t: 26\nmodel\t\t: 2\n"
        "model name\t: AMD EPYC\nstepping\t: 1\n\n"
        "processor\t: 1\ncpu family\t: 25\nmodel\t\t: 1\nmodel name\t: Other CPU\n";
    EXPECT_EQ(describe_cpu(cpuinfo, 2), "AMD EPYC (family 26, model 2), 2 CPUs");
    EXPECT_EQ(describe_cpu(cpuinfo, 1), "AMD EPYC (family 26, model 2), 1 CPU");
    EXPECT_EQ(describe_cpu(cpuinfo, 0), "AMD EPYC (family 26, model 2)");
}

TEST(Host, LeavesOutWhatTheTextLacks) {
    // "model name" is not "model"; an Arm kernel has neither name nor family.
    EXPECT_EQ(describe_cpu("model name\t: Some CPU\n", 4), "Some CPU, 4 CPUs");
    EXPECT_EQ(describe_cpu("processor\t: 0\nBogoMIPS\t: 50.00\nCPU part\t: 0xd0c\n", 8),
              "unknown CPU, 8 CPUs");
    EXPECT_EQ(describe_cpu("", 0), "unknown CPU");
}

TEST(Host, ThisMachineHasACpuLine) {
    const std::string line = host_cpu();
    EXPECT_FALSE(line.empty());
    EXPECT_NE(line.find("CPU"), std::string::npos) << line;  // at least the count
}

}  // namespace
}  // namespace shprt
