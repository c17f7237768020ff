// The transfer kinds as a closed set: one row per kind (TransferKind) saying what its transfer
// is — channels, shape, parts (a direct part T_0, interreflection info), whether its bake needs
// the whole domain at once, and how it is shaded — and the queries everything else asks instead
// of naming a kind. A new kind is its row here, its bake stage (bake/) and its shading pass.
//
//   kind            name (files, CLI)  channels  shape             rays  cos  T_0  bounces  whole K
//   unshadowed      "unshadowed"       1         vector            no    yes  no   no       no 16
//   shadowed        "shadowed"         1         vector            yes   yes  no   no       no 16
//   interreflected  "interreflected"   3         vector            yes   yes  yes  yes      yes 16
//   glossy          "glossy"           1         symmetric_matrix  yes   no   no   no       no 25
//
// cos: whether T carries max(0, n·ω). Without it (glossy) a bake weighs a direction 1 above the
// horizon and 0 below, and its local direction set is uniform on the hemisphere, not
// cosine-weighted (a cosine density would weigh each sample by 1/cos θ).
//
// What a row says is what a bake of that kind produces (bake_description: layout_for) and what a
// file of it must be (the reader checks a matrix kind's shape). A set may still differ from its
// row where something narrowed it on purpose (glossy matrices shaded as their diffuse transfer,
// an RGB shadowed set made from Python arrays): code that reads a set asks its layout
// (is_matrix, shading_pass); code that decides what to make asks the row.
#pragma once

#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace shprt {

// How a set is shaded (by the CPU and by the GL renderer): one pass per way.
enum class ShadingPass {
    vertex_vectors,   // E = Σ c_T·c_L per vertex (and per channel)
    vertex_matrices,  // per vertex M·L, then the BRDF's lobe (its rows or its CPCA code)
    texels,           // per texel of the atlas: vectors (or a matrix set's colours)
    none,             // no pass draws it (full K×K matrices)
};

struct TransferKindRow {
    TransferKind kind;
    const char* name;      // as .shprt files and the command line spell it
    int channels;          // 1 (grey), 3 (RGB: the albedo enters at the bounces)
    TransferShape shape;   // vector, or symmetric_matrix (glossy: packed upper triangle)
    bool traces_rays;      // its bake casts occlusion rays (unshadowed: the cosine alone)
    bool cosine;           // T carries max(0, n·ω) (else the hemisphere's indicator alone)
    bool direct_part;      // keeps T_0 beside the sum (TransferSet::direct; direct_only())
    bool interreflection;  // has bounces: TransferInfo::interreflection, the bounce options
    // Its bake needs every receiver of the mesh at once (the bounces couple them): no shards,
    // refinement, MPI units or caller-chosen receivers.
    bool whole_domain;
    bool error_bounded;  // an error-bounded bake (--target-error) exists for it
    int default_K;       // the bake's default basis size (BakeOptions::K)
};

// Every row, in TransferKind's order.
std::span<const TransferKindRow> kind_rows();
// The row of `kind`.
const TransferKindRow& kind_row(TransferKind kind);

// The layout a bake of `kind` produces: the row's channels and shape, basis size K (not checked
// here: TransferLayout::validate), the domain and encoding given.
TransferLayout layout_for(TransferKind kind, int K, ReceiverDomain domain = ReceiverDomain::vertex,
                          TransferEncoding encoding = TransferEncoding::f32);

// Whether a channel is a K×K matrix (full or symmetric) rather than a vector.
bool is_matrix(TransferShape shape);
inline bool is_matrix(const TransferLayout& layout) { return is_matrix(layout.shape); }
inline bool is_matrix(const TransferKindRow& row) { return is_matrix(row.shape); }
// Whether a channel is the packed symmetric K×K matrix the glossy passes shade (a full matrix is
// a matrix too, but no pass draws one: no bake makes them).
inline bool is_glossy_matrix(const TransferLayout& layout) {
    return layout.shape == TransferShape::symmetric_matrix;
}
// Whether the receivers are the texels of an atlas (TransferSet::texels) rather than vertices.
inline bool is_texel(ReceiverDomain domain) { return domain == ReceiverDomain::texel; }
inline bool is_texel(const TransferLayout& layout) { return is_texel(layout.domain); }

// The channel of a set of this layout that colour `colour` (0 R, 1 G, 2 B) is lit through: the
// colour's own for RGB transfer, the one channel for grey transfer.
inline int channel_for(const TransferLayout& layout, int colour) {
    return layout.channels == 3 ? colour : 0;
}
// The layout of a set's direct part T_0 (TransferSet::direct): one channel of the set's rows (the
// direct light is the same for R, G and B; the albedo enters only at the bounces).
inline TransferLayout direct_part_layout(TransferLayout layout) {
    layout.channels = 1;
    return layout;
}

// The pass that shades a set of this layout: texels for the texel domain, else vertex matrices
// for glossy matrices (with or without a CPCA code), vertex vectors for vectors, and none for
// full matrices.
ShadingPass shading_pass(const TransferLayout& layout);
const char* to_string(ShadingPass pass);  // "vertex_vectors", "vertex_matrices", "texels", "none"

// One receiver's row as an array's trailing axes (what Python's arrays are): the channel axis for
// more than one channel, then (K, K) for a full matrix, else the channel's floats (K for a
// vector, K(K+1)/2 for a packed symmetric matrix).
std::vector<std::size_t> receiver_shape(const TransferLayout& layout);

// Unpacks the packed upper triangle of a symmetric K×K matrix (row by row) into its top-left
// K'×K' block, row-major, in `out` (K'² values).
void unpack_symmetric(const float* packed, int K, int K_used, double* out);
// One matrix channel of this layout (a full K×K matrix row-major, or a packed symmetric one) as
// the full K×K matrix, row-major, in `out` (K² values).
void unpack_matrix(const TransferLayout& layout, const float* channel, double* out);

// The basis size K of a matrix channel of `floats` floats in `shape` (symmetric: K(K+1)/2 = floats;
// full: K² = floats; vector: floats), or −1 when no K gives exactly that many.
int basis_size_of(TransferShape shape, std::size_t floats);

}  // namespace shprt
