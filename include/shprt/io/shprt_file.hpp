// The .shprt file: one baked scene — mesh, per-vertex transfer coefficients and the metadata
// needed to use them correctly (SH convention, K, sampler, scene hash, bake statistics).
// docs/file_format.md describes it byte by byte; in short:
//
//   48-byte header  magic "\x89SHPRT\r\n\x1a\n\0\0", format version, endianness marker,
//                   metadata offset/length/CRC-32, header CRC-32
//   metadata        UTF-8 JSON object (conventions, K, bands, sampler, ..., section table)
//   sections        64-byte aligned little-endian arrays, each with its byte length and CRC-32,
//                   in the order of the one section table (src/io/shprt_sections.cpp):
//                   positions, normals, albedo (float32 V×3), triangles (uint32 T×3),
//                   source_vertex (uint32 V, only when the mesh has one),
//                   transfer (the layout's encoding, float32 or float16: receivers × floats per
//                   receiver, transfer/transfer.hpp)
//
// Version 2 adds the transfer layout's receiver domain and shape to the metadata; version 1 files
// (vertex domain, vector shape) still read. Version 3 (CPCA files only) replaces the transfer
// section by a clustered-PCA code; the reader reconstructs the rows (transfer/cpca.hpp).
//
// Every byte of the file is covered by a check (a CRC or "padding is zero"), and the reader
// validates every length and offset against the file size before it reads or allocates.
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// The format version this build writes (it reads 1 too).
inline constexpr std::uint32_t kShprtFormatVersion = 2;
// The version of a file that stores a CPCA code instead of the rows (TransferSet::cpca, "cpca"
// metadata and the cpca_* sections; docs/file_format.md): only those files carry it, so every
// other file stays readable by older builds.
inline constexpr std::uint32_t kShprtCpcaFormatVersion = 3;
// The newest version this build reads.
inline constexpr std::uint32_t kShprtNewestReadVersion = kShprtCpcaFormatVersion;

struct WriteOptions {
    // The first receiver of the transfer's rows: 0 for a whole file; for a part of a sharded bake
    // (its rows are receivers [receiver_first, receiver_first + rows)), where its range starts.
    std::size_t receiver_first = 0;
    // A JSON object merged into the metadata (e.g. timings, peak memory, the bake command line);
    // empty = none. Objects merge recursively ({"stats": {"seconds_load": 0.1}} adds to the
    // stats); a key that would replace a value the writer sets is an Error(invalid_argument).
    std::string extra_metadata_json;
    // As extra_metadata_json, but facts that the same inputs always reproduce (a refinement's
    // passes and budget, a texel bake's coverage): kept in reproducible files too.
    std::string kept_metadata_json;
    // Leave out everything that differs between two runs of the same bake (the stats: timings,
    // rays, peak memory, device; and extra_metadata_json), so that the same inputs give the same
    // bytes.
    bool reproducible = false;
};

// Writes `mesh` and `transfer` to `path` through AtomicFile (a temporary file beside `path`,
// renamed over it at the end): on any failure the target is untouched and no temporary is left.
// The coefficients are stored in transfer.layout.encoding (float32, or IEEE float16). A transfer
// with fewer rows than the mesh has vertices, or options.receiver_first > 0, is written as a part
// of a sharded bake (metadata "receivers": its range), which read_shprt refuses and
// read_shprt_part / merge_shprt_parts read.
// Preconditions, checked (Error(invalid_argument) naming the file and the problem): transfer
// .check_rows(mesh, options.receiver_first) (layout, whole rows inside the mesh's vertices,
// normals and albedo per vertex); source_vertex is
// empty or has one entry per vertex; triangle indices are < V; coefficients are finite and, for
// float16, within its range (|c| < 65520). Filesystem failures throw Error(io) naming the path.
void write_shprt(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
                 const WriteOptions& options = {});

struct ShprtFile {
    Mesh mesh;                  // mesh.source is the scene's source as recorded at bake time
    TransferSet transfer;       // coeffs always float32 in memory (float16 files widened); the
                                // layout's encoding says how the file stored them
    std::string metadata_json;  // the metadata block exactly as stored
    // The transfer's rows are receivers [receiver_first, receiver_first + rows): 0 and all of them
    // for a whole file; a range for a part of a sharded bake (read_shprt_part).
    std::size_t receiver_first = 0;
    bool is_part() const {
        return receiver_first != 0 || transfer.receiver_count() != transfer.receiver_total(mesh);
    }
};

// Reads and validates a .shprt file: magic, version, endianness, header and metadata CRCs, the
// JSON, every section's offset and length against the file size (before reading anything), the
// section sizes against V, T, K and channels, every section's CRC-32, zero padding, triangle
// indices, finite values and the recorded scene hash. Any problem throws shprt::Error with
// ErrorCode::format (content) or ErrorCode::io (cannot open/read), whose one-line message names
// the file and the problem, e.g. "room.shprt: truncated: section 'transfer' needs 1234 bytes at
// offset 5678 but the file has 4000". Memory allocated is bounded by the file's size.
// A part of a sharded bake (see write_shprt) is refused with a one-line Error(format) that says
// to join the parts with `shprt merge`: every reader of whole files sees whole transfers.
ShprtFile read_shprt(const std::string& path);

// The same, but a part of a sharded bake is read too (receiver_first and the transfer's rows say
// which receivers it holds).
ShprtFile read_shprt_part(const std::string& path);

// Joins the parts of one sharded bake (read with read_shprt_part; `names` name them in messages,
// one per part, in the same order) into the whole: the parts, in any order, must have the same
// mesh (scene hash), transfer kind, layout, sampler, samples and seed, and their receiver ranges
// must tile [0, V) without a gap or an overlap. The rows are concatenated in receiver order, so
// the result equals a single-process bake with the same options bit for bit. Stats: rays and
// seconds summed (the parts' work), the largest peak memory, the devices listed. Throws
// Error(invalid_argument) naming the part and the problem.
ShprtFile merge_shprt_parts(std::vector<ShprtFile> parts, const std::vector<std::string>& names);

// Human-readable multi-line description for `shprt info`: scene, vertices, triangles, transfer
// kind, K with its bands (and whether the last band is full), sampler, samples, seed, precision,
// bake time split, rays/s, peak memory, file size, scene hash, tool version. Ends with '\n'.
std::string shprt_summary(const ShprtFile& file);

// An interreflected bake's bounces in words, as `shprt info` and the bake's own line print them:
// "converged: last relative change 3e-05 < tolerance 0.0001" (or "NOT converged: ... >= ..."), for
// a fixed count "a fixed count, not tested for convergence; largest relative change by bounce 3:
// 0.16" (information, not a failure), for none "the direct light only".
std::string describe_convergence(const InterreflectionInfo& ir);

}  // namespace shprt
