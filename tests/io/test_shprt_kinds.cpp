// One small file of every transfer kind, against fixtures written by the build before the
// metadata became one field table (tests/data/shprt_kinds/): the writer gives the same bytes for
// the same set (the metadata's key order included), and each fixture reads back to a set that
// writes those bytes again (so every field the metadata holds is read as it was written). The
// sets are built from exact arithmetic, not baked, so the bytes do not depend on the host.
// SHPRT_UPDATE_GOLDEN=1 rewrites the fixtures (after a deliberate format change, or a new
// tool_version: the version is in the metadata).
#include "shprt/core/error.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/scene/material.hpp"
#include "shprt/transfer/cpca.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(SHPRT_TEST_DATA_DIR) / "shprt_kinds";

// A strip of n quads in the y = 0 plane: 2(n + 1) vertices, 2n triangles, values in exact
// binary fractions.
Mesh strip(int n) {
    Mesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j < 2; ++j) {
            m.positions.push_back({0.5f * float(i), 0.0f, float(j)});
            m.normals.push_back({0.0f, 1.0f, 0.0f});
            m.albedo.push_back({0.25f * float(i % 4), 0.5f, 0.125f * float(j + 1)});
            m.uvs.push_back({float(i) / float(n), float(j)});
        }
    for (int i = 0; i < n; ++i) {
        const auto v = std::uint32_t(2 * i);
        m.triangles.push_back({v, v + 1, v + 2});
        m.triangles.push_back({v + 1, v + 3, v + 2});
    }
    m.source = "test:strip";
    return m;
}

void fill(std::vector<float>& v, std::size_t n, float scale) {
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = scale * float(int(i % 17) - 8) / 8.0f;
}

TransferSet vector_set(const Mesh& mesh, int K, int channels) {
    TransferSet t;
    t.kind = TransferKind::shadowed;
    t.layout.K = K;
    t.layout.channels = channels;
    t.sampler = SamplerKind::fibonacci;
    t.samples = 64;
    t.seed = 7;
    fill(t.coeffs, t.layout.floats(mesh.positions.size()), 0.5f);
    return t;
}

CpcaCode code(std::size_t rows, int D, int clusters, int vectors) {
    CpcaCode c;
    c.clusters = clusters;
    c.vectors = vectors;
    c.seed = 11;
    for (std::size_t r = 0; r < rows; ++r) c.cluster.push_back(std::uint32_t(r % clusters));
    fill(c.weights, rows * std::size_t(vectors), 0.25f);
    fill(c.means, std::size_t(clusters) * std::size_t(D), 0.5f);
    fill(c.basis, std::size_t(clusters) * std::size_t(vectors) * std::size_t(D), 0.125f);
    return c;
}

ProbeGrid probes(int K) {
    ProbeGrid g;
    g.origin = {-0.5f, 0.25f, 0.0f};
    g.spacing = {1.0f, 0.5f, 1.0f};
    g.counts = {2, 2, 1};
    g.K = K;
    fill(g.matrices, g.count() * std::size_t(K * K), 0.75f);
    g.valid = {1, 0, 1, 1};
    return g;
}

struct Kind {
    const char* name;
    std::function<void(Mesh&, TransferSet&, WriteOptions&)> make;
};

const Kind kKinds[] = {
    // Per-vertex vectors, RGB, a local direction set, with the bake's stats and extra metadata.
    {"vector",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         m.source_vertex = {5, 4, 3, 2, 1, 0};
         t = vector_set(m, 9, 3);
         t.direction_frame = DirectionFrame::local;
         t.sampler = SamplerKind::sobol;
         t.stats = {0.125, 0.5, 0.25, 1.0, 123456, 1 << 20, 0, "cpu: 2 threads"};
         o.extra_metadata_json = R"({"command": "shprt bake", "stats": {"seconds_load": 0.0625}})";
     }},
    {"glossy",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.kind = TransferKind::glossy;
         t.layout.shape = TransferShape::symmetric_matrix;
         t.layout.encoding = TransferEncoding::f16;
         fill(t.coeffs, t.layout.floats(m.positions.size()), 0.5f);
         m.brdfs = {parse_brdf("phong:16"), parse_brdf("ggx:0.5:1,0.5,0.25")};
         m.brdf_index = {0, 0, 1, 1, 0xFFFFFFFFu, 1};
         o.reproducible = true;
     }},
    {"cpca",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 9, 1);
         t.cpca = code(m.positions.size(), 9, 2, 2);
         reconstruct_cpca(t.cpca, 9, t.coeffs);
         o.reproducible = true;
     }},
    {"interreflected",
     [](Mesh& m, TransferSet& t, WriteOptions&) {
         t = vector_set(m, 4, 3);
         t.kind = TransferKind::interreflected;
         fill(t.direct, t.layout.floats_per_channel() * m.positions.size(), 0.25f);
         t.interreflection = {3,  true, true, 1e-3, 5e-4, true, "--albedo 0.5,0.5,0.5",
                              40, 960,  4096, 12,   0.25, 2,    16,
                              1,  2};
         t.stats = {0.125, 0.5, 0.25, 1.5, 4096, 1 << 21, 0, "cpu: 1 thread", 0.125, 0.25, 512};
     }},
    {"texels",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.layout.domain = ReceiverDomain::texel;
         t.texels = {4, 3, 0, {0, 1, 5, 6, 11}};
         fill(t.coeffs, t.layout.floats(5), 0.5f);
         o.reproducible = true;
         o.kept_metadata_json = R"({"texel_bake": {"covered": 5, "density": 2.5}})";
     }},
    {"refined",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         m.parents.assign(m.positions.size(), {Mesh::kNoParent, Mesh::kNoParent});
         m.parents[4] = {0, 2};
         m.parents[5] = {1, 3};
         t = vector_set(m, 4, 1);
         o.reproducible = true;
         o.kept_metadata_json = R"({"refinement": {"passes": 1, "tolerance": 0.125}})";
     }},
    {"probes",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.probes = probes(4);
         o.reproducible = true;
     }},
    {"probe_cpca",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.probes = probes(4);
         t.probes.cpca = code(3, 16, 2, 1);
         reconstruct_probes(t.probes);
         o.reproducible = true;
     }},
    {"error_bounded",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.target_error = 0.0625;
         t.receiver_samples = {16, 32, 64, 64, 16, 32};
         t.receiver_error = {0.03125f, 0.0625f, 0.125f, 0.0625f, 0.015625f, 0.03125f};
         o.reproducible = true;
     }},
    // A part of a sharded bake: receivers [2, 5) of 6.
    {"part",
     [](Mesh& m, TransferSet& t, WriteOptions& o) {
         t = vector_set(m, 4, 1);
         t.coeffs.resize(t.layout.floats(3));
         o.receiver_first = 2;
         o.reproducible = true;
     }},
};

void PrintTo(const Kind& kind, std::ostream* os) { *os << kind.name; }

std::string bytes_of(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

bool update_golden() {
    const char* v = std::getenv("SHPRT_UPDATE_GOLDEN");
    return v && std::string(v) == "1";
}

class ShprtKinds : public ::testing::TestWithParam<Kind> {};

TEST_P(ShprtKinds, SameBytesAsTheFixtureAndReadsBackToThem) {
    const Kind& kind = GetParam();
    const fs::path fixture = kDir / (std::string(kind.name) + ".shprt");
    Mesh mesh = strip(2);
    TransferSet t;
    WriteOptions options;
    kind.make(mesh, t, options);
    if (update_golden()) {
        fs::create_directories(kDir);
        write_shprt(fixture.string(), mesh, t, options);
        GTEST_SKIP() << "wrote " << fixture;
    }
    const std::string expected = bytes_of(fixture);
    ASSERT_FALSE(expected.empty()) << fixture;
    EXPECT_LT(expected.size(), 50000u);
    const fs::path out =
        fs::temp_directory_path() / fmt::format("kinds_{}_{}.shprt", kind.name, ::getpid());
    write_shprt(out.string(), mesh, t, options);
    EXPECT_TRUE(bytes_of(out) == expected)
        << kind.name << ": written bytes differ from " << fixture;

    // Read back, the fixture gives a set that writes the same bytes again.
    const ShprtFile f = read_shprt_part(fixture.string());
    EXPECT_EQ(f.receiver_first, options.receiver_first);
    write_shprt(out.string(), f.mesh, f.transfer, options);
    EXPECT_TRUE(bytes_of(out) == expected) << kind.name << ": read and rewritten, bytes differ";
    fs::remove(out);
}

INSTANTIATE_TEST_SUITE_P(EveryKind, ShprtKinds, ::testing::ValuesIn(kKinds),
                         [](const auto& p) { return std::string(p.param.name); });

// Every metadata field of every kind removed, or given a value of another type, in turn (the
// header's CRCs fixed): the file still reads, or the reader says one line that starts with the
// file's name — never a crash, another error type or a message of several lines.
TEST(ShprtKindsMetadata, EveryFieldRemovedOrRetypedReadsOrIsOneLine) {
    using Json = nlohmann::json;
    const fs::path path =
        fs::temp_directory_path() / fmt::format("kinds_edited_{}.shprt", ::getpid());
    int edits = 0, refused = 0;
    for (const Kind& kind : kKinds) {
        const std::string good = bytes_of(kDir / (std::string(kind.name) + ".shprt"));
        ShprtHeader h = decode_shprt_header(reinterpret_cast<const unsigned char*>(good.data()));
        const Json meta = Json::parse(good.substr(kShprtHeaderSize, h.metadata_length));
        const auto check = [&](const Json& edited, const std::string& what) {
            std::string text = edited.dump();
            ASSERT_LE(text.size(), h.metadata_length) << what;
            text.resize(h.metadata_length, ' ');
            ShprtHeader e = h;
            e.metadata_crc32 = crc32(text.data(), text.size());
            std::string bytes = good;
            bytes.replace(kShprtHeaderSize, text.size(), text);
            encode_shprt_header(e, reinterpret_cast<unsigned char*>(bytes.data()));
            std::ofstream(path, std::ios::binary) << bytes;
            ++edits;
            try {
                read_shprt_part(path.string());
            } catch (const Error& err) {
                const std::string message = err.what();
                EXPECT_EQ(err.code(), ErrorCode::format) << what << ": " << message;
                EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << what << ": " << message;
                EXPECT_EQ(message.find('\n'), std::string::npos) << what << ": " << message;
                ++refused;
            }
        };
        // Each key of the metadata's objects (the section table's entries left to
        // IoShprtCorrupt), by its JSON pointer.
        std::vector<Json::json_pointer> keys;
        const std::function<void(const Json&, const Json::json_pointer&)> walk =
            [&](const Json& j, const Json::json_pointer& at) {
                for (auto it = j.begin(); it != j.end(); ++it) {
                    if (at.empty() && it.key() == "sections") continue;
                    keys.push_back(at / it.key());
                    if (it->is_object()) walk(*it, at / it.key());
                }
            };
        walk(meta, Json::json_pointer());
        for (const Json::json_pointer& key : keys) {
            Json removed = meta;
            removed[key.parent_pointer()].erase(key.back());
            check(removed, std::string(kind.name) + ": without " + key.to_string());
            Json retyped = meta;
            retyped[key] = retyped[key].is_string() ? Json(7) : Json("x");
            check(retyped, std::string(kind.name) + ": " + key.to_string() + " retyped");
        }
    }
    fs::remove(path);
    // Most edits are refused (the required fields), some read (the informative ones).
    EXPECT_GT(refused, edits / 2);
    EXPECT_LT(refused, edits);
}

}  // namespace
}  // namespace shprt
