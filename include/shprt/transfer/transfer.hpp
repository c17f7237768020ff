// Transfer: what a bake produces, what .shprt files store, what shading consumes — and its
// layout, the one place that knows how many floats a receiver has.
//
// A transfer set holds, for each *receiver* (a mesh vertex today; a texel, a refined vertex or a
// shard's range later), `channels` blocks of coefficients in the SH basis of size K (flat index
// i = l(l+1)+m, sh/basis.hpp). A block is either a vector of K coefficients (diffuse transfer:
// E = Σ_i c_T[i]·c_L[i]) or a K×K matrix (glossy transfer: shadowed incident radiance = M·L),
// full or, when symmetric, as its packed upper triangle. Everything is stored receiver-major:
//
//     coeffs[layout.offset(r, c) + j] = element j of channel c of receiver r
//     layout.offset(r, c)            = (r·channels + c) · layout.floats_per_channel()
//
// In memory coefficients are always float32; `encoding` says how a file stores them (or should).
#pragma once

#include "shprt/scene/texel_raster.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/transfer/cpca_code.hpp"
#include "shprt/transfer/probes.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

struct Mesh;

enum class TransferKind {
    unshadowed,  // T(w) = max(0, n·w)
    shadowed,    // T(w) = V(w) · max(0, n·w), V = 1 where the ray escapes the scene
    // The shadowed transfer plus the light that reaches the receiver after bouncing off the
    // scene's diffuse surfaces: T_0 + T_1 + … + T_N, RGB (three channels), docs/interreflection.md.
    interreflected,
    // Glossy (incident-radiance) transfer: per receiver the symmetric K×K matrix
    // M = Σ_s weight_s V(w_s) y(w_s) y(w_s)ᵀ over the hemisphere of the normal (V = 0 below it;
    // no cosine), so that M·L is the SH projection of the shadowed incident radiance
    // (docs/glossy.md). One channel, TransferShape::symmetric_matrix.
    glossy,
};

// Where the receivers are: the mesh's vertices, or the texel centres of its UV atlas
// (bake/texels.hpp; the set's TexelAtlas says which texels).
enum class ReceiverDomain { vertex, texel };

// The shape of one channel of one receiver.
enum class TransferShape {
    vector,            // K coefficients
    matrix,            // K×K, row-major
    symmetric_matrix,  // K×K symmetric, its upper triangle packed row by row: K(K+1)/2 floats
};

// How the coefficients are (to be) stored in a file. In memory they are float32 always.
enum class TransferEncoding { f32, f16 };

const char* to_string(TransferKind kind);
TransferKind parse_transfer_kind(const std::string& name);  // throws Error(invalid_argument)
const char* to_string(ReceiverDomain domain);
ReceiverDomain parse_receiver_domain(const std::string& name);  // throws Error(invalid_argument)
const char* to_string(TransferShape shape);
TransferShape parse_transfer_shape(const std::string& name);  // throws Error(invalid_argument)
const char* to_string(TransferEncoding encoding);  // "float32", "float16" (the file's dtype)
TransferEncoding parse_transfer_encoding(const std::string& name);  // throws Error
// The bytes of one stored value: 4 (float32) or 2 (float16).
inline int bytes_per_value(TransferEncoding encoding) {
    return encoding == TransferEncoding::f16 ? 2 : 4;
}

// Largest basis size a transfer may have (64 bands; a bake allows fewer, see bake.hpp).
inline constexpr int kMaxTransferK = sh_count(kMaxBands);

struct TransferLayout {
    ReceiverDomain domain = ReceiverDomain::vertex;
    int channels = 1;  // 1 (grey transfer) or 3 (RGB, e.g. with interreflections)
    int K = 0;         // basis size: the first K coefficients in index order
    TransferShape shape = TransferShape::vector;
    TransferEncoding encoding = TransferEncoding::f32;

    // Floats of one channel of one receiver: K, K², or K(K+1)/2.
    std::size_t floats_per_channel() const;
    // channels · floats_per_channel(): one receiver's row.
    std::size_t floats_per_receiver() const { return std::size_t(channels) * floats_per_channel(); }
    // Floats of `receivers` rows.
    std::size_t floats(std::size_t receivers) const { return receivers * floats_per_receiver(); }
    // Index of the first float of channel `channel` of receiver `receiver`.
    std::size_t offset(std::size_t receiver, int channel = 0) const {
        return (receiver * std::size_t(channels) + std::size_t(channel)) * floats_per_channel();
    }
    // Throws Error(invalid_argument) unless 1 ≤ K ≤ kMaxTransferK and channels is 1 or 3.
    void validate() const;

    bool operator==(const TransferLayout&) const = default;
};

// Timings (seconds) and counters of one bake, stored in the file's metadata.
struct BakeStats {
    double seconds_bvh = 0, seconds_trace = 0, seconds_project = 0, seconds_total = 0;
    std::uint64_t rays_cast = 0;  // rays actually traced (below-horizon rays are not cast)
    // The bake's peak host memory: its working memory with the BVH, plus the rows held for the
    // output (all V·K floats, unless streamed to the file as chunks finish). The bake's summary
    // line ("peak") and `shprt info` ("peak memory … host") print this one number.
    std::uint64_t peak_bytes_host = 0;
    std::uint64_t peak_bytes_device = 0;
    std::string device_name;  // "cpu: 2 threads" or the GPU's name
    // Interreflected transfer only: merging the closest hits into the transport operator A (the
    // hits themselves are traced once, for T_0 and A together: seconds_trace) and the bounces'
    // sparse products with their sums.
    double seconds_operator = 0, seconds_bounces = 0;
    // Interreflected transfer only: bytes of A that did not fit the memory budget and were read
    // from a memory-mapped temporary file instead (BakeOptions::memory_budget); 0 = none.
    std::uint64_t operator_bytes_spilled = 0;
};

// How an interreflected transfer was made (TransferKind::interreflected; empty otherwise).
struct InterreflectionInfo {
    int bounces = 0;            // N: the stored transfer is T_0 + … + T_N
    bool converge = false;      // N was chosen by iterating until `tolerance` was met (or
                                // max_bounces ran out: then `converged` is false)
    bool converged = false;     // converge asked and last_change < tolerance
    double tolerance = 0;       // converge only: the largest relative change allowed
    double last_change = 0;     // the largest relative change of any receiver's transfer by T_N
    bool two_sided = false;     // rays that hit a back face see its front's radiance
    std::string albedo_source;  // where the albedo came from: "--albedo 0.5,0.5,0.5", ...
    std::uint64_t operator_nnz = 0;    // non-zeros of A (one pattern, three channels' values)
    std::uint64_t operator_bytes = 0;  // bytes of A: pattern + 3 value arrays
    std::uint64_t operator_rays = 0;   // closest-hit rays traced for A: the same rays as T_0's
                                       // (stats.rays_cast) since one pass traces both
    // The bounce sources (bake/bounce_sources.hpp; 0 in files written before them): how many
    // points A's rows and columns are, their cell size, how many were invalid (inside or under
    // geometry, filled from their neighbours), the directions each traced, and how many
    // receivers saw a back face (a hint of a leaky or open asset).
    std::uint64_t sources = 0;
    double source_spacing = 0;
    std::uint64_t invalid_sources = 0;
    std::uint64_t indirect_samples = 0;
    std::uint64_t receivers_seeing_back_faces = 0;
    // The coefficients the light carries from its second bounce on (BakeOptions::bounce_coeffs;
    // 0 in files written before it: all K).
    std::uint64_t bounce_coeffs = 0;
};

// Adds the work of `part` (one part of a bake: a shard, an MPI rank's share) to `total`: seconds
// and rays summed, peak memory the larger, and part's device name appended to total's
// "; "-separated list unless it is there already. How the parts' stats combine, everywhere.
void add_stats(BakeStats& total, const BakeStats& part);

// The texels of a texel-domain transfer (ReceiverDomain::texel; empty otherwise): a W×H image
// of the mesh's UV set, row 0 at the top (v = 1), and for each receiver r, in ascending order,
// the index y·width + x of its texel. Texels not listed are outside every chart.
struct TexelAtlas {
    int width = 0, height = 0;
    int uv_set = 0;                    // which UV set of the scene (load_scene's uv_set)
    std::vector<std::uint32_t> texel;  // one per receiver, strictly increasing, < width·height

    bool empty() const { return texel.empty(); }
    bool operator==(const TexelAtlas&) const = default;
};

// Gutter dilation, so bilinear filtering and mip-maps do not bleed the empty background into a
// chart: for every texel of the atlas's width × height image, the receiver whose value it shows:
// its own for a covered texel; for an empty texel within `gutter` rings (8-neighbourhood) of a
// chart, the receiver of a covered texel reached ring by ring (the first neighbour in the order
// W, E, N, S, NW, NE, SW, SE that has one); −1 elsewhere.
std::vector<std::int64_t> dilate_texels(const TexelAtlas& atlas, int gutter);

// Why `samples` (TransferInfo::samples) cannot describe a transfer of `kind`, or nullptr: a
// negative count, or 0 for a kind other than unshadowed. 0 means "no directions": only unshadowed
// transfer has a closed form (the clamped cosine's SH projection, sh/zonal.hpp); shadowed, glossy
// and interreflected transfer are baked from at least one direction per receiver (and bake()
// traces at least one for unshadowed transfer too). The .shprt writer and reader refuse both.
const char* samples_refusal(TransferKind kind, int samples);

// Everything about a transfer set but its coefficients: what a bake into a sink returns.
struct TransferInfo {
    TransferKind kind = TransferKind::shadowed;
    TransferLayout layout;

    // Sampling that produced it (recorded in the file).
    SamplerKind sampler = SamplerKind::uniform;
    DirectionFrame direction_frame = DirectionFrame::sphere;  // the set's frame (sampler.hpp)
    int samples = 0;
    std::uint64_t seed = 0;
    // An error-bounded bake's target error E (0: none; then every receiver has `samples`, and
    // with one, `samples` is the most a receiver has: docs/sampling.md).
    double target_error = 0;
    BakeStats stats;
    InterreflectionInfo interreflection;  // kind == interreflected only
    TexelAtlas texels;                    // layout.domain == texel only: which texel each
                                          // receiver is (the bake leaves it to its caller)
};

struct TransferSet : TransferInfo {
    std::vector<float> coeffs;  // layout.floats(receiver_count()) floats, see the file comment
    // Interreflected transfer only (else empty): the direct (shadowed) transfer T_0, one channel
    // per receiver (it is the same for R, G and B: the albedo enters only at bounces),
    // receiver_count() × layout.floats_per_channel() floats. direct_only() shades with it.
    std::vector<float> direct;
    // The CPCA code the rows were reconstructed from (or are to be stored as); empty otherwise.
    CpcaCode cpca;
    // Transfer probes baked beside the receivers (`shprt bake --probes`, transfer/probes.hpp);
    // empty (no counts) otherwise.
    ProbeGrid probes;
    // An error-bounded bake's per-receiver directions and estimated errors (receiver_count()
    // each); empty otherwise: every receiver then has `samples`.
    std::vector<std::uint32_t> receiver_samples;
    std::vector<float> receiver_error;

    // An all-zero set of `receivers` rows with the given description (what a progressive display
    // starts from before the first chunk arrives).
    static TransferSet zeros(const TransferInfo& info, std::size_t receivers);

    std::size_t receiver_count() const {
        const std::size_t n = layout.floats_per_receiver();
        return n > 0 ? coeffs.size() / n : 0;
    }
    const float* receiver(std::size_t r, int channel = 0) const {
        return coeffs.data() + layout.offset(r, channel);
    }
    float* receiver(std::size_t r, int channel = 0) {
        return coeffs.data() + layout.offset(r, channel);
    }

    // The direct (T_0) transfer of an interreflected set as a one-channel shadowed set with the
    // same K, sampler and seed: "direct only" for shading. Throws Error(invalid_argument) when
    // there is no direct part.
    TransferSet direct_only() const;

    // How many receivers the domain has: the mesh's vertices, or texels.texel.size().
    std::size_t receiver_total(const Mesh& mesh) const;

    // The one check of a transfer against its mesh: a valid layout, one row per receiver of the
    // mesh (its vertices, for the vertex domain: coeffs.size() == layout.floats(V); its atlas's
    // texels for the texel domain, whose atlas must be valid and the mesh have UVs), and normals
    // and albedo for every vertex. Throws Error(invalid_argument) naming the mismatch.
    void check(const Mesh& mesh) const;
    // The same for a part of a transfer (a shard): whole rows (coeffs.size() a non-zero multiple
    // of layout.floats_per_receiver()) of receivers [first, first + receiver_count()), a range
    // inside the mesh's. check(mesh) is check_rows(mesh, 0) with receiver_count() == V.
    void check_rows(const Mesh& mesh, std::size_t first) const;
    // What check_rows checks but the coefficients themselves: `count` rows of `layout` for
    // receivers [first, first + count) of `mesh` (for rows not in memory, e.g. a streamed file).
    // `total` is the domain's receiver count (receiver_total).
    static void check_range(const Mesh& mesh, const TransferLayout& layout, std::size_t first,
                            std::size_t count, std::size_t total);
};

// The texel centres of a texel set's atlas on `mesh`: rasterize_texels (scene/texel_raster.hpp)
// at the atlas's size and UV set, checked against its texel list. Throws Error(format) naming the
// mesh when the mesh's UVs give other texels (another scene), and what rasterize_texels throws.
TexelSamples atlas_texel_samples(const Mesh& mesh, const TexelAtlas& atlas);

// The unit normals of the receivers of `transfer` on `mesh`, one per receiver: the vertex normals,
// or the texel centres' (atlas_texel_samples).
std::vector<Vec3f> receiver_normals(const Mesh& mesh, const TransferSet& transfer);

}  // namespace shprt
