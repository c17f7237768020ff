// Bake-sweep stage of the paper study: the basis sizes of the table and, per size, the bakes of
// the paper's method (options.sampler, on the CPU and/or the GPU) and of the improved method
// (kImprovedSampler, same S).
#pragma once

#include "paper/paper_study.hpp"
#include "paper/stage_log.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>
#include <vector>

namespace shprt::paper {

struct Devices {
    bool cpu = true, gpu = false;
    std::string gpu_description;  // the GPU's name, or "no GPU (why)"
};

// The devices options.device asks for: cpu; cuda; both; auto = the CPU, plus the GPU when there
// is one. Throws Error(unsupported) for cuda or both without a usable GPU.
Devices choose_devices(const Options& options);

// The K of the table: the paper's 32, 48, 64, 128, 256, plus the full bands 16, 25, … 1024 when
// `extended`; sorted, without repeats.
std::vector<int> table_sizes(bool extended);

// The study's bake at K on `device`: options.samples, sampler, seed and threads.
BakeOptions bake_options(const Options& options, int K, Device device);

struct RowBakes {
    TransferSet paper;     // the paper's method: the CPU bake, or the GPU's without the CPU
    TransferSet improved;  // kImprovedSampler, same S: on the CPU, or the GPU without the CPU
};

// Bakes row.K with the paper's method on each device asked for, then with the improved method;
// records their statistics in row.cpu, row.gpu and row.improved.
RowBakes bake_row(const Mesh& mesh, const Options& options, const Devices& devices, KRow& row,
                  const StageLog& log);

}  // namespace shprt::paper
