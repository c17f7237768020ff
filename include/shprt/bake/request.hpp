// A whole bake as one value (docs/architecture.md, "The bake request"): what to bake
// (BakeOptions), which receivers (every vertex, a shard of them, the texels of a UV atlas, or
// vertices refined until the transfer is smooth), where the rows go (memory, or a .shprt file
// written at the end or streamed as chunks finish), a checkpoint to resume from, and the memory the
// bake may take. `shprt bake`, Python's shprt.bake and the viewer build the same request; one
// function says what cannot combine (request_refusal) and one runs it (run). The shells only parse
// their text into it and print its result.
//
// What run() adds to the bare bake (bake.hpp): the memory check before any work (the estimate of
// estimate_bake_peak_bytes or texel_bake_bytes against `max_memory`, else the machine's available
// memory), the spill folder of an interreflected bake's operator (the output's), the texel atlas
// and the refinement's record in the file's metadata, the shard's range in the metadata, the
// checkpoint (synced and named in the error when the bake is cancelled), and the write through
// AtomicFile or the streaming writer — nothing at the path until the whole file is there.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/bake/probe_bake.hpp"
#include "shprt/bake/refine.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_stream.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/uv_atlas.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace shprt {

// Which receivers a request bakes.
struct AllVertices {};
// Part `index` of `count` of the vertices: receivers [⌊V·i/n⌋, ⌊V·(i+1)/n⌋) of the same bake,
// bit for bit (`shprt merge` joins the parts' files); 0 ≤ index < count ≤ V.
struct VertexShard {
    std::size_t index = 0, count = 1;
};
// The texel centres of the mesh's UV set `uv_set` in a width × height image (bake/texels.hpp),
// each side 1..kMaxTexelSide. With `unwrap`, run() first lays out a new atlas on a copy of the
// mesh (make_uv_atlas, conformal; scene/uv_atlas.hpp), replacing its UVs, and bakes and writes
// that mesh: the image is its resolution² (texels_per_metre > 0: chosen by the atlas; width and
// height are then 0), the UV set 0.
struct TexelGrid {
    int width = 0, height = 0;
    int uv_set = 0;
    std::optional<UvAtlasOptions> unwrap;
};
// The vertices, refined where the transfer changes too much across an edge (bake/refine.hpp).
struct RefinedVertices {
    RefineOptions refine;
};
using ReceiverSet = std::variant<AllVertices, VertexShard, TexelGrid, RefinedVertices>;

// The receivers as the front ends spell them (`shprt bake --domain --resolution --uv-set --refine
// --max-vertices --max-edge-split-depth --shard`, and Python's keywords of the same names), parsed
// by one function so that both take the same values.
struct ReceiverChoice {
    std::string domain = "vertex";  // "vertex" or "texel"
    std::string resolution;         // texel: "W" (square) or "WxH", each 1..kMaxTexelSide
    int uv_set = 0;                 // texel: the UV set
    std::optional<double> refine;   // vertex: the refinement's tolerance (> 0)
    std::optional<long long> max_vertices, max_edge_split_depth;  // refinement's limits
    std::string shard;                    // vertex: "I/N", part I of N (0 ≤ I < N), or empty
    bool unwrap = false;                  // texel: a new atlas (TexelGrid::unwrap)
    std::optional<double> texel_density;  // texel with unwrap: texels per metre (> 0)
    // Transfer probes beside the receivers (`--probes --probe-box --probe-bands`): parsed by
    // parse_probes (bake/probe_bake.hpp) into BakeRequest::probes.
    std::string probes, probe_box;
    std::optional<long long> probe_bands;
    // Not a receiver set's but typed with the texel options (`--float32`): texel coefficients
    // stored as float32 (FileOutput::encoding; default float16).
    bool float32 = false;
};
// The ReceiverSet of `choice`; one-line Error(invalid_argument) naming the option for a bad value
// or options that need another (--resolution without --domain texel, --shard with texels, ...).
// --domain texel needs --resolution, or --unwrap with --texel-density (not both); --unwrap takes a
// square --resolution and no --uv-set.
ReceiverSet parse_receivers(const ReceiverChoice& choice);

// A .shprt file as the output.
struct FileOutput {
    std::string path;
    // float32 or float16 coefficients; unset: float16 for texels (their count makes the size
    // matter), float32 otherwise.
    std::optional<TransferEncoding> encoding;
    // Rows written into the file as chunks finish (io/shprt_stream.hpp): no V×K array in memory.
    bool stream = false;
    // The caller's metadata (e.g. the command line, the load time) and reproducibility; the
    // request adds its own (the shard, the texel bake, the refinement).
    WriteOptions write;
};

// Keep the finished rows in `path` as the bake goes (io/checkpoint.hpp); with `resume`, continue
// the bake whose checkpoint it is (same scene and options): the rows already there are not baked
// again, and the result is the uninterrupted bake's bit for bit. Removed once the output is in
// place.
struct CheckpointRequest {
    std::string path;
    bool resume = false;
    double sync_seconds = 30;  // between syncs to disk, ≥ 0
};

struct BakeRequest {
    BakeOptions options;  // with its progress callback
    ReceiverSet receivers = AllVertices{};
    std::optional<FileOutput> output;  // none: the rows stay in memory (BakeResult::transfer)
    std::optional<CheckpointRequest> checkpoint;
    // The most bytes the bake may take, checked against its estimate before any work; 0 = the
    // machine's available memory (core/memory.hpp), unchecked where that cannot be read.
    std::uint64_t max_memory = 0;
    // Transfer probes baked beside the receivers into the same file (bake/probe_bake.hpp): the
    // grid laid over the scene's bounds or the spec's box; none = no probes. BakeResult's
    // transfer.probes holds them (with a file output too).
    std::optional<ProbeSpec> probes;
    // Run across the ranks of an MPI job (dist/mpi_bake.hpp runs such a request); here it only
    // decides what cannot combine.
    bool distributed = false;
    // An error-bounded bake of every vertex, its rows held for the output, goes breadth first in
    // rounds (BakeSession::bake_in_rounds): each round is a stage of the progress ("bake",
    // "≤ 1024 samples", …) whose estimated error falls from round to round, at the price of the
    // rounds' rows in memory (round_rows_bytes). The same rows. For a display that shows the
    // stages and the error (the `shprt` program's); a caller that sees only done and total would
    // see them start over each round. Ignored (one pass) for a streamed output, a shard, probes,
    // a checkpoint or interreflected transfer.
    bool error_rounds = false;
    // Called once the output and the checkpoint are laid out, just before the bake starts.
    std::function<void()> before_bake;
    // Called once the bake is over and before the output is written (a shell ends its cancel
    // mode there: a signal from then on means nothing is written).
    std::function<void()> before_write;
};

// The one list of combinations that do not work, as the one-line reason (naming the options as
// `shprt bake` spells them), or nothing: a checkpoint of an MPI, texel, refined or interreflected
// bake, or one that is the output file; texels or refinement with a shard, streaming or MPI;
// interreflected transfer sharded, streamed, refined or across ranks; streaming without a file;
// probes with a shard, streaming, refinement, a checkpoint or MPI;
// options the request's receivers cannot take (a shard of more parts than vertices is checked by
// run(), which knows the mesh).
std::optional<std::string> request_refusal(const BakeRequest& request);
// Throws Error(unsupported) with request_refusal's line when there is one (Error(invalid_argument)
// for values out of range: a shard, a texel size, the checkpoint's sync interval).
void check(const BakeRequest& request);

struct BakeResult {
    TransferInfo info;      // what was baked: kind, layout (with the file's encoding), stats
    TransferSet transfer;   // without a file output: the rows (and the texel atlas); else no rows
    std::size_t first = 0;  // the receivers baked: [first, first + receivers)
    std::size_t receivers = 0;
    std::optional<Mesh> refined_mesh;  // RefinedVertices: the mesh the rows belong to
    RefineResult refinement;           // RefinedVertices: the summary (its mesh and rows moved out)
    std::uint64_t covered_texels = 0;  // TexelGrid: texels covered by the atlas
    std::optional<UvAtlasInfo> unwrap;   // TexelGrid with unwrap: the atlas made
    std::optional<Mesh> unwrapped_mesh;  // ... and the mesh it was made on (rows are its texels)
    std::uint64_t estimated_bytes = 0;   // the estimate checked against the memory limit
    double seconds_bake = 0, seconds_write = 0;
};

// What run() throws when a checkpointed bake stops with rows in its checkpoint — cancelled, or
// failed (a full disk, a device error): the error's code, its message followed by "; N of M
// receivers are saved in PATH", and those facts. The checkpoint is synced: the same request with
// `resume` continues it.
class CheckpointKept : public Error {
public:
    CheckpointKept(const Error& cause, std::size_t done, std::size_t count, std::string path);
    std::size_t done = 0, count = 0;
    std::string path;
};

// Runs `request` on `mesh` (the occluders, and the vertices or UVs of the receivers): checks it
// (check, then what needs the mesh: the shard's size, the memory estimate — Error(out_of_memory)
// naming the estimate and the limit), bakes, calls before_write and writes the output. Throws
// what bake(), bake_refined and the writers throw; CheckpointKept when a checkpointed bake stops
// with rows saved.
BakeResult run(const BakeRequest& request, const Mesh& mesh);

// The pieces of run() for a vertex bake, for the runner of distributed requests
// (dist/mpi_request.hpp), whose rank 0 writes what every rank bakes.
//
// The receivers of a vertex request (every vertex, or the shard's range: Error(invalid_argument)
// for more shards than vertices) and the file's write options (the caller's, with the shard).
Receivers request_receivers(const BakeRequest& request, const Mesh& mesh, WriteOptions& write);
// Where the rows of a vertex request go: the streaming writer, laid out at construction (the
// file's temporary exists from then on), or host memory. finish() calls before_write and writes
// the file (or, without a file output, moves the rows into out.transfer); returns its seconds.
class BakeOutput {
public:
    BakeOutput(const BakeRequest& request, const Mesh& mesh, const Receivers& receivers,
               WriteOptions write);
    ~BakeOutput();
    BakeOutput(const BakeOutput&) = delete;
    BakeOutput& operator=(const BakeOutput&) = delete;
    TransferSink& sink();
    // Where an interreflected bake's direct part goes (nullptr when streamed).
    TransferSink* direct();
    double finish(const TransferInfo& info, BakeResult& out);

private:
    const BakeRequest& m_request;
    const Mesh& m_mesh;
    WriteOptions m_write;
    std::unique_ptr<ShprtStreamWriter> m_writer;
    HostSink m_host, m_direct;
};

}  // namespace shprt
