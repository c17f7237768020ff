// The transfer layout and the names of its parts (transfer/transfer.hpp).
#include "shprt/transfer/transfer.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>

namespace shprt {

void add_stats(BakeStats& total, const BakeStats& part) {
    total.seconds_bvh += part.seconds_bvh;
    total.seconds_trace += part.seconds_trace;
    total.seconds_project += part.seconds_project;
    total.seconds_total += part.seconds_total;
    total.rays_cast += part.rays_cast;
    total.peak_bytes_host = std::max(total.peak_bytes_host, part.peak_bytes_host);
    total.peak_bytes_device = std::max(total.peak_bytes_device, part.peak_bytes_device);
    total.seconds_operator += part.seconds_operator;
    total.seconds_bounces += part.seconds_bounces;
    total.operator_bytes_spilled += part.operator_bytes_spilled;
    const std::string& name = part.device_name;
    std::size_t at = 0;
    while ((at = total.device_name.find(name, at)) != std::string::npos) {
        const std::size_t end = at + name.size();
        const bool whole =
            (at == 0 || total.device_name.compare(at - 2, 2, "; ") == 0) &&
            (end == total.device_name.size() || total.device_name.compare(end, 2, "; ") == 0);
        if (whole) return;
        at = end;
    }
    total.device_name += (total.device_name.empty() ? "" : "; ") + name;
}

namespace {

constexpr Named<ReceiverDomain> kReceiverDomainNames[] = {{ReceiverDomain::vertex, "vertex"},
                                                          {ReceiverDomain::texel, "texel"}};
constexpr Named<TransferShape> kTransferShapeNames[] = {
    {TransferShape::vector, "vector"},
    {TransferShape::matrix, "matrix"},
    {TransferShape::symmetric_matrix, "symmetric_matrix"},
};
constexpr Named<TransferEncoding> kTransferEncodingNames[] = {{TransferEncoding::f32, "float32"},
                                                              {TransferEncoding::f16, "float16"}};

}  // namespace

const char* to_string(ReceiverDomain domain) { return name_of(kReceiverDomainNames, domain); }
ReceiverDomain parse_receiver_domain(const std::string& name) {
    return parse_named(kReceiverDomainNames, name, "receiver domain");
}
const char* to_string(TransferShape shape) { return name_of(kTransferShapeNames, shape); }
TransferShape parse_transfer_shape(const std::string& name) {
    return parse_named(kTransferShapeNames, name, "transfer shape");
}
const char* to_string(TransferEncoding encoding) {
    return name_of(kTransferEncodingNames, encoding);
}
TransferEncoding parse_transfer_encoding(const std::string& name) {
    return parse_named(kTransferEncodingNames, name, "encoding");
}

std::size_t TransferLayout::floats_per_channel() const {
    const std::size_t k = K > 0 ? std::size_t(K) : 0;
    switch (shape) {
        case TransferShape::vector:
            return k;
        case TransferShape::matrix:
            return k * k;
        case TransferShape::symmetric_matrix:
            return k * (k + 1) / 2;
    }
    return k;
}

void TransferLayout::validate() const {
    SHPRT_CHECK(K >= 1 && K <= kMaxTransferK, invalid_argument,
                "transfer basis size K = {} is outside [1, {}]", K, kMaxTransferK);
    SHPRT_CHECK(channels == 1 || channels == 3, invalid_argument,
                "transfer has {} channels (expected 1 or 3)", channels);
}

const char* samples_refusal(TransferKind kind, int samples) {
    if (samples < 0) return "a sample count cannot be negative";
    if (samples == 0 && kind_row(kind).traces_rays)
        return "only unshadowed transfer has a closed form: a transfer of any other kind is baked "
               "from at least one direction per receiver";
    return nullptr;
}

TransferSet TransferSet::zeros(const TransferInfo& info, std::size_t receivers) {
    info.layout.validate();
    TransferSet t;
    static_cast<TransferInfo&>(t) = info;
    t.coeffs.assign(info.layout.floats(receivers), 0.0f);
    return t;
}

TransferSet TransferSet::direct_only() const {
    SHPRT_CHECK(!direct.empty(), invalid_argument,
                "the transfer has no direct part (only interreflected transfer keeps one)");
    TransferSet out;
    static_cast<TransferInfo&>(out) = *this;
    out.kind = TransferKind::shadowed;
    out.layout = direct_part_layout(layout);
    out.interreflection = {};
    out.coeffs = direct;
    return out;
}

std::size_t TransferSet::receiver_total(const Mesh& mesh) const {
    return is_texel(layout) ? texels.texel.size() : mesh.vertex_count();
}

TexelSamples atlas_texel_samples(const Mesh& mesh, const TexelAtlas& atlas) {
    TexelSamples samples = rasterize_texels(mesh, atlas.width, atlas.height, atlas.uv_set);
    SHPRT_CHECK(samples.texel == atlas.texel, format,
                "{}: the texels of its UVs at {}x{} ({}) are not the file's ({})", mesh.source,
                atlas.width, atlas.height, samples.count(), atlas.texel.size());
    return samples;
}

std::vector<Vec3f> receiver_normals(const Mesh& mesh, const TransferSet& transfer) {
    if (!is_texel(transfer.layout)) return mesh.normals;
    return atlas_texel_samples(mesh, transfer.texels).normals;
}

void TransferSet::check(const Mesh& mesh) const {
    layout.validate();
    const std::size_t V = receiver_total(mesh);
    SHPRT_CHECK(coeffs.size() == layout.floats(V), invalid_argument,
                "transfer holds {} floats, expected {} {}s × {} channels × {} = {}", coeffs.size(),
                V, to_string(layout.domain), layout.channels, layout.floats_per_channel(),
                layout.floats(V));
    check_rows(mesh, 0);
}

void TransferSet::check_rows(const Mesh& mesh, std::size_t first) const {
    layout.validate();
    const std::size_t row = layout.floats_per_receiver();
    SHPRT_CHECK(!coeffs.empty() && coeffs.size() % row == 0, invalid_argument,
                "transfer holds {} floats, not a whole number of rows of {} ({} channels × {})",
                coeffs.size(), row, layout.channels, layout.floats_per_channel());
    if (is_texel(layout)) {
        SHPRT_CHECK(!mesh.uvs.empty(), invalid_argument,
                    "texel transfer of a mesh without texture coordinates");
        const std::uint64_t image = std::uint64_t(texels.width) * std::uint64_t(texels.height);
        SHPRT_CHECK(texels.width >= 1 && texels.height >= 1 && !texels.texel.empty(),
                    invalid_argument, "texel transfer without its atlas ({}x{}, {} texels)",
                    texels.width, texels.height, texels.texel.size());
        for (std::size_t i = 0; i < texels.texel.size(); ++i)
            SHPRT_CHECK(
                texels.texel[i] < image && (i == 0 || texels.texel[i] > texels.texel[i - 1]),
                invalid_argument,
                "texel atlas entry {} ({}) is out of order or outside the {}x{} image", i,
                texels.texel[i], texels.width, texels.height);
    } else {
        SHPRT_CHECK(texels.empty(), invalid_argument, "vertex transfer with a texel atlas");
    }
    check_range(mesh, layout, first, coeffs.size() / row, receiver_total(mesh));
    SHPRT_CHECK(
        direct.empty() || direct.size() == coeffs.size() / row * layout.floats_per_channel(),
        invalid_argument, "direct transfer holds {} floats, expected {} rows × {}", direct.size(),
        coeffs.size() / row, layout.floats_per_channel());
}

void TransferSet::check_range(const Mesh& mesh, const TransferLayout& layout, std::size_t first,
                              std::size_t count, std::size_t total) {
    layout.validate();
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(count >= 1 && first <= total && count <= total - first, invalid_argument,
                "transfer rows of receivers [{}, {}) outside the mesh's {} {}s (or empty)", first,
                first + count, total, to_string(layout.domain));
    SHPRT_CHECK(mesh.normals.size() == V && mesh.albedo.size() == V, invalid_argument,
                "mesh {} has {} vertices but {} normals and {} albedo values", mesh.source, V,
                mesh.normals.size(), mesh.albedo.size());
}

}  // namespace shprt
