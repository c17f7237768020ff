// The per-chunk stages of the CPU bake, one function each: weight → trace → project, then the
// sink (sink.hpp). Separate so that later transfer kinds plug in at the right one: closest hits
// for bounces beside trace, Yᵀ·diag(w)·Y for glossy matrices beside project.
//
// For a receiver with position p and unit normal n, and the shared direction set {w_s, weight_s}:
//   weight   W[s] = max(0, n·w_s) · weight_s                 (the unoccluded transfer samples)
//   trace    W[s] = 0 where the ray from offset_ray_origin(p, n) along w_s hits the occluders;
//            only directions with W[s] ≠ 0 are cast (below the horizon nothing is)
//   project  C[count×K] = W[count×S] · Y[S×K]                (one single-threaded SGEMM)
// These are exactly the operations of transfer_sample() (transfer_sample.hpp), which the GPU
// kernel runs, so the two backends' W agree bit for bit where their tracers agree.
//
// With a local set (DirectionFrame::local, docs/sampling.md) the set lives in the receiver's
// tangent frame (local_frame.hpp) and the weight already holds the cosine (or the hemisphere's
// constant density): weight copies it, trace casts every direction turned into the frame, project
// gives the coefficients in the frame over full bands, and
//   rotate   c = D(R)·c' per receiver (vectors), M = D·M'·Dᵀ (glossy), truncated to K.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/sh/sampler.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace shprt {
class Tracer;
struct BakeOptions;
}  // namespace shprt

namespace shprt::detail {

// The direction set as structure-of-arrays (the weight loop vectorises) and as Vec3f (the form
// the tracer takes), in the set's order; and the order trace_row casts the rays in:
// trace_order = coherent_order(set) (sh/direction_order.hpp), trace_dirs[i] = dirs[trace_order[i]].
// The set's order is what the nested prefixes, the basis table and the rows keep; tracing in the
// coherent order is faster (issue 39) and changes nothing else: every answer goes to the
// direction's own index.
// A local table (frame == local) holds the set in the tangent frame; its trace order is the
// coherent order of the local directions, which a rotation keeps coherent.
struct DirectionTable {
    DirectionFrame frame = DirectionFrame::sphere;
    std::vector<float> x, y, z, weight;
    std::vector<Vec3f> dirs;
    std::vector<std::uint32_t> trace_order;
    std::vector<Vec3f> trace_dirs;
    std::size_t size() const { return weight.size(); }
    std::size_t bytes() const { return size() * kBytesPerDirection; }
    static constexpr std::size_t kBytesPerDirection =
        4 * sizeof(float) + 2 * sizeof(Vec3f) + sizeof(std::uint32_t);
};
// first_prefix > 0 (the error-bounded bake): the trace order is coherent within each new
// segment of the nested prefixes [0, P), [P, 2P), … instead (coherent_order(set, P)), so that a
// segment is traced on its own.
DirectionTable make_direction_table(const DirectionSet& directions,
                                    DirectionFrame frame = DirectionFrame::sphere,
                                    std::size_t first_prefix = 0);

// Directions [begin, end) of a table: a segment of nested prefixes (the error-bounded bake).
struct DirectionRange {
    std::size_t begin = 0, end = 0;
};

// The basis size a bake projects onto: K, or for a local set the full bands that hold K (a
// partial last band is rotated whole, then truncated: sh/rotation.hpp).
int projected_coeffs(const BakeOptions& options);

// One worker's buffers for trace_row, reused across receivers.
struct TraceScratch {
    std::vector<Vec3f> ray_dirs;           // directions above the horizon of the receiver
    std::vector<std::uint32_t> ray_index;  // their indices in the direction set
    std::vector<std::uint8_t> occluded;    // the tracer's answers
    void reserve(std::size_t samples);
    static std::size_t bytes(std::size_t samples) {
        return samples * (sizeof(Vec3f) + sizeof(std::uint32_t) + sizeof(std::uint8_t));
    }
};

// weight: row[s] = max(0, n·w_s)·weight_s for s < S; with `hemisphere` (glossy transfer),
// row[s] = weight_s where n·w_s > 0, else 0 (the hemisphere, no cosine). A local table:
// row[s] = weight_s (every direction is above the horizon, the density is in the weight).
void weight_row(Vec3f n, const DirectionTable& directions, float* row, bool hemisphere = false);
// The same for directions [range.begin, range.end) only: row[s − range.begin].
void weight_row(Vec3f n, const DirectionTable& directions, DirectionRange range, float* row,
                bool hemisphere = false);

// The glossy projection table: P[s·F + p(i,j)] = y_i(w_s)·y_j(w_s) for 0 ≤ i ≤ j < K, with
// F = K(K+1)/2 and p(i,j) the packed upper-triangle index (row by row), from the basis table
// Y[S×K]. project_rows(W, count, S, P, F, C) then gives each receiver's packed M = Yᵀ·diag(W)·Y.
std::vector<float> pair_product_table(const std::vector<float>& Y, std::size_t S, int K);

// trace: zeroes row[s] where the direction is occluded; casts one stream of the directions with
// row[s] ≠ 0 from offset_ray_origin(p, n), in the table's trace order (a local table: turned
// into n's frame by to_world(local_frame(n), ·)). Returns the rays cast.
std::uint32_t trace_row(const Tracer& tracer, Vec3f p, Vec3f n, const DirectionTable& directions,
                        float* row, TraceScratch& scratch);
// The same for directions [range.begin, range.end) only (row[s − range.begin]); the range must be
// whole segments of the table's trace order (the whole set, or [a, b) of its nested prefixes).
std::uint32_t trace_row(const Tracer& tracer, Vec3f p, Vec3f n, const DirectionTable& directions,
                        DirectionRange range, float* row, TraceScratch& scratch);

// Twins: receivers with the same position and normal, bit for bit, cast the same rays and get the
// same row, so a chunk traces one of them and copies its row to the others. Loaders that split
// vertices at UV, material or smoothing seams make many (Assimp's Collada duck: 8 500 vertices,
// 2 290 distinct; docs/sampling.md, "Twins"). twin[j] = the first i ≤ j of [0, count) whose
// position and normal equal receiver j's (j itself when none).
void find_twins(const Vec3f* positions, const Vec3f* normals, std::size_t count,
                std::vector<std::uint32_t>& twin);

// Twins in other chunks: find_twins sees one chunk, and a seam's copies of a vertex often lie in
// several. For receivers [0, count) of a range whose grid of chunks starts `lead` receivers
// before it (chunk c holds grid positions [c·chunk, (c+1)·chunk)): reps are the first receivers
// of each (position, normal) that a receiver in another chunk shares, in increasing order, at
// most `max_reps`; slot[j] is the index in reps of receiver j's first twin, or kNoSlot. The bake
// shares each slot's visibility among its twins (SharedVisibility, below).
struct CrossTwins {
    static constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;
    std::vector<std::uint32_t> reps;  // indices into the range
    std::vector<std::uint32_t> slot;  // per receiver of the range
};
CrossTwins find_cross_twins(const Vec3f* positions, const Vec3f* normals, std::size_t count,
                            std::size_t lead, std::size_t chunk, std::size_t max_reps);
// The most bits of reps' visibility a fixed-S bake keeps (the reps past it trace their own rows).
constexpr std::size_t kCrossTwinBytes = std::size_t(64) << 20;

// Twins in other chunks share their visibility (CrossTwins; docs/sampling.md, "Twins"), in
// fixed-S and error-bounded bakes alike. The first receiver of each (position, normal) that
// several chunks of the grid hold gets a slot of visibility bits over the set, in the set's
// nested segments ([0, S0), [S0, 2·S0), …; a fixed-S bake's one segment is the whole set). The
// first chunk to need a segment of it traces that segment, under the slot's lock; every other
// twin masks its W row with the bits. A row is what tracing it gives, bit for bit (the same
// normal, the same weights), and each segment is traced once, so the bake's rays, too, are the
// same for any thread count. What is shared is visibility, never a projected row or an estimate,
// whose bits depend on the chunk.
class SharedVisibility {
public:
    // Receivers [origin, origin + count) of the arrays, in chunks of `chunk` from origin, over
    // `table` (first segment: first_segment directions, a multiple of 64 or the whole table); at
    // most kCrossTwinBytes of bits (the firsts past it trace their own rows).
    SharedVisibility(const Vec3f* positions, const Vec3f* normals, std::size_t origin,
                     std::size_t count, std::size_t chunk, const DirectionTable& table,
                     std::size_t first_segment);
    // Receiver r's slot (an index of the arrays' numbering), or CrossTwins::kNoSlot.
    std::uint32_t slot(std::size_t r) const;
    // `row` (the weights of one segment [range.begin, range.end) of the table, for this slot's
    // normal) with the slot's blocked directions set to 0, tracing the segment first if no twin
    // has. Returns the rays this call cast (0 when the bits were there).
    std::uint32_t mask(std::uint32_t slot, const Tracer& tracer, Vec3f p, Vec3f n,
                       DirectionRange range, float* row, TraceScratch& scratch);
    std::size_t bytes() const { return bits_.size() * sizeof(std::uint64_t); }

private:
    CrossTwins twins_;
    std::size_t origin_ = 0, words_ = 0, first_segment_ = 1;
    const DirectionTable* table_ = nullptr;
    std::vector<std::uint64_t> bits_;      // reps × words_
    std::vector<std::uint32_t> segments_;  // per rep: bit i set when segment i is traced
    std::unique_ptr<std::mutex[]> locks_;  // per rep
};

// Which receivers of a whole fixed-S bake of S directions over [0, count), in chunks of `chunk`,
// cast rays (1) and which take a twin's row (0): the first of each chunk's twins, unless it is a
// CrossTwins receiver that is not a rep (a slot's rays are cast once, by whichever of its twins
// needs them first; its rep stands for that one here). For tests and benchmarks that count the
// bake's rays.
std::vector<std::uint8_t> traced_receivers(const Vec3f* positions, const Vec3f* normals,
                                           std::size_t count, std::size_t chunk, std::size_t S);

// project: C[count×K] = W[count×S]·Y[S×K], all row-major, one single-threaded cblas_sgemm (the
// caller keeps OpenBLAS at one thread: SingleThreadedBlas).
void project_rows(const float* W, std::size_t count, std::size_t S, const float* Y, int K,
                  float* C);
// The same over the first `depth` ≤ S directions only (W's rows keep their stride S): for rows
// whose weights past `depth` are zero, the same sums without the zero terms.
void project_rows(const float* W, std::size_t count, std::size_t S, std::size_t depth,
                  const float* Y, int K, float* C);

// project, for rows whose weights are one value w or 0 (a local set's: every direction has the
// same weight, and a blocked one is 0): C = W·Y is w times the sum of Y's rows where W ≠ 0, or,
// where more are visible than blocked, w·(T − the sum where W = 0), with T the column sums of Y
// over the `depth` directions (segment_sums). Each row sums its own directions in increasing
// order from zero, so its bits depend on its weights only, never on the other rows of the call
// (a GEMM's may), the CPU's SIMD width or the thread. It adds min(visible, blocked) rows of Y
// per receiver where the GEMM multiplies and adds all of them: about a quarter on the room
// (bench/RESULTS.md, "Blocker cones and projection by sums"); the bakes use it from
// kSumsMinColumns columns.
void project_visibility_rows(const float* W, std::size_t count, std::size_t S, std::size_t depth,
                             const float* Y, int K, const float* T, float w, float* C);
// Below this many columns the SGEMM is faster: listing a row's directions costs as much as adding
// few columns (bench_bake, local set: sums at 0.42-0.50 of the bare SGEMM's rate at K = 32, 0.66
// at 48, 1.6 at 64 and 1.8 at 256).
inline constexpr int kSumsMinColumns = 64;
// The sums of project_visibility_rows: out[k] = the sum of Y[rows[q]·K + k] over q in order, from
// zero, for k < K. The kernels add the same terms in the same order for every k, so all give
// the same bits: the widest the CPU runs (automatic), or one asked for (tests; Error(unsupported)
// where the CPU lacks it).
enum class SumKernel { automatic, portable, avx2, avx512 };
void sum_rows(const float* Y, int K, const std::uint32_t* rows, std::size_t n, float* out,
              SumKernel kernel = SumKernel::automatic);
// The column sums of Y's rows [0, depth) (K columns) in double.
std::vector<double> column_sums(const float* Y, std::size_t depth, int K);
// T for project_visibility_rows: column_sums rounded once to float.
std::vector<float> segment_sums(const float* Y, std::size_t depth, int K);
// The one weight of every direction of the table, or 0 where they differ (a sphere set's).
float common_weight(const DirectionTable& table);

// The open part exactly (local sets, docs/sampling.md "The open part exactly"). In its frame every
// receiver's open transfer f_open (the cosine for vectors, 1 for glossy matrices, over the
// hemisphere) is the same, so the set's quadrature error on it, δ = Q_S(f_open) − ∫ f_open, is one
// vector for all receivers. A receiver's row c' = Q_S(V·f_open) is corrected to
//   c' − β·δ,   β = c'₀/∫f_open,₀ (its visible fraction: the set's weights are equal)
// the control variate ∫f_open − Q_S((1−V)·f_open) weighted by β: an open receiver is exact at any
// S, a closed one stays 0, and in between the error of Q_S on the visible and on the blocked part
// are mixed as (1−β)·e_V − β·e_B.
struct OpenControl {
    std::vector<double> delta;  // δ over the row's columns (FL)
    double open0 = 0;           // ∫ f_open's first column
};
// δ of the prefix [0, count) of a local set with these weights, times `scale` (the error-bounded
// bake's prefix of a larger set: Smax/count), from the table Y the rows are projected on (KL
// columns, or the pair-product table's KL(KL+1)/2 with `matrix`).
OpenControl make_open_control(const float* weights, const float* Y, std::size_t count, double scale,
                              int KL, bool matrix);
// The same for a prefix whose directions all weigh w, from the column sums of its rows of Y
// (column_sums, added segment by segment) and ∫ f_open (sh/sampler.hpp, open_hemisphere_transfer):
// δ = w·scale·sums − ∫ f_open.
OpenControl open_control_from_sums(const std::vector<double>& sums, double weight_scale,
                                   const std::vector<double>& open);
// rows[j] ← rows[j] − β_j·δ for `count` rows of δ.size() columns (none: an empty control).
void apply_open_control(const OpenControl& control, float* rows, std::size_t count);

// rotate (local sets): `count` rows projected in their receivers' frames, `normals[j]` receiver
// j's normal, each `local_columns` wide (KL = projected_coeffs, or KL(KL+1)/2 packed for
// `matrix`), to world rows of K (K(K+1)/2 packed) columns in `world`: c = D(R)·c' over the full
// bands, then the first K; M = D·M'·Dᵀ, then its leading K×K block. In double, per receiver:
// O(Σ(2l+1)²) for a vector, K times more for a matrix. Vectors go eight receivers at a time
// with AVX-512 where the CPU has it (automatic), each receiver with the portable loop's products
// and sums in its order, so the same bits; a kernel this CPU lacks is Error(unsupported).
enum class RotationKernel { automatic, portable, avx512 };
void rotate_rows_to_world(const Vec3f* normals, std::size_t count, int KL, int K, bool matrix,
                          const float* local, float* world,
                          RotationKernel kernel = RotationKernel::automatic);

// OpenBLAS's thread count set to 1 for a scope, restored afterwards: the bake's TBB workers each
// run their own single-threaded SGEMM (bake_cpu.cpp says why). The setting is process-wide, so
// the scopes are counted: with bakes running at once on several threads (two Python threads,
// say), the first scope saves the count, the last one restores it, and no bake's SGEMMs turn
// multi-threaded while another bake still runs.
class SingleThreadedBlas {
public:
    SingleThreadedBlas();
    ~SingleThreadedBlas();
    SingleThreadedBlas(const SingleThreadedBlas&) = delete;
    SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

}  // namespace shprt::detail
