// The estimate stage of the error-bounded bake (BakeOptions::target_error, docs/sampling.md
// "Error-bounded bakes"): weight → trace → project → estimate, repeated on the new segment of the
// nested set for the receivers whose estimated error is still over the target.
//
// Per chunk of the grid (bake_cpu.cpp), with the set of max_samples directions and its basis
// table Y (the set's weights are those of the whole set, e.g. π/Smax):
//   pass 0   every row traces directions [0, S0) and projects the halves [0, S0/2) and
//            [S0/2, S0) as two GEMMs over the chunk's rows: A = G0 + G1;
//   pass k   the rows still over the target trace [S, 2S) only and project it, G = W_seg·Y[S, 2S)
//            (one GEMM per block of rows of the same count), A += G;
//   estimate ĉ_S = (Smax/S)·A_S, and err = ‖ĉ_2S − ĉ_S‖ / ‖c_open‖ = (Smax/2S)·‖G − A_S‖ /
//            ‖c_open‖ (pass 0: (Smax/S0)·‖G1 − G0‖ / ‖c_open‖); a row that is still exactly zero
//            (every ray blocked) gets at least the error one visible ray would make,
//            w_max·(Smax/S)·√(KL/4π)/‖c_open‖: its halves agree, but only because both missed.
// A local set's estimates ĉ_S are corrected by the open part (stages.hpp, OpenControl) with the
// prefix's own δ_S before they are compared; then an open row (every ray so far visible) is
// exact whatever S, and gets the same floor as a closed one: a blocker that all S rays missed
// would change it by about one ray's worth.
// Every row of the chunk is baked, also those outside the bake's range: which rows share a GEMM
// (and so a row's last bits: bake.hpp, "Determinism") then depends on the chunk's receivers only,
// never on the range, the shard or the thread that runs it.
#pragma once

#include "bake/stages.hpp"
#include "shprt/bake/receivers.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace shprt {
class Tracer;
}

namespace shprt::detail {

class BakeProgress;

struct ErrorBound {
    const DirectionTable* table = nullptr;  // the whole nested set (max_samples directions)
    const float* Y = nullptr;               // its basis table, Smax × KL
    int KL = 0;                             // columns of Y
    std::size_t first_samples = 0, max_samples = 0;  // S0 and Smax, powers of two
    double target = 0;                               // E
    double open_norm = 1;                            // open_transfer_norm (bake.hpp)
    bool shadowed = true;                            // rays are cast
    // A local set: the open part exactly (stages.hpp, OpenControl) for the prefixes S0/2, S0,
    // 2·S0, …, Smax (controls[i] for (S0/2)·2^i); empty for a sphere set.
    std::vector<OpenControl> controls;
    // A set whose directions all weigh `weight` (a local set's; 0 for a sphere set): its rows are
    // projected by sums (stages.hpp, project_visibility_rows) over the segments [0, S0/2),
    // [S0/2, S0), [S0, 2·S0), …, [Smax/2, Smax), whose column sums of Y are sums[0], sums[1], ….
    float weight = 0.0f;
    std::vector<std::vector<float>> sums;
    // G (m × KL) = W·Y over the segment [a, b) of the set for `m` rows of W (stride `stride`,
    // from the segment's first direction): by sums where the weights allow, else one SGEMM.
    void project(const float* W, std::size_t m, std::size_t stride, std::size_t a, std::size_t b,
                 float* G) const;
};
// The controls of ErrorBound for a local table and its basis table Y (Smax × KL).
std::vector<OpenControl> make_open_controls(const DirectionTable& table, const float* Y, int KL,
                                            std::size_t first_samples);
// The bound of `options` (target_error > 0) over the nested set's `table` (Smax directions, the
// error-bounded bake's: make_direction_table with kTargetFirstSamples) and its basis table Y
// (Smax × KL), which it points to; the open part's controls for a local set (with
// options.open_control). `shadowed`: rays are cast.
ErrorBound make_error_bound(const BakeOptions& options, const DirectionTable& table, const float* Y,
                            int KL, bool shadowed);

// Three guards against an estimate that agrees by chance (docs/sampling.md, "When the estimate
// is fooled"; chosen by measurement: bench/RESULTS.md, "No receiver over 2E" and "… at K = 16"):
//  - rare outcomes: a receiver with n < kRareRays visible rays of b (or, with the open part
//    exact, n blocked ones) gets an estimate of at least (kRareFloor + √n) rays' worth at b
//    samples — a small opening or blocker that both halves met, or missed, alike;
//  - two successive estimates: a receiver stops at b only if its estimate at b/2 was at most
//    kPreviousFactor·E as well (so every receiver takes at least 2·S0 samples);
//  - a visibility edge: a receiver that saw v of b rays visible and h blocked gets an estimate of
//    at least kEdgeFloor·√(v·h)/b · b^(−3/4) rays' worth over the first two bands — the error a
//    scrambled net makes at an edge falls as b^(−3/4), not faster, and few coefficients (K = 16)
//    let two halves agree by chance that often.
inline constexpr std::uint32_t kRareRays = 16;
inline constexpr double kRareFloor = 1.5;
inline constexpr double kPreviousFactor = 2.0;
inline constexpr double kEdgeFloor = 3.5;

// What a chunk's rows have so far, `height` rows of each: A, the sum over the row's prefix with
// the whole set's weights (KL floats), the prefix (0: not baked yet) and the estimated error. A
// bake session keeps them across calls (BakeSession::bake_to), so that a later call with a larger
// cap traces only the new segments; a one-off bake keeps them in its scratch.
struct BoundRows {
    float* acc = nullptr;
    std::uint32_t* samples = nullptr;
    float* error = nullptr;
    std::uint32_t* visible = nullptr;  // rays that reached the sky so far
    std::uint32_t* blocked = nullptr;  // rays that hit something so far
    std::uint8_t* more = nullptr;      // 1: the last estimate asked for more samples
    // Whether row j has more to trace in a pass to prefixes of at most `cap`: never baked, or
    // stopped over the target at a smaller cap.
    bool goes_on(std::size_t j, std::size_t cap) const {
        return samples[j] == 0 || (more[j] != 0 && samples[j] < cap);
    }
};

// One worker's buffers, reused across chunks.
struct ErrorBoundScratch {
    std::vector<float> w;      // W of a block of rows over one segment
    std::vector<float> g, g0;  // the block's segment sums (pass 0: its two halves)
    std::vector<float> acc;    // the chunk's rows' A when no session keeps them (height × KL)
    std::vector<std::uint32_t> samples;           // … their prefixes
    std::vector<float> error;                     // … their estimated errors
    std::vector<std::uint32_t> visible, blocked;  // … their rays' outcomes
    std::vector<std::uint8_t> more;               // … whether they asked for more
    std::vector<std::uint32_t> active;            // rows still refining
    std::vector<std::uint32_t> twin;              // the chunk's twins (stages.hpp: find_twins)
    std::vector<float> out;                       // the chunk's rows ĉ (height × KL)
    TraceScratch trace;
    double trace_seconds = 0, project_seconds = 0;  // CPU time (this worker)
    // The scratch's own rows for `height` receivers, zeroed (nothing baked yet).
    BoundRows fresh_rows(std::size_t height, int KL);
};

// Bakes receivers [first, first + height) of `receivers` (the whole chunk: see above) to the
// bound, with prefixes of at most `cap` (≤ max_samples; a power of two ≥ first_samples): rows
// that `rows` says were baked before (to an earlier, smaller cap) and whose estimate is still
// over the target go on from their sums, tracing only the new segments; a fresh row starts at
// pass 0. The result is the same bits as one call with this cap. Afterwards sc.out holds the
// rows ĉ in the table's frame (KL each) and `rows` their sums, prefixes and estimated errors.
// Returns the rays cast (also added to `progress`); stops early, with rows unfinished, once
// progress.poll() says stop. The chunk's twins (stages.hpp, find_twins) are not traced: each
// takes its twin's sums, prefix and estimate; with `shared`, a row whose twins lie in other chunks
// takes its visibility from there (stages.hpp, SharedVisibility).
std::uint64_t bake_chunk_to_error(const ErrorBound& bound, std::size_t cap, const Tracer* tracer,
                                  const Receivers& receivers, std::size_t first, std::size_t height,
                                  BoundRows rows, ErrorBoundScratch& sc, BakeProgress& progress,
                                  SharedVisibility* shared = nullptr);

// A backend that bakes segments of the nested set for a list of rows (the GPU bake's device
// pipeline): rows[i] of the `m` given (indices into the block baked) over directions [a, b),
// unnormalised with the whole set's weights (G = W_seg·Y[a, b), m × KL, into G). With `halves`
// (pass 0, a = 0), the sums over the two halves instead: [a, (a+b)/2) into halves, the rest into
// G. Returns the rays it cast.
using SegmentBaker =
    std::function<std::uint64_t(const std::uint32_t* rows, std::size_t m, std::size_t a,
                                std::size_t b, float* G, float* halves)>;

// bake_chunk_to_error over such a backend, for `height` rows to max_samples: the same passes,
// estimates and guards, one segment of every row still over the target at a time (pass 0: its
// two halves). The rays' outcomes are read from each segment's first coefficient (a local set's
// weights are all equal and y₀₀ is constant), so a shadowed bake needs a local set (else
// Error(unsupported)). Afterwards sc.out holds the rows ĉ in the frame and `rows` their sums,
// prefixes and estimates. Rows agree with bake_chunk_to_error's up to the GEMMs' summation order.
// It bakes twins like any other row (the device kernels have no twins yet).
std::uint64_t bake_segments_to_error(const ErrorBound& bound, std::size_t height,
                                     const SegmentBaker& segment, BoundRows rows,
                                     ErrorBoundScratch& sc, BakeProgress& progress);

}  // namespace shprt::detail
