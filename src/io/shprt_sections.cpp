// The .shprt section table (shprt_sections.hpp).
#include "io/shprt_sections.hpp"

#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace shprt::detail {
namespace {

// Accessors of one std::vector member of the mesh, or of the transfer's coefficients; counts are
// in scalar elements (a Vec3f is 3 floats, a triangle 3 indices).
template <auto Member>
struct MeshArray {
    using Vector = std::remove_reference_t<decltype(std::declval<Mesh&>().*Member)>;
    static constexpr std::uint64_t kScalars =
        sizeof(typename Vector::value_type) / sizeof(std::uint32_t);
    static_assert(sizeof(typename Vector::value_type) % sizeof(std::uint32_t) == 0);
    static const void* data(const Mesh& m, const TransferSet&) { return (m.*Member).data(); }
    static std::uint64_t count(const Mesh& m, const TransferSet&) {
        return (m.*Member).size() * kScalars;
    }
    static void* resize(Mesh& m, TransferSet&, std::uint64_t n) {
        (m.*Member).resize(static_cast<std::size_t>(n / kScalars));
        return (m.*Member).data();
    }
};

struct TransferArray {
    static const void* data(const Mesh&, const TransferSet& t) { return t.coeffs.data(); }
    static std::uint64_t count(const Mesh&, const TransferSet& t) { return t.coeffs.size(); }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        t.coeffs.resize(static_cast<std::size_t>(n));
        return t.coeffs.data();
    }
};

// The direct part T_0 of an interreflected transfer (TransferSet::direct).
struct DirectArray {
    static const void* data(const Mesh&, const TransferSet& t) { return t.direct.data(); }
    static std::uint64_t count(const Mesh&, const TransferSet& t) { return t.direct.size(); }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        t.direct.resize(static_cast<std::size_t>(n));
        return t.direct.data();
    }
};

// One std::vector member of a part of the transfer: the CPCA code's arrays (TransferSet::cpca),
// the probes' (TransferSet::probes).
template <auto Part, auto Member>
struct PartArray {
    static const void* data(const Mesh&, const TransferSet& t) { return (t.*Part.*Member).data(); }
    static std::uint64_t count(const Mesh&, const TransferSet& t) {
        return (t.*Part.*Member).size();
    }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        (t.*Part.*Member).resize(static_cast<std::size_t>(n));
        return (t.*Part.*Member).data();
    }
};
template <auto Member>
using CpcaArray = PartArray<&TransferSet::cpca, Member>;
template <auto Member>
using ProbeArray = PartArray<&TransferSet::probes, Member>;

// One std::vector member of the transfer set itself: an error-bounded bake's per-receiver
// estimates (TransferSet::receiver_samples, receiver_error).
template <auto Member>
struct SetArray {
    static const void* data(const Mesh&, const TransferSet& t) { return (t.*Member).data(); }
    static std::uint64_t count(const Mesh&, const TransferSet& t) { return (t.*Member).size(); }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        (t.*Member).resize(static_cast<std::size_t>(n));
        return (t.*Member).data();
    }
};

// One std::vector member of the probes' CPCA code (ProbeGrid::cpca).
template <auto Member>
struct ProbeCpcaArray {
    static const void* data(const Mesh&, const TransferSet& t) {
        return (t.probes.cpca.*Member).data();
    }
    static std::uint64_t count(const Mesh&, const TransferSet& t) {
        return (t.probes.cpca.*Member).size();
    }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        (t.probes.cpca.*Member).resize(static_cast<std::size_t>(n));
        return (t.probes.cpca.*Member).data();
    }
};

// The mesh's UVs, stored with texel-domain transfer only (the texels were rasterised in them).
struct UvArray {
    static bool stored(const TransferSet& t) { return is_texel(t.layout); }
    static const void* data(const Mesh& m, const TransferSet&) { return m.uvs.data(); }
    static std::uint64_t count(const Mesh& m, const TransferSet& t) {
        return stored(t) ? m.uvs.size() * 2 : 0;
    }
    static void* resize(Mesh& m, TransferSet&, std::uint64_t n) {
        m.uvs.resize(static_cast<std::size_t>(n / 2));
        return m.uvs.data();
    }
};

// Which texel each receiver of a texel-domain transfer is (TexelAtlas::texel).
struct TexelIndexArray {
    static const void* data(const Mesh&, const TransferSet& t) { return t.texels.texel.data(); }
    static std::uint64_t count(const Mesh&, const TransferSet& t) { return t.texels.texel.size(); }
    static void* resize(Mesh&, TransferSet& t, std::uint64_t n) {
        t.texels.texel.resize(static_cast<std::size_t>(n));
        return t.texels.texel.data();
    }
};

// When a row applies (SectionRule::applies), from the counts the metadata or the writer's parts
// give: every file; the transfer's rows unless a CPCA code stands for them, the code's arrays when
// there is one; the probes' arrays when there are probes: their matrices, or their code's arrays.
bool always(const SectionCounts&) { return true; }
bool with_rows(const SectionCounts& c) { return c.clusters == 0; }
bool with_code(const SectionCounts& c) { return c.clusters > 0; }
bool with_probes(const SectionCounts& c) { return c.probes > 0; }
bool with_probe_matrices(const SectionCounts& c) { return with_probes(c) && c.probe_clusters == 0; }
bool with_probe_code(const SectionCounts& c) { return with_probes(c) && c.probe_clusters > 0; }

template <class A>
constexpr SectionRule rule(const char* name, SectionType type, SectionRows rows, std::uint64_t cols,
                           bool required, bool (*applies)(const SectionCounts&) = always,
                           std::uint32_t since = 1) {
    return {name, type, rows, cols, required, applies, since, &A::data, &A::count, &A::resize};
}

using S = SectionType;
using R = SectionRows;
constexpr bool kRequired = true, kOptional = false;
constexpr std::uint32_t kCodeVersion = kShprtCpcaFormatVersion;  // a CPCA code's sections

const std::array kRules = {
    rule<MeshArray<&Mesh::positions>>("positions", S::f32, R::vertices, 3, kRequired),
    rule<MeshArray<&Mesh::normals>>("normals", S::f32, R::vertices, 3, kRequired),
    rule<MeshArray<&Mesh::albedo>>("albedo", S::f32, R::vertices, 3, kRequired),
    rule<MeshArray<&Mesh::triangles>>("triangles", S::u32, R::triangles, 3, kRequired),
    rule<MeshArray<&Mesh::source_vertex>>("source_vertex", S::u32, R::vertices, 1, kOptional),
    // Adaptive refinement (bake/refine.hpp): the two ends of the edge each vertex split, or
    // 0xFFFFFFFF twice for a vertex of the scene as loaded.
    rule<MeshArray<&Mesh::parents>>("vertex_parents", S::u32, R::vertices, 2, kOptional),
    // Per vertex, its material's BRDF in metadata scene.brdfs (or 0xFFFFFFFF: none).
    rule<MeshArray<&Mesh::brdf_index>>("brdf_index", S::u32, R::vertices, 1, kOptional),
    // Texel domain (docs/texels.md): the mesh's UVs and each receiver's texel.
    rule<UvArray>("uvs", S::f32, R::vertices, 2, kOptional),
    rule<TexelIndexArray>("texel_index", S::u32, R::receivers, 1, kOptional),
    // Transfer probes (docs/probes.md): per probe, channels K×K matrices (row-major, [out][in]),
    // and its validity (1, or 0 inside geometry). Metadata "probes" describes the grid.
    rule<ProbeArray<&ProbeGrid::matrices>>("probe_matrices", S::f32, R::probes,
                                           SectionRule::kProbeFloats, kRequired,
                                           with_probe_matrices),
    rule<ProbeArray<&ProbeGrid::valid>>("probe_valid", S::u8, R::probes, 1, kRequired, with_probes),
    // Probes stored as a CPCA code (`shprt compress --probe-cpca`) instead of "probe_matrices":
    // per valid probe its cluster and weights, per cluster the mean and basis (float32).
    rule<ProbeCpcaArray<&CpcaCode::cluster>>("probe_cpca_cluster", S::u32, R::valid_probes, 1,
                                             kRequired, with_probe_code),
    rule<ProbeCpcaArray<&CpcaCode::weights>>("probe_cpca_weights", S::f32, R::valid_probes,
                                             SectionRule::kProbeVectors, kRequired,
                                             with_probe_code),
    rule<ProbeCpcaArray<&CpcaCode::means>>("probe_cpca_means", S::f32, R::probe_clusters,
                                           SectionRule::kProbeFloats, kRequired, with_probe_code),
    rule<ProbeCpcaArray<&CpcaCode::basis>>("probe_cpca_basis", S::f32, R::probe_basis_rows,
                                           SectionRule::kProbeFloats, kRequired, with_probe_code),
    // An error-bounded bake (docs/sampling.md, "Error-bounded bakes"): each receiver's
    // directions and estimated error. Metadata "target_error" is the bound.
    rule<SetArray<&TransferSet::receiver_samples>>("receiver_samples", S::u32, R::receivers, 1,
                                                   kOptional),
    rule<SetArray<&TransferSet::receiver_error>>("receiver_error", S::f32, R::receivers, 1,
                                                 kOptional),
    // Interreflected transfer's direct part, one channel per receiver: before "transfer", which
    // stays last (a streamed bake writes it in place).
    rule<DirectArray>("transfer_direct", S::transfer, R::receivers, SectionRule::kPerChannel,
                      kOptional),
    // A CPCA file (format version 3) stores its code instead of "transfer": each receiver's
    // cluster and weights, each cluster's mean and basis (transfer/cpca.hpp).
    rule<CpcaArray<&CpcaCode::cluster>>("cpca_cluster", S::u32, R::receivers, 1, kRequired,
                                        with_code, kCodeVersion),
    rule<CpcaArray<&CpcaCode::weights>>("cpca_weights", S::transfer, R::receivers,
                                        SectionRule::kVectors, kRequired, with_code, kCodeVersion),
    rule<CpcaArray<&CpcaCode::means>>("cpca_means", S::transfer, R::clusters, 0, kRequired,
                                      with_code, kCodeVersion),
    rule<CpcaArray<&CpcaCode::basis>>("cpca_basis", S::transfer, R::basis_rows, 0, kRequired,
                                      with_code, kCodeVersion),
    rule<TransferArray>("transfer", S::transfer, R::receivers, 0, kRequired, with_rows),
};

}  // namespace

SectionCounts section_counts(const Mesh& mesh, const TransferLayout& layout, std::uint64_t rows,
                             const TransferSet& parts) {
    const auto whole = [](int n) { return std::uint64_t(std::max(n, 0)); };
    const ProbeGrid& probes = parts.probes;
    SectionCounts c;
    c.vertices = mesh.positions.size();
    c.triangles = mesh.triangles.size();
    c.receivers = rows;
    c.layout = layout;
    c.clusters = whole(parts.cpca.clusters);
    c.vectors = whole(parts.cpca.vectors);
    c.probes = probes.count();
    c.probe_floats = whole(probes.channels) * whole(probes.K) * whole(probes.K);
    c.probes_valid = probes.cpca.cluster.size();
    c.probe_clusters = whole(probes.cpca.clusters);
    c.probe_vectors = whole(probes.cpca.vectors);
    return c;
}

std::string SectionRule::dtype(const TransferLayout& layout) const {
    switch (type) {
        case SectionType::f32:
            return "float32";
        case SectionType::u32:
            return "uint32";
        case SectionType::u8:
            return "uint8";
        case SectionType::transfer:
            break;
    }
    return to_string(layout.encoding);
}

std::uint64_t SectionRule::element_size(const TransferLayout& layout) const {
    if (type == SectionType::u8) return 1;
    return type == SectionType::transfer ? bytes_per_value(layout.encoding) : 4;
}

std::uint64_t SectionRule::row_count(const SectionCounts& counts) const {
    switch (rows) {
        case SectionRows::vertices:
            return counts.vertices;
        case SectionRows::triangles:
            return counts.triangles;
        case SectionRows::clusters:
            return counts.clusters;
        case SectionRows::basis_rows:
            return counts.clusters * counts.vectors;
        case SectionRows::probes:
            return counts.probes;
        case SectionRows::valid_probes:
            return counts.probes_valid;
        case SectionRows::probe_clusters:
            return counts.probe_clusters;
        case SectionRows::probe_basis_rows:
            return counts.probe_clusters * counts.probe_vectors;
        case SectionRows::receivers:
            break;
    }
    return counts.receivers;
}

std::span<const SectionRule> section_rules() { return kRules; }

}  // namespace shprt::detail
