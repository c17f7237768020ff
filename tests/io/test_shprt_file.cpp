// .shprt write/read: bit-exact float32 round trip, float16 within half precision, the metadata
// fields, the mesh hash, reproducible output, writer input checks and atomic writes.
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/half.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/transfer/cpca.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <random>

namespace shprt {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A small grid mesh with deterministic pseudo-random attributes and transfer, plus values that
// would expose a lossy float32 path (subnormals, -0, large magnitudes).
struct Scene {
    Mesh mesh;
    TransferSet transfer;
};

Scene make_scene(int n, int K, int channels, bool with_source_vertex, std::uint32_t seed = 1) {
    Scene s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            s.mesh.positions.push_back(
                {0.1f * float(i), std::sin(0.3f * float(i + j)), 0.1f * float(j)});
            s.mesh.normals.push_back(normalize(Vec3f{normal(rng), 1.0f + unit(rng), normal(rng)}));
            s.mesh.albedo.push_back({unit(rng), unit(rng), unit(rng)});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const auto v = std::uint32_t(j * n + i), w = std::uint32_t(n);
            s.mesh.triangles.push_back({v, v + w, v + 1});
            s.mesh.triangles.push_back({v + 1, v + w, v + w + 1});
        }
    if (with_source_vertex)
        for (int v = 0; v < n * n; ++v)
            s.mesh.source_vertex.push_back(std::uint32_t(n * n - 1 - v));
    s.mesh.source = "builtin:test-grid";

    TransferSet& t = s.transfer;
    t.kind = TransferKind::unshadowed;
    t.layout.K = K;
    t.layout.channels = channels;
    t.coeffs.resize(std::size_t(n) * n * channels * K);
    for (float& c : t.coeffs) c = normal(rng);
    if (t.coeffs.size() >= 3) {
        t.coeffs[0] = 1e-40f;  // float32 subnormal
        t.coeffs[1] = -0.0f;
        t.coeffs[2] = 12345.678f;
    }
    t.sampler = SamplerKind::fibonacci;
    t.samples = 4096;
    t.seed = 0x8000000000000005ull;  // above 2^63: must survive JSON
    t.stats.seconds_bvh = 0.012;
    t.stats.seconds_trace = 0.25;
    t.stats.seconds_project = 0.0625;
    t.stats.seconds_total = 0.33;
    t.stats.rays_cast = 123456789012ull;
    t.stats.peak_bytes_host = 50u << 20;
    t.stats.peak_bytes_device = 0;
    t.stats.device_name = "cpu: 2 threads";
    return s;
}

class IoShprtFile : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                fmt::format("shprt_io_file_{}_{}", ::getpid(),
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    std::vector<std::string> dir_entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(m_dir))
            names.push_back(e.path().filename().string());
        return names;
    }

    fs::path m_dir;
};

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

TEST_F(IoShprtFile, RoundTripFloat32IsBitExact) {
    for (const bool source_vertex : {false, true})
        for (const int channels : {1, 3}) {
            const Scene s = make_scene(7, 32, channels, source_vertex);
            const std::string file = path("a.shprt");
            write_shprt(file, s.mesh, s.transfer);
            const ShprtFile r = read_shprt(file);
            EXPECT_TRUE(same_bytes(r.mesh.positions, s.mesh.positions));
            EXPECT_TRUE(same_bytes(r.mesh.normals, s.mesh.normals));
            EXPECT_TRUE(same_bytes(r.mesh.albedo, s.mesh.albedo));
            EXPECT_TRUE(same_bytes(r.mesh.triangles, s.mesh.triangles));
            EXPECT_TRUE(same_bytes(r.mesh.source_vertex, s.mesh.source_vertex));
            EXPECT_TRUE(same_bytes(r.transfer.coeffs, s.transfer.coeffs));
            EXPECT_TRUE(std::signbit(r.transfer.coeffs[1]));
            EXPECT_EQ(r.mesh.source, s.mesh.source);
            EXPECT_EQ(r.transfer.kind, s.transfer.kind);
            EXPECT_EQ(r.transfer.layout.K, 32);
            EXPECT_EQ(r.transfer.layout.channels, channels);
            EXPECT_EQ(r.transfer.receiver_count(), 49u);
            EXPECT_EQ(r.transfer.sampler, SamplerKind::fibonacci);
            EXPECT_EQ(r.transfer.samples, 4096);
            EXPECT_EQ(r.transfer.seed, 0x8000000000000005ull);
            const BakeStats& st = r.transfer.stats;
            EXPECT_EQ(st.seconds_bvh, 0.012);
            EXPECT_EQ(st.seconds_trace, 0.25);
            EXPECT_EQ(st.seconds_project, 0.0625);
            EXPECT_EQ(st.seconds_total, 0.33);
            EXPECT_EQ(st.rays_cast, 123456789012ull);
            EXPECT_EQ(st.peak_bytes_host, 50u << 20);
            EXPECT_EQ(st.device_name, "cpu: 2 threads");
            EXPECT_EQ(r.metadata_json,
                      read_file(file).substr(kShprtHeaderSize, r.metadata_json.size()));
        }
}

// A probe grid of 3×2×2 probes with `channels` K×K matrices of noise, probe 5 invalid (zero).
ProbeGrid noise_probes(int K, int channels) {
    ProbeGrid g;
    g.origin = {-1.5f, 0.25f, 0.1f};
    g.spacing = {0.5f, 0.75f, 1.0f / 3.0f};  // not exact in binary or decimal
    g.counts = {3, 2, 2};
    g.K = K;
    g.channels = channels;
    g.valid.assign(g.count(), 1);
    g.valid[5] = 0;
    g.matrices.resize(g.count() * std::size_t(channels * K * K));
    std::mt19937 rng(5);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (float& v : g.matrices) v = normal(rng);
    std::fill_n(g.matrices.begin() + 5 * channels * K * K, channels * K * K, 0.0f);
    return g;
}

TEST_F(IoShprtFile, ProbesRoundTripBitExactBesideEveryEncoding) {
    for (const auto encoding : {TransferEncoding::f32, TransferEncoding::f16})
        for (const int channels : {1, 3}) {
            Scene s = make_scene(5, 9, channels, false);
            s.transfer.layout.encoding = encoding;
            for (float& c : s.transfer.coeffs) c = std::clamp(c, -100.0f, 100.0f);
            s.transfer.probes = noise_probes(9, channels);
            const std::string file = path("p.shprt");
            write_shprt(file, s.mesh, s.transfer);
            const ShprtFile r = read_shprt(file);
            EXPECT_TRUE(r.transfer.probes == s.transfer.probes);  // float32 whatever the rows
            EXPECT_TRUE(same_bytes(r.transfer.probes.matrices, s.transfer.probes.matrices));
            const nlohmann::json meta = nlohmann::json::parse(r.metadata_json);
            EXPECT_EQ(meta["probes"]["valid"], 11);
            EXPECT_EQ(meta["probes"]["counts"], nlohmann::json::array({3, 2, 2}));
            EXPECT_NE(
                shprt_summary(r).find("probes       3x2x2 = 12 (11 valid), spacing 0.5 x 0.75 x "
                                      "0.333 m"),
                std::string::npos)
                << shprt_summary(r);
        }
    // Without probes: no metadata, no sections, and an empty grid read back.
    const Scene s = make_scene(5, 9, 1, false);
    write_shprt(path("n.shprt"), s.mesh, s.transfer);
    const ShprtFile r = read_shprt(path("n.shprt"));
    EXPECT_TRUE(r.transfer.probes.empty());
    EXPECT_EQ(r.metadata_json.find("probe"), std::string::npos);
}

// Probes stored as a CPCA code (`shprt compress --probe-cpca`): the code's sections instead of
// "probe_matrices", the code read back bit for bit, the matrices rebuilt from it exactly as
// compress_probes rebuilt them, invalid probes zero, and metadata.probes.cpca described.
TEST_F(IoShprtFile, ProbesStoredAsACpcaCodeRoundTrip) {
    for (const int channels : {1, 3}) {
        Scene s = make_scene(5, 9, channels, false);
        CpcaOptions options;
        options.clusters = 3;
        options.vectors = 2;
        const ProbeCpcaResult c = compress_probes(noise_probes(9, channels), options);
        s.transfer.probes = c.compressed;
        ASSERT_EQ(s.transfer.probes.cpca.cluster.size(), 11u);  // the valid probes
        const std::string file = path("pc.shprt");
        write_shprt(file, s.mesh, s.transfer);
        const ShprtFile r = read_shprt(file);
        EXPECT_TRUE(r.transfer.probes == s.transfer.probes);
        EXPECT_TRUE(same_bytes(r.transfer.probes.matrices, c.compressed.matrices));
        for (int k = 0; k < channels * 81; ++k)
            EXPECT_EQ(r.transfer.probes.matrices[5 * channels * 81 + k], 0.0f);
        const nlohmann::json meta = nlohmann::json::parse(r.metadata_json);
        EXPECT_EQ(meta["probes"]["cpca"]["clusters"], 3);
        EXPECT_EQ(meta["probes"]["cpca"]["vectors"], 2);
        std::vector<std::string> names;
        for (const auto& section : meta["sections"]) names.push_back(section["name"]);
        EXPECT_EQ(std::count(names.begin(), names.end(), "probe_matrices"), 0);
        EXPECT_EQ(std::count(names.begin(), names.end(), "probe_cpca_basis"), 1);
        EXPECT_NE(shprt_summary(r).find("; CPCA 3 clusters x 2 vectors"), std::string::npos)
            << shprt_summary(r);
        // The code's sections are smaller than the matrices they stand for (the whole file is
        // not, at this size: the four sections' metadata entries weigh as much).
        std::uint64_t code_bytes = 0;
        for (const auto& section : meta["sections"])
            if (section["name"].get<std::string>().starts_with("probe_cpca_"))
                code_bytes += section["length"].get<std::uint64_t>();
        EXPECT_LT(code_bytes, 12u * std::uint64_t(channels) * 81u * 4u);
    }
}

TEST_F(IoShprtFile, WriterRefusesInconsistentProbes) {
    Scene s = make_scene(5, 9, 1, false);
    s.transfer.probes = noise_probes(9, 1);
    s.transfer.probes.valid.pop_back();
    EXPECT_THROW(write_shprt(path("p.shprt"), s.mesh, s.transfer), Error);
    s.transfer.probes = noise_probes(9, 1);
    s.transfer.probes.matrices[7] = std::nanf("");
    try {
        write_shprt(path("p.shprt"), s.mesh, s.transfer);
        ADD_FAILURE() << "a NaN probe matrix was written";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("probe matrix value 7 is not finite"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(dir_entries().empty());
}

TEST_F(IoShprtFile, MaterialBrdfsRoundTripAndAreDescribed) {
    Scene s = make_scene(4, 9, 1, false);
    s.mesh.brdfs = {Brdf{BrdfModel::blinn_phong, 0.1 + 0.2}, Brdf{BrdfModel::ggx, 0.05}};
    for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v)
        s.mesh.brdf_index.push_back(v < 3 ? Mesh::kNoBrdf : std::uint32_t(v % 2));
    const std::string file = path("m.shprt");
    write_shprt(file, s.mesh, s.transfer);
    const ShprtFile r = read_shprt(file);
    EXPECT_EQ(r.mesh.brdfs, s.mesh.brdfs);  // 0.1 + 0.2 survives the text spec bit for bit
    EXPECT_EQ(r.mesh.brdf_index, s.mesh.brdf_index);
    EXPECT_EQ(format_mesh_hash(mesh_hash(r.mesh)),
              format_mesh_hash(mesh_hash(make_scene(4, 9, 1, false).mesh)))
        << "BRDFs are not part of the scene hash";
    EXPECT_NE(shprt_summary(r).find("brdfs        blinn:0.30000000000000004 (6 vertices), ggx:0.05 "
                                    "(7 vertices), none (3 vertices) (from the materials)"),
              std::string::npos)
        << shprt_summary(r);
    // Without BRDFs the file has neither the section nor the list.
    const std::string plain = path("p.shprt");
    write_shprt(plain, make_scene(4, 9, 1, false).mesh, s.transfer);
    EXPECT_EQ(read_file(plain).find("brdf"), std::string::npos);
    // The writer refuses an index past the list, and an index without a list.
    Mesh bad = s.mesh;
    bad.brdf_index[5] = 2;
    EXPECT_THROW(write_shprt(path("b.shprt"), bad, s.transfer), Error);
    bad.brdfs.clear();
    bad.brdf_index.assign(bad.vertex_count(), Mesh::kNoBrdf);
    EXPECT_THROW(write_shprt(path("b.shprt"), bad, s.transfer), Error);
    EXPECT_FALSE(fs::exists(path("b.shprt")));
}

TEST_F(IoShprtFile, RoundTripFloat16WithinHalfPrecision) {
    // Transfer coefficients are O(1); the largest here is 12345.678 (still within float16).
    constexpr float kHalfRelativeError = 1.0f / 2048.0f;   // 2^-11, round to nearest
    constexpr float kHalfSubnormalError = 2.98023224e-8f;  // 2^-25: half the subnormal spacing
    const Scene s = make_scene(9, 16, 3, true);
    TransferSet half = s.transfer;
    half.layout.encoding = TransferEncoding::f16;
    write_shprt(path("h.shprt"), s.mesh, half);
    write_shprt(path("f.shprt"), s.mesh, s.transfer);
    const ShprtFile r = read_shprt(path("h.shprt"));
    ASSERT_EQ(r.transfer.coeffs.size(), s.transfer.coeffs.size());
    for (std::size_t i = 0; i < r.transfer.coeffs.size(); ++i) {
        const float c = s.transfer.coeffs[i], got = r.transfer.coeffs[i];
        EXPECT_EQ(got, half_to_float(float_to_half(c))) << i;
        EXPECT_LE(std::fabs(got - c), kHalfRelativeError * std::fabs(c) + kHalfSubnormalError) << i;
    }
    // The mesh stays float32 and exact.
    EXPECT_TRUE(same_bytes(r.mesh.positions, s.mesh.positions));
    const Json meta = Json::parse(r.metadata_json);
    EXPECT_EQ(meta["precision"], "float16");
    // Half the transfer bytes: the files differ by the coefficient count · 2 bytes (± padding).
    const auto coeff_bytes = std::int64_t(s.transfer.coeffs.size()) * 2;
    const auto diff =
        std::int64_t(fs::file_size(path("f.shprt"))) - std::int64_t(fs::file_size(path("h.shprt")));
    EXPECT_NEAR(double(diff), double(coeff_bytes), double(kShprtAlignment));
}

TEST_F(IoShprtFile, MetadataHoldsEveryField) {
    for (const int K : {32, 36}) {
        const Scene s = make_scene(5, K, 1, true);
        const std::string file = path("m.shprt");
        WriteOptions options;
        options.extra_metadata_json = R"({"command_line": "shprt bake builtin:room -o m.shprt",
                                          "stats": {"seconds_load": 0.5}})";
        write_shprt(file, s.mesh, s.transfer, options);
        const ShprtFile r = read_shprt(file);
        const Json m = Json::parse(r.metadata_json);
        EXPECT_EQ(m["format"], "shprt");
        EXPECT_EQ(m["format_version"], kShprtFormatVersion);
        EXPECT_EQ(m["tool_version"], SHPRT_VERSION_STRING);
        EXPECT_EQ(m["convention"]["basis"],
                  "real SH, Condon\u2013Shortley phase, index l(l+1)+m, theta from +Z, phi from +X "
                  "toward +Y");
        EXPECT_EQ(m["K"], K);
        EXPECT_EQ(m["bands"], 6);  // 32 and 36 both need l = 0..5
        EXPECT_EQ(m["last_band_full"], K == 36);
        EXPECT_EQ(m["channels"], 1);
        EXPECT_EQ(m["transfer_kind"], "unshadowed");
        EXPECT_EQ(m["sampler"], "fibonacci");
        EXPECT_EQ(m["samples"], 4096);
        EXPECT_EQ(m["seed"].get<std::uint64_t>(), 0x8000000000000005ull);
        EXPECT_EQ(m["precision"], "float32");
        EXPECT_EQ(m["scene"]["source"], "builtin:test-grid");
        EXPECT_EQ(m["scene"]["hash"], format_mesh_hash(mesh_hash(s.mesh)));
        EXPECT_EQ(m["scene"]["vertices"], 25);
        EXPECT_EQ(m["scene"]["triangles"], 32);
        EXPECT_EQ(m["stats"]["seconds_trace"], 0.25);
        EXPECT_EQ(m["stats"]["rays_cast"], 123456789012ull);
        EXPECT_EQ(m["stats"]["peak_bytes_host"], 50u << 20);
        EXPECT_EQ(m["stats"]["device"], "cpu: 2 threads");
        EXPECT_EQ(m["stats"]["seconds_load"], 0.5);  // merged from the extra metadata
        EXPECT_EQ(m["command_line"], "shprt bake builtin:room -o m.shprt");

        // The section table describes the bytes: recompute every CRC from the raw file.
        const std::string bytes = read_file(file);
        const char* names[] = {"positions", "normals",       "albedo",
                               "triangles", "source_vertex", "transfer"};
        ASSERT_EQ(m["sections"].size(), 6u);
        std::uint64_t end = 0;
        for (std::size_t i = 0; i < 6; ++i) {
            const Json& sec = m["sections"][i];
            EXPECT_EQ(sec["name"], names[i]);
            const auto offset = sec["offset"].get<std::uint64_t>();
            const auto length = sec["length"].get<std::uint64_t>();
            EXPECT_EQ(offset % 64, 0u) << names[i];
            EXPECT_EQ(length, sec["count"].get<std::uint64_t>() * 4) << names[i];
            ASSERT_LE(offset + length, bytes.size());
            EXPECT_EQ(sec["crc32"].get<std::uint32_t>(), crc32(bytes.data() + offset, length))
                << names[i];
            end = offset + length;
        }
        EXPECT_EQ(end, bytes.size());
        EXPECT_EQ(m["sections"][5]["shape"], Json::array({25, K}));
        EXPECT_EQ(m["sections"][5]["dtype"], "float32");
    }
}

// The header bytes as docs/file_format.md lists them, decoded by hand.
TEST_F(IoShprtFile, HeaderBytesFollowTheSpecification) {
    const Scene s = make_scene(4, 9, 1, false);
    write_shprt(path("h.shprt"), s.mesh, s.transfer);
    const std::string b = read_file(path("h.shprt"));
    const auto u8 = [&b](std::size_t i) { return unsigned(static_cast<unsigned char>(b[i])); };
    const auto u32 = [&](std::size_t i) {
        return u8(i) | u8(i + 1) << 8 | u8(i + 2) << 16 | std::uint32_t(u8(i + 3)) << 24;
    };
    const auto u64 = [&](std::size_t i) { return u32(i) | std::uint64_t(u32(i + 4)) << 32; };
    EXPECT_EQ(b.substr(0, 12), std::string("\x89SHPRT\r\n\x1a\n\0\0", 12));
    EXPECT_EQ(u32(12), 2u);                                          // version
    EXPECT_EQ(b.substr(16, 4), std::string("\x04\x03\x02\x01", 4));  // endianness marker
    EXPECT_EQ(u32(20), 48u);                                         // header size
    EXPECT_EQ(u64(24), 48u);                                         // metadata offset
    const std::uint64_t length = u64(32);
    const std::string meta = b.substr(48, length);
    EXPECT_EQ(u32(40), crc32(meta.data(), meta.size()));
    EXPECT_EQ(u32(44), crc32(b.data(), 44));
    EXPECT_EQ(Json::parse(meta)["K"], 9);
    // The first section starts at the next multiple of 64 after the metadata, zeros between.
    const auto first = Json::parse(meta)["sections"][0]["offset"].get<std::uint64_t>();
    EXPECT_EQ(first, (48 + length + 63) / 64 * 64);
    EXPECT_EQ(b.substr(48 + length, first - 48 - length), std::string(first - 48 - length, '\0'));
    // zlib's CRC-32 check value, as the document states.
    EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);
    ShprtHeader h = decode_shprt_header(reinterpret_cast<const unsigned char*>(b.data()));
    EXPECT_EQ(h.metadata_length, length);
    unsigned char again[kShprtHeaderSize];
    EXPECT_EQ(encode_shprt_header(h, again), u32(44));
    EXPECT_EQ(std::memcmp(again, b.data(), kShprtHeaderSize), 0);
}

TEST_F(IoShprtFile, ExtraMetadataCannotReplaceWriterFields) {
    const Scene s = make_scene(3, 4, 1, false);
    for (const char* extra :
         {R"({"K": 9})", R"({"stats": {"rays_cast": 1}})", R"([1, 2])", "{oops"}) {
        WriteOptions options;
        options.extra_metadata_json = extra;
        try {
            write_shprt(path("x.shprt"), s.mesh, s.transfer, options);
            ADD_FAILURE() << "accepted " << extra;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
        }
        EXPECT_TRUE(dir_entries().empty()) << extra;
    }
}

TEST_F(IoShprtFile, ReproducibleOutputIgnoresTimings) {
    Scene a = make_scene(6, 9, 1, false);
    Scene b = a;
    b.transfer.stats.seconds_trace = 9.0;
    b.transfer.stats.device_name = "another machine";
    WriteOptions options;
    options.reproducible = true;
    write_shprt(path("a.shprt"), a.mesh, a.transfer, options);
    write_shprt(path("b.shprt"), b.mesh, b.transfer, options);
    EXPECT_EQ(read_file(path("a.shprt")), read_file(path("b.shprt")));
    EXPECT_FALSE(Json::parse(read_shprt(path("a.shprt")).metadata_json).contains("stats"));
    write_shprt(path("a.shprt"), a.mesh, a.transfer);
    write_shprt(path("b.shprt"), b.mesh, b.transfer);
    EXPECT_NE(read_file(path("a.shprt")), read_file(path("b.shprt")));
}

// Kept metadata (a refinement's or texel bake's facts) stays in reproducible files; the extra
// metadata of the run does not; both merge into one object where they share a key.
TEST_F(IoShprtFile, ReproducibleOutputKeepsTheKeptMetadata) {
    const Scene a = make_scene(6, 9, 1, false);
    WriteOptions options;
    options.kept_metadata_json = R"({"refinement": {"passes": 3}})";
    options.extra_metadata_json = R"({"refinement": {"seconds": 1.5}, "command_line": "x"})";
    write_shprt(path("a.shprt"), a.mesh, a.transfer, options);
    Json m = Json::parse(read_shprt(path("a.shprt")).metadata_json);
    EXPECT_EQ(m["refinement"]["passes"], 3);
    EXPECT_EQ(m["refinement"]["seconds"], 1.5);
    options.reproducible = true;
    write_shprt(path("a.shprt"), a.mesh, a.transfer, options);
    m = Json::parse(read_shprt(path("a.shprt")).metadata_json);
    EXPECT_EQ(m["refinement"]["passes"], 3);
    EXPECT_FALSE(m["refinement"].contains("seconds"));
    EXPECT_FALSE(m.contains("command_line"));
    options.kept_metadata_json = "[1]";
    EXPECT_THROW(write_shprt(path("c.shprt"), a.mesh, a.transfer, options), Error);
}

// The scene hash is FNV-1a 64 over the documented byte sequence; recompute it independently.
TEST_F(IoShprtFile, MeshHashFollowsItsDefinition) {
    const Scene s = make_scene(4, 1, 1, true);
    std::string bytes;
    const auto append = [&bytes](const void* p, std::size_t n) {
        bytes.append(static_cast<const char*>(p), n);
    };
    const std::uint64_t counts[2] = {16, 18};
    append(counts, sizeof counts);
    append(s.mesh.positions.data(), 16 * 12);
    append(s.mesh.normals.data(), 16 * 12);
    append(s.mesh.albedo.data(), 16 * 12);
    append(s.mesh.triangles.data(), 18 * 12);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
    EXPECT_EQ(mesh_hash(s.mesh), h);
    // FNV-1a test vectors: "" and "a".
    EXPECT_EQ(fnv1a64("", 0), 0xcbf29ce484222325ull);
    EXPECT_EQ(fnv1a64("a", 1), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(format_mesh_hash(0xabcull), "fnv1a64:0000000000000abc");

    Mesh moved = s.mesh;
    moved.source = "elsewhere.ply";
    moved.source_vertex.clear();
    EXPECT_EQ(mesh_hash(moved), mesh_hash(s.mesh));  // not part of the geometry
    moved.positions[5].y = std::nextafter(moved.positions[5].y, 10.0f);
    EXPECT_NE(mesh_hash(moved), mesh_hash(s.mesh));
    Mesh flipped = s.mesh;
    std::swap(flipped.triangles[0][0], flipped.triangles[0][1]);
    EXPECT_NE(mesh_hash(flipped), mesh_hash(s.mesh));
}

TEST_F(IoShprtFile, WriterRejectsInconsistentInput) {
    const Scene good = make_scene(3, 4, 1, false);
    const auto expect_rejected = [&](const Scene& s, bool half, const char* what) {
        TransferSet transfer = s.transfer;
        if (half) transfer.layout.encoding = TransferEncoding::f16;
        try {
            write_shprt(path("bad.shprt"), s.mesh, transfer);
            ADD_FAILURE() << "accepted: " << what;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << what << ": " << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.shprt"), std::string::npos) << e.what();
        }
        EXPECT_TRUE(dir_entries().empty()) << what;
    };
    Scene s = good;
    s.mesh.normals.pop_back();
    expect_rejected(s, false, "normals count");
    s = good;
    s.mesh.albedo.push_back({});
    expect_rejected(s, false, "albedo count");
    s = good;
    s.mesh.source_vertex = {1, 2};
    expect_rejected(s, false, "source_vertex count");
    s = good;
    s.mesh.triangles[3][2] = 9;
    expect_rejected(s, false, "triangle index");
    s = good;
    s.transfer.layout.K = 0;
    expect_rejected(s, false, "K = 0");
    s = good;
    s.transfer.layout.channels = 2;
    expect_rejected(s, false, "2 channels");
    s = good;
    s.transfer.coeffs.pop_back();
    expect_rejected(s, false, "coefficient count");
    s = good;
    s.transfer.coeffs[7] = std::nanf("");
    expect_rejected(s, false, "NaN coefficient");
    s = good;
    s.transfer.coeffs[7] = 70000.0f;
    expect_rejected(s, true, "float16 overflow");
    s = good;
    s.transfer.samples = 0;  // only unshadowed transfer has a closed form (no directions)
    EXPECT_NO_THROW(write_shprt(path("analytic.shprt"), s.mesh, s.transfer));
    fs::remove(path("analytic.shprt"));
    s.transfer.kind = TransferKind::shadowed;
    expect_rejected(s, false, "samples = 0, shadowed");
    s.transfer.samples = -1;
    expect_rejected(s, false, "samples = -1");
    s = good;
    s.transfer.coeffs[7] = 70000.0f;
    EXPECT_NO_THROW(write_shprt(path("ok.shprt"), s.mesh, s.transfer));  // fine in float32
}

TEST_F(IoShprtFile, UnwritableDestinationLeavesNothing) {
    const Scene s = make_scene(3, 4, 1, false);
    // A missing directory, and a "directory" that is a regular file (fails even for root).
    write_shprt(path("plain"), s.mesh, s.transfer);
    for (const std::string& target : {path("missing/dir/out.shprt"), path("plain/out.shprt")}) {
        try {
            write_shprt(target, s.mesh, s.transfer);
            ADD_FAILURE() << "wrote " << target;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::io) << e.what();
            EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(target));
    }
    EXPECT_EQ(dir_entries(), std::vector<std::string>{"plain"});
}

// A write that fails half-way (the file-size limit stops it) leaves the existing target intact
// and no temporary file behind.
TEST_F(IoShprtFile, FailedWriteLeavesTargetUntouched) {
    const Scene small = make_scene(3, 4, 1, false);
    const Scene big = make_scene(40, 256, 1, false);  // ~1.6 MB of coefficients
    const std::string target = path("keep.shprt");
    write_shprt(target, small.mesh, small.transfer);
    const std::string before = read_file(target);

    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    struct rlimit limited = old;
    limited.rlim_cur = 256 << 10;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
    const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // get EFBIG instead of a signal
    bool threw = false;
    try {
        write_shprt(target, big.mesh, big.transfer);
    } catch (const Error& e) {
        threw = e.code() == ErrorCode::io;
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, old_handler);

    EXPECT_TRUE(threw);
    EXPECT_EQ(read_file(target), before);
    EXPECT_EQ(dir_entries(), std::vector<std::string>{"keep.shprt"});
    EXPECT_NO_THROW(read_shprt(target));
}

TEST_F(IoShprtFile, ReaderReportsMissingFiles) {
    try {
        read_shprt(path("nope.shprt"));
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::io);
        EXPECT_NE(std::string(e.what()).find("nope.shprt"), std::string::npos);
    }
    EXPECT_THROW(read_shprt(m_dir.string()), Error);  // a directory
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
    EXPECT_THROW(read_shprt(path("fifo")), Error);  // and no hang waiting for a writer
}

TEST_F(IoShprtFile, SummaryDescribesTheFile) {
    const Scene s = make_scene(5, 32, 1, false);
    write_shprt(path("s.shprt"), s.mesh, s.transfer);
    const std::string text = shprt_summary(read_shprt(path("s.shprt")));
    for (const char* expected :
         {"vertices     25\n", "triangles    32\n", "K = 32: 6 bands, last band partial", "7 of 11",
          "fibonacci, 4096 samples, seed 9223372036854775813", "float32", "unshadowed",
          "trace 0.250", "bvh 0.012", "0.330 s total", "rays/s", "50.0 MiB host", "cpu: 2 threads",
          "fnv1a64:", "file size", SHPRT_VERSION_STRING})
        EXPECT_NE(text.find(expected), std::string::npos) << "missing '" << expected << "' in\n"
                                                          << text;
    EXPECT_NE(text.find(fmt::format("({} bytes)", fs::file_size(path("s.shprt")))),
              std::string::npos)
        << text;

    const Scene full = make_scene(2, 16, 3, false);
    write_shprt(path("f.shprt"), full.mesh, full.transfer);
    const std::string text_full = shprt_summary(read_shprt(path("f.shprt")));
    EXPECT_NE(text_full.find("K = 16: 4 bands, last band full"), std::string::npos) << text_full;
    EXPECT_NE(text_full.find("3 channels"), std::string::npos) << text_full;
}

}  // namespace
}  // namespace shprt
