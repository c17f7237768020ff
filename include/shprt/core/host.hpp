// The CPU a measurement ran on, for the first line of every benchmark report. The hosts of one
// machine kind differ between sessions (bench/RESULTS.md measured the same frame at half the CPU
// time on an AMD family 26 host as on the one before), so numbers are read against it.
#pragma once

#include <string>
#include <string_view>

namespace shprt {

// "MODEL (family F, model M)" from the text of /proc/cpuinfo (its first processor's "model name",
// "cpu family" and "model" fields), then ", N CPUs"; the fields it lacks are left out, and with
// none of them it says "unknown CPU".
std::string describe_cpu(std::string_view cpuinfo, unsigned cpus);

// describe_cpu of this machine's /proc/cpuinfo and std::thread::hardware_concurrency.
std::string host_cpu();

// Whether this CPU runs AVX2: the switch for code compiled with a target("avx2") attribute beside
// a portable path (the same answers from both). Checked once.
bool cpu_has_avx2();
// The same for AVX-512F.
bool cpu_has_avx512f();

// This process's command line as typed (from /proc/self/cmdline), each argument that needs it in
// single quotes, for a file's metadata; empty where unavailable.
std::string process_command_line();

}  // namespace shprt
