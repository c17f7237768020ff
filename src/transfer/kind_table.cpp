// The transfer kind table (transfer/kind_table.hpp): the one file that says, per kind, what its
// transfer is.
#include "shprt/transfer/kind_table.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"

#include <algorithm>
#include <array>
#include <string_view>
#include <vector>

namespace shprt {
namespace {

// One row per kind, in TransferKind's order (kind_row indexes it).
constexpr std::array<TransferKindRow, 4> kKindRows = {{
    {.kind = TransferKind::unshadowed,
     .name = "unshadowed",
     .channels = 1,
     .shape = TransferShape::vector,
     .traces_rays = false,
     .cosine = true,
     .direct_part = false,
     .interreflection = false,
     .whole_domain = false,
     .error_bounded = true,
     .default_K = 16},
    {.kind = TransferKind::shadowed,
     .name = "shadowed",
     .channels = 1,
     .shape = TransferShape::vector,
     .traces_rays = true,
     .cosine = true,
     .direct_part = false,
     .interreflection = false,
     .whole_domain = false,
     .error_bounded = true,
     .default_K = 16},
    {.kind = TransferKind::interreflected,
     .name = "interreflected",
     .channels = 3,
     .shape = TransferShape::vector,
     .traces_rays = true,
     .cosine = true,
     .direct_part = true,
     .interreflection = true,
     .whole_domain = true,
     .error_bounded = true,
     .default_K = 16},
    {.kind = TransferKind::glossy,
     .name = "glossy",
     .channels = 1,
     .shape = TransferShape::symmetric_matrix,
     .traces_rays = true,
     .cosine = false,
     .direct_part = false,
     .interreflection = false,
     .whole_domain = false,
     .error_bounded = false,
     .default_K = 25},
}};
static_assert([] {
    for (std::size_t i = 0; i < kKindRows.size(); ++i)
        if (static_cast<std::size_t>(kKindRows[i].kind) != i) return false;
    return true;
}());

constexpr Named<ShadingPass> kShadingPassNames[] = {
    {ShadingPass::vertex_vectors, "vertex_vectors"},
    {ShadingPass::vertex_matrices, "vertex_matrices"},
    {ShadingPass::texels, "texels"},
    {ShadingPass::none, "none"}};

}  // namespace

std::span<const TransferKindRow> kind_rows() { return kKindRows; }

const TransferKindRow& kind_row(TransferKind kind) {
    const auto i = static_cast<std::size_t>(kind);
    SHPRT_CHECK(i < kKindRows.size(), invalid_argument, "transfer kind {} is not a kind", i);
    return kKindRows[i];
}

const char* to_string(TransferKind kind) {
    const auto i = static_cast<std::size_t>(kind);
    return i < kKindRows.size() ? kKindRows[i].name : "?";
}

TransferKind parse_transfer_kind(const std::string& name) {
    for (const TransferKindRow& row : kKindRows)
        if (name == row.name) return row.kind;
    std::vector<std::string_view> names;
    for (const TransferKindRow& row : kKindRows) names.emplace_back(row.name);
    fail_unknown_name("transfer kind", name, names);
}

TransferLayout layout_for(TransferKind kind, int K, ReceiverDomain domain,
                          TransferEncoding encoding) {
    const TransferKindRow& row = kind_row(kind);
    TransferLayout layout;
    layout.domain = domain;
    layout.channels = row.channels;
    layout.K = K;
    layout.shape = row.shape;
    layout.encoding = encoding;
    return layout;
}

bool is_matrix(TransferShape shape) { return shape != TransferShape::vector; }

ShadingPass shading_pass(const TransferLayout& layout) {
    if (is_texel(layout)) return ShadingPass::texels;
    if (!is_matrix(layout)) return ShadingPass::vertex_vectors;
    return is_glossy_matrix(layout) ? ShadingPass::vertex_matrices : ShadingPass::none;
}

const char* to_string(ShadingPass pass) { return name_of(kShadingPassNames, pass); }

std::vector<std::size_t> receiver_shape(const TransferLayout& layout) {
    std::vector<std::size_t> shape;
    if (layout.channels != 1) shape.push_back(std::size_t(layout.channels));
    if (layout.shape == TransferShape::matrix) {
        shape.push_back(std::size_t(layout.K));
        shape.push_back(std::size_t(layout.K));
    } else {
        shape.push_back(layout.floats_per_channel());
    }
    return shape;
}

void unpack_symmetric(const float* packed, int K, int K_used, double* out) {
    std::size_t p = 0;
    for (int i = 0; i < K; ++i)
        for (int j = i; j < K; ++j, ++p) {
            if (i >= K_used || j >= K_used) continue;
            out[i * K_used + j] = out[j * K_used + i] = double(packed[p]);
        }
}

void unpack_matrix(const TransferLayout& layout, const float* channel, double* out) {
    const int K = layout.K;
    if (is_glossy_matrix(layout))
        unpack_symmetric(channel, K, K, out);
    else
        std::copy_n(channel, std::size_t(K) * std::size_t(K), out);
}

int basis_size_of(TransferShape shape, std::size_t floats) {
    TransferLayout layout;
    layout.shape = shape;
    for (int k = 1; k <= kMaxTransferK; ++k) {
        layout.K = k;
        const std::size_t n = layout.floats_per_channel();
        if (n == floats) return k;
        if (n > floats) break;
    }
    return -1;
}

}  // namespace shprt
