// Private pieces shared by the bake's translation units.
#pragma once

#include "bake/error_bound.hpp"
#include "bake/stages.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/bounce_sources.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/probe_bake.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace shprt::detail {

// Throws Error(invalid_argument) for a direction set a bake cannot take (empty, coordinates that
// do not match the weights, more than kMaxBakeSamples directions).
void validate_direction_set(const DirectionSet& directions);

// The options of a bake given `directions`: the set validated, S its size and the frame its own
// (DirectionSet::frame: a set is never read in another frame than the one it was made in).
BakeOptions with_direction_set(BakeOptions options, const DirectionSet& directions);

// The rest of the boundary check, after validate(options): the occluders (triangles), the
// receivers (normals, a non-empty range inside the domain, fewer than 2^32). (The sink is checked
// by bake(); the test hooks of gpu.hpp check jobs without one.)
void validate_job(const BakeJob& job, const BakeOptions& options);

// The checks bake() makes of a whole-mesh job of `kind` with `directions`, for the GPU test hooks
// of gpu.hpp (which take a mesh and a direction set, not a job).
void validate_whole_mesh(const Mesh& mesh, TransferKind kind, const DirectionSet& directions);

// What a diffuse bake with `options` over S directions produces: kind, the layout (the receivers'
// domain, one channel, K, a vector each, float32), sampler, S, seed; no stats yet.
TransferInfo bake_info(const BakeOptions& options, Receivers receivers, std::size_t samples);

// The backends, called after the boundary checks with the direction set in hand. The CPU bake
// (bake_cpu.cpp): `tracer` may be null for unshadowed transfer, which casts no rays;
// `seconds_bvh` is recorded as the tracer's build time. The GPU bake (bake_gpu.cpp, or
// gpu_fallback.cpp without CUDA) builds its own flat BVH.
TransferInfo bake_cpu(const BakeJob& job, const BakeOptions& options,
                      const DirectionSet& directions, const Tracer* tracer, double seconds_bvh);
// What every pass of a CPU bake shares (bake_cpu.cpp; a BakeSession keeps it): the direction
// table, the basis table Y (or glossy's pair-product table), the open part's control, the
// error bound's parameters.
struct CpuBakeTables {
    CpuBakeTables(const BakeOptions& options, const DirectionSet& directions);
    CpuBakeTables(const CpuBakeTables&) = delete;  // `bound` points into the tables
    CpuBakeTables& operator=(const CpuBakeTables&) = delete;
    std::size_t bytes() const;

    bool glossy = false, shadowed = false, bounded = false, local = false;
    bool hemisphere = false;  // W without the cosine (the kind's row: !cosine)
    std::size_t S = 0;
    int K = 0, KL = 0, F = 0, FL = 0;  // row and product columns (stages.hpp)
    DirectionTable table;
    std::vector<float> Y;
    OpenControl open_control;  // local fixed-S sets
    // Local fixed-S sets: the one weight of every direction, and Y's column sums over the set
    // (stages.hpp, project_visibility_rows); weight 0: rows are projected by one SGEMM.
    float weight = 0.0f;
    std::vector<float> sums;
    ErrorBound bound;  // error-bounded bakes
};
// One pass over job.receivers with the tables: bake_cpu's body. An error-bounded pass bakes to
// prefixes of at most `cap` (0: the whole set), keeping each row's sums, prefix and estimate in
// `kept` (the whole receiver set's rows; null: the pass's scratch) — a later pass with a larger cap
// and the same `kept` traces only the new segments.
TransferInfo bake_cpu_pass(const BakeJob& job, const BakeOptions& options,
                           const CpuBakeTables& tables, const Tracer* tracer, double seconds_bvh,
                           BoundRows kept = {}, std::size_t cap = 0);
// Interreflected transfer (interreflect.cpp), CPU only: T_0 by bake_cpu, then the transport
// operator and the bounces; `tracer` is required.
TransferInfo bake_interreflected(const BakeJob& job, const BakeOptions& options,
                                 const DirectionSet& directions, const Tracer* tracer,
                                 double seconds_bvh);
// The occluders as a GPU bake traces them: the flat BVH built on the host and its copy on the
// device (bake_gpu.cpp). A bake session keeps them across its passes (`kept`: built by the first
// pass that traces, then reused — the device copy stays until the session and the passes let it
// go); null: the bake builds its own.
struct GpuOccluders;
TransferInfo bake_gpu(const BakeJob& job, const BakeOptions& options,
                      const DirectionSet& directions,
                      std::shared_ptr<GpuOccluders>* kept = nullptr);

// Interreflected transfer, the pieces both backends share (interreflect.cpp): the job check (all
// vertices of the scene, host rows, an albedo per vertex), and, once T_0 (V × K) and A exist, the
// bounces — each `bounce` is out = A·in over V × 3K floats, counting rows on `progress` — with
// the sums, the relative changes, --bounces converged, the sink and the stats. `other_bytes`:
// the backend's host memory besides T_0, A and the bounce buffers; `seconds_so_far`: since the
// bake began (BVH included).
class BakeProgress;
// Where the finished blocks of A go, on the CPU and from the GPU: kept in memory (trimmed to
// their size) while the kept ones fit `budget` bytes (0 = no limit), else spilled to a temporary
// file in `spill_directory` (TransportOptions says how); finish() maps the spilled blocks back
// into A (A.spill, A.spilled_bytes). keep() is thread-safe; which blocks spill depends on the
// order they come, never the bits.
class TransportBlockStore {
public:
    TransportBlockStore(std::uint64_t budget, std::string spill_directory);
    ~TransportBlockStore();
    TransportBlockStore(const TransportBlockStore&) = delete;
    TransportBlockStore& operator=(const TransportBlockStore&) = delete;

    void keep(std::size_t index, TransportOperator::Block& block);
    void finish(TransportOperator& A);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// The bytes BakeOptions::memory_budget leaves for A once the rest of an interreflected bake
// (estimate_bake_peak_bytes) has its share: 0 without a budget, at least 1 (every block spills).
std::uint64_t transport_memory_budget(const Mesh& mesh, const BakeOptions& options);

// One call of a bounce's product: rows [first, end) of out = A·in — each a block boundary of A —,
// the first `columns` coefficients of each channel. `in` holds A's N rows of in_channels × in_K
// floats (in_channels 1: one channel that the three share, the first bounce's T_0); row r of the
// result goes to out + (r − first)·3·out_K, channel c at c·out_K. Counts its rows on `progress`.
struct BounceRows {
    const float* in = nullptr;
    int in_channels = 3, in_K = 0;
    std::size_t first = 0, end = 0;
    float* out = nullptr;
    int out_K = 0;
    int columns = 0;
};
using BounceProduct = std::function<void(const BounceRows& rows, BakeProgress& progress)>;
// The CPU's product for one BounceRows (transport_product.cpp), counting its rows on `progress`
// (or null); apply_transport is the same over every row and column.
void apply_transport_rows(const TransportOperator& A, const BounceRows& rows, int threads,
                          TransportKernel kernel, BakeProgress* progress);
void check_interreflected_job(const BakeJob& job);
// The probes of `job` (BakeJob::probes; nothing when null) baked with the bake's direction set (a
// local bake: the sphere set of its sampler and seed) and `tracer` (null: built here for
// shadowed kinds), after its receivers; `info`'s stats gain their rays and seconds.
void bake_job_probes(const BakeJob& job, const BakeOptions& options, const DirectionSet& directions,
                     const Tracer* tracer, const ProbeBounce* bounce, TransferInfo& info);
// Whether a ray along `dir` that hit triangle `t` met its back (one-sided: counter-clockwise is
// the front), as transport_hit_entries decides; the bounce sources' and the probes' validity.
bool meets_back_face(const Mesh& mesh, std::uint32_t t, Vec3f dir);
// What the operator's pass learnt of the bounce sources: which are valid (source_is_valid), the
// directions each traced, and how many receivers saw a back face.
struct BounceSourceRays {
    const BounceSources* sources = nullptr;
    std::vector<std::uint8_t> valid;  // one per source
    std::size_t indirect_samples = 0;
    std::uint64_t receivers_seeing_back_faces = 0;
};
// The bounces over the sources (A: N × N, `bounce` over N × 3K floats), from T_0 (the receivers',
// V × K) and T0_sources (N × K; its first V rows are replaced by T0's); with no bounces wanted A
// and the sources are empty. `estimates` (an error-bounded bake): T_0's per-receiver prefixes and
// estimated errors, written to the sink with the rows. With `source_light`, it gets each source's
// light as the probes read it (ProbeBounce::light: N rows of 3 × K, T_0 + … + T_{N−1} after the
// fill of invalid sources; empty with no bounces).
TransferInfo finish_interreflected(const BakeJob& job, const BakeOptions& options,
                                   TransferInfo info, std::vector<float> T0,
                                   std::vector<float> T0_sources, const BounceSourceRays& rays,
                                   const TransportOperator& A, const BounceProduct& bounce,
                                   std::uint64_t other_bytes, double seconds_so_far,
                                   std::vector<float>* source_light = nullptr,
                                   const TransferSet* estimates = nullptr);
// The operator of an interreflected bake over its bounce sources, traced on the CPU from the
// indirect directions (indirect_direction_set): A, each source's T_0 from the same rays (the
// receivers' rows are replaced by the full bake's in finish_interreflected), what the rays met;
// `stats` gains the pass's rays and seconds. Shared by both backends.
struct SourceOperator {
    std::unique_ptr<BounceSources> sources;  // rays.sources points here
    std::vector<float> T0_sources;
    BounceSourceRays rays;
    TransportOperator A;
    std::uint64_t pass_bytes = 0;  // the pass's tables and buffers
};
SourceOperator trace_source_operator(const Mesh& mesh, const BakeOptions& options,
                                     const DirectionSet& directions, const Tracer& tracer,
                                     BakeStats& stats, std::size_t gather_base = 0);
// The options of an interreflected bake's T_0 stage: the shadowed bake's, whose progress names
// the bounce sources and the bounces that follow (ProgressInfo::then).
BakeOptions direct_stage_options(const BakeOptions& options);
// The directions an inner bounce source (not a receiver) traces: the first gather/kInnerShare of
// the receivers' `gather`.
std::size_t inner_source_samples(std::size_t gather);
// The bounce sources of a bake with `options` (spacing 0 = default_source_spacing).
BounceSources bake_bounce_sources(const Mesh& mesh, const BakeOptions& options);
// The GPU backend of interreflected transfer (bake_gpu.cpp; gpu_fallback.cpp without CUDA):
// closest hits, T_0 and A's blocks on the device (A's from the hit records with the CPU rows'
// arithmetic, transport_build.hpp), the bounces by cuSPARSE.
TransferInfo bake_interreflected_gpu(const BakeJob& job, const BakeOptions& options,
                                     const DirectionSet& directions);

}  // namespace shprt::detail
