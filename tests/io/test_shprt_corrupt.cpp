// Damaged .shprt files: every truncation of the header and metadata, a sample of truncations in
// the arrays, every single-byte flip, wrong magic, future versions, lengths and offsets past the
// end of the file or absurd (2^63), inconsistent counts, bad JSON. Each must give shprt::Error
// naming the file and the problem; none may crash or allocate from a corrupt length (run this
// under -DSHPRT_SANITIZE=ON to check the "no crash" half).
//
// Files with a forged but self-consistent header/metadata are made by re-encoding the header
// (shprt_format.hpp) and recomputing CRCs, so the check under test is reached.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/transfer/cpca.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

namespace shprt {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// A small scene (16 vertices, 18 triangles, K = 9) with source_vertex and brdf_index sections.
Mesh small_mesh() {
    Mesh mesh;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            mesh.positions.push_back({float(i), 0.0f, float(j)});
            mesh.normals.push_back({0.0f, 1.0f, 0.0f});
            mesh.albedo.push_back({0.5f, 0.25f, float(i + j) / 8.0f});
            mesh.source_vertex.push_back(std::uint32_t(j * 4 + i));
            mesh.brdf_index.push_back(i == 3 ? Mesh::kNoBrdf : std::uint32_t(i % 2));
        }
    mesh.brdfs = {Brdf{BrdfModel::phong, 32}, Brdf{BrdfModel::ggx, 0.25}};
    for (std::uint32_t j = 0; j < 3; ++j)
        for (std::uint32_t i = 0; i < 3; ++i) {
            const std::uint32_t v = j * 4 + i;
            mesh.triangles.push_back({v, v + 4, v + 1});
            mesh.triangles.push_back({v + 1, v + 4, v + 5});
        }
    mesh.source = "builtin:corrupt-test";
    return mesh;
}

void write_small_file(const std::string& path) {
    const Mesh mesh = small_mesh();
    TransferSet t;
    t.layout.K = 9;
    t.coeffs.resize(16 * 9);
    for (std::size_t i = 0; i < t.coeffs.size(); ++i) t.coeffs[i] = std::sin(float(i));
    t.samples = 64;
    t.seed = 3;
    write_shprt(path, mesh, t);
}

class IoShprtCorrupt : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / fmt::format("shprt_io_corrupt_{}", ::getpid());
        fs::create_directories(m_dir);
        m_path = (m_dir / "c.shprt").string();
        write_small_file(m_path);
        m_good = read_file(m_path);
        m_meta = Json::parse(m_good.substr(kShprtHeaderSize, header().metadata_length));
    }
    void TearDown() override { fs::remove_all(m_dir); }

    ShprtHeader header() const {
        return decode_shprt_header(reinterpret_cast<const unsigned char*>(m_good.data()));
    }
    const Json& section(const std::string& name) const {
        for (const Json& s : m_meta["sections"])
            if (s["name"].get<std::string>() == name) return s;
        throw std::runtime_error("no section " + name);
    }

    // Writes `bytes` as the file and returns the reader's Error (failing the test if it reads).
    Error read_error(const std::string& bytes, const std::string& what) {
        {
            fs::remove(m_path);  // a fresh file: truncating one makes ext4 flush it on close
            std::ofstream out(m_path, std::ios::binary);
            out.write(bytes.data(), std::streamsize(bytes.size()));
        }
        try {
            read_shprt(m_path);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::format) << what << ": " << e.what();
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(m_path + ": ", 0), 0u) << what << ": " << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << what << ": " << message;
            return e;
        }
        ADD_FAILURE() << "read succeeded: " << what;
        return Error(ErrorCode::format, "");
    }
    void expect_error(const std::string& bytes, const std::string& substring,
                      const std::string& what) {
        const std::string message = read_error(bytes, what).what();
        EXPECT_NE(message.find(substring), std::string::npos)
            << what << ": expected '" << substring << "' in: " << message;
    }

    // The file with the metadata replaced by `meta` (compact, padded with spaces to the old
    // length so no offset moves) and the header's CRCs recomputed.
    std::string with_metadata(const Json& meta) const {
        ShprtHeader h = header();
        std::string text = meta.dump();
        EXPECT_LE(text.size(), h.metadata_length);
        text.resize(h.metadata_length, ' ');
        return with_metadata_text(text);
    }
    std::string with_metadata_text(const std::string& text) const {
        ShprtHeader h = header();
        EXPECT_EQ(text.size(), h.metadata_length);
        h.metadata_crc32 = crc32(text.data(), text.size());
        std::string out = m_good;
        out.replace(kShprtHeaderSize, text.size(), text);
        return with_header(out, h);
    }
    static std::string with_header(std::string bytes, const ShprtHeader& h) {
        unsigned char head[kShprtHeaderSize];
        encode_shprt_header(h, head);
        std::memcpy(bytes.data(), head, sizeof head);
        return bytes;
    }
    // The file with `patch` applied to one section's bytes and its CRC fixed in the metadata.
    template <class Patch>
    std::string with_section_patch(const std::string& name, Patch&& patch,
                                   const Json* base = nullptr) const {
        Json meta = base ? *base : m_meta;
        std::string bytes = m_good;
        for (Json& s : meta["sections"]) {
            if (s["name"].get<std::string>() != name) continue;
            const auto offset = s["offset"].get<std::size_t>(),
                       length = s["length"].get<std::size_t>();
            patch(bytes.data() + offset);
            s["crc32"] = crc32(bytes.data() + offset, length);
        }
        ShprtHeader h = header();
        std::string text = meta.dump();
        text.resize(h.metadata_length, ' ');
        h.metadata_crc32 = crc32(text.data(), text.size());
        bytes.replace(kShprtHeaderSize, text.size(), text);
        return with_header(bytes, h);
    }

    fs::path m_dir;
    std::string m_path, m_good;
    Json m_meta;
};

TEST_F(IoShprtCorrupt, TheUndamagedFileReads) { EXPECT_NO_THROW(read_shprt(m_path)); }

TEST_F(IoShprtCorrupt, TruncatedAtEveryOffsetOfHeaderAndMetadata) {
    const std::size_t data_start = section("positions")["offset"].get<std::size_t>();
    for (std::size_t n = 0; n <= data_start; ++n)
        expect_error(m_good.substr(0, n), "truncated", fmt::format("truncated to {} bytes", n));
}

TEST_F(IoShprtCorrupt, TruncatedInsideTheArrays) {
    const std::size_t data_start = section("positions")["offset"].get<std::size_t>();
    for (std::size_t n = data_start; n < m_good.size(); n += 13)
        expect_error(m_good.substr(0, n), "truncated", fmt::format("truncated to {} bytes", n));
    for (const Json& s : m_meta["sections"]) {  // at and around every section boundary
        const auto offset = s["offset"].get<std::size_t>(),
                   end = offset + s["length"].get<std::size_t>();
        for (std::size_t n : {offset - 1, offset, offset + 1, end - 1})
            if (n < m_good.size())
                expect_error(m_good.substr(0, n), "truncated",
                             fmt::format("truncated to {} bytes", n));
    }
    // The message names the section, what it needs and what the file has.
    const Json& t = section("transfer");
    const std::size_t n = t["offset"].get<std::size_t>() + 10;
    expect_error(m_good.substr(0, n),
                 fmt::format("truncated: section 'transfer' needs {} bytes at offset {} but the "
                             "file has {}",
                             t["length"].get<std::size_t>(), t["offset"].get<std::size_t>(), n),
                 "truncated in transfer");
}

TEST_F(IoShprtCorrupt, FlippedByteInEachSectionNamesTheSection) {
    for (const Json& s : m_meta["sections"]) {
        std::string bytes = m_good;
        bytes[s["offset"].get<std::size_t>() + s["length"].get<std::size_t>() / 2] ^= 0x10;
        const std::string name = s["name"];
        expect_error(bytes, "section '" + name + "' fails its checksum", name);
    }
    std::string bytes = m_good;
    bytes[30] ^= 0x01;  // metadata_length
    expect_error(bytes, "header fails its checksum", "header");
    bytes = m_good;
    bytes[kShprtHeaderSize + 20] ^= 0x01;
    expect_error(bytes, "metadata fails its checksum", "metadata");
}

// Every byte is covered by a check: a flip anywhere is an error.
TEST_F(IoShprtCorrupt, EverySingleByteFlipIsDetected) {
    for (std::size_t i = 0; i < m_good.size(); ++i)
        for (const int mask : {0x01, 0x80}) {
            std::string bytes = m_good;
            bytes[i] = char(bytes[i] ^ mask);
            read_error(bytes, fmt::format("byte {} ^ {:#x}", i, mask));
        }
}

TEST_F(IoShprtCorrupt, WrongMagic) {
    expect_error("PK\x03\x04 this is a zip file, not a shprt file at all..........................",
                 "not a .shprt file", "zip");
    expect_error(std::string(100, '\0'), "not a .shprt file", "zeros");
    // What a text-mode copy does: CRLF -> LF shortens the magic.
    std::string text_mode = m_good;
    text_mode.erase(6, 1);
    expect_error(text_mode, "text mode", "CRLF -> LF");
    std::string seven_bit = m_good;
    seven_bit[0] = char(0x09);
    expect_error(seven_bit, "text mode", "high bit stripped");
}

TEST_F(IoShprtCorrupt, FutureAndInvalidVersions) {
    ShprtHeader h = header();
    h.version = kShprtNewestReadVersion + 1;
    expect_error(with_header(m_good, h),
                 fmt::format("format version {} is newer", kShprtNewestReadVersion + 1),
                 "version +1");
    h.version = 0;
    expect_error(with_header(m_good, h), "invalid format version 0", "version 0");
    h = header();
    h.endian_marker = 0x04030201u;
    expect_error(with_header(m_good, h), "big-endian", "byte-swapped marker");
    h.endian_marker = 0xdeadbeefu;
    expect_error(with_header(m_good, h), "endianness marker", "bad marker");
    h = header();
    h.header_size = 64;
    expect_error(with_header(m_good, h), "header size", "header size");
    h = header();
    h.metadata_offset = 64;
    expect_error(with_header(m_good, h), "metadata offset", "metadata offset");
    Json meta = m_meta;
    meta["format_version"] = 7;
    expect_error(with_metadata(meta), "format_version 7 differs", "json version");
    // A field newer than the file (the field table's `since`) is refused, not ignored: a CPCA
    // code's object in a version 2 file would otherwise read its rows as if it had none.
    meta = m_meta;
    meta["cpca"] = Json::object({{"clusters", 1}, {"vectors", 1}});
    expect_error(with_metadata(meta), "'cpca' in a version 2 file (it came with version 3)",
                 "a version 3 field in a version 2 file");
}

TEST_F(IoShprtCorrupt, MetadataLengthPastTheEndOrAbsurd) {
    for (const std::uint64_t length :
         {std::uint64_t(m_good.size()), std::uint64_t(1) << 40, std::uint64_t(1) << 63,
          ~std::uint64_t(0), ~std::uint64_t(0) - 40}) {
        ShprtHeader h = header();
        h.metadata_length = length;
        expect_error(with_header(m_good, h), "truncated: the metadata needs",
                     fmt::format("length {}", length));
    }
    // Inside the file but over the sanity cap: needs a big file.
    std::string big = m_good + std::string(kShprtMaxMetadataBytes + 10, ' ');
    ShprtHeader h = header();
    h.metadata_length = kShprtMaxMetadataBytes + 1;
    expect_error(with_header(big, h), "exceeds the limit", "metadata cap");
}

TEST_F(IoShprtCorrupt, SectionOffsetsAndLengthsPastTheEndOrAbsurd) {
    const std::uint64_t huge[] = {std::uint64_t(m_good.size()),
                                  std::uint64_t(m_good.size()) + 64,
                                  std::uint64_t(1) << 50,
                                  std::uint64_t(1) << 63,
                                  ~std::uint64_t(0),
                                  ~std::uint64_t(0) - 15};
    for (const char* name :
         {"positions", "normals", "albedo", "triangles", "source_vertex", "transfer"})
        for (const char* field : {"offset", "length"})
            for (const std::uint64_t value : huge) {
                Json meta = m_meta;
                for (Json& s : meta["sections"])
                    if (s["name"].get<std::string>() == name) s[field] = value;
                expect_error(with_metadata(meta),
                             fmt::format("truncated: section '{}' needs", name),
                             fmt::format("{} {} = {}", name, field, value));
            }
    // Offset + length overflowing 64 bits must not wrap around into the file.
    Json meta = m_meta;
    meta["sections"][1]["offset"] = ~std::uint64_t(0) - 7;
    meta["sections"][1]["length"] = 64;
    expect_error(with_metadata(meta), "truncated: section 'normals'", "wrapping offset");
}

TEST_F(IoShprtCorrupt, CountsInconsistentWithVKAndChannels) {
    struct Edit {
        const char* what;
        void (*apply)(Json&);
        const char* message;
    };
    const Edit edits[] = {
        {"K",
         [](Json& m) {
             m["K"] = 16;
             m["bands"] = 4;
             m["last_band_full"] = true;
         },
         "section 'transfer' has shape"},
        {"channels", [](Json& m) { m["channels"] = 3; }, "section 'transfer' has shape"},
        {"vertices", [](Json& m) { m["scene"]["vertices"] = 15; },
         "receivers.total = 16 but the scene has 15 vertices"},
        {"vertices and receivers",
         [](Json& m) {
             m["scene"]["vertices"] = 15;
             m["receivers"]["total"] = 15;
             m["receivers"]["count"] = 15;
         },
         "section 'positions' has shape"},
        {"receivers count 0", [](Json& m) { m["receivers"]["count"] = 0; }, "field 'count'"},
        {"receivers past the end", [](Json& m) { m["receivers"]["first"] = 10; },
         "field 'count' = 16 is outside [1, 6]"},
        {"receivers first huge", [](Json& m) { m["receivers"]["first"] = std::uint64_t(1) << 62; },
         "field 'first'"},
        {"receivers not an object", [](Json& m) { m["receivers"] = 3; }, "receivers"},
        {"triangles", [](Json& m) { m["scene"]["triangles"] = 19; },
         "section 'triangles' has shape"},
        {"count", [](Json& m) { m["sections"][0]["count"] = 47; }, "has count 47"},
        {"dtype", [](Json& m) { m["sections"][5]["dtype"] = "float16"; }, "dtype"},
        {"precision", [](Json& m) { m["precision"] = "float16"; }, "dtype"},
        {"precision value", [](Json& m) { m["precision"] = "float64"; }, "precision"},
        {"bands", [](Json& m) { m["bands"] = 4; }, "bands"},
        {"last band", [](Json& m) { m["last_band_full"] = false; }, "last_band_full"},
        {"K = 0", [](Json& m) { m["K"] = 0; }, "field 'K'"},
        {"K huge", [](Json& m) { m["K"] = std::uint64_t(1) << 62; }, "field 'K'"},
        {"K negative", [](Json& m) { m["K"] = -9; }, "field 'K'"},
        {"K float", [](Json& m) { m["K"] = 9.5; }, "field 'K'"},
        {"K string", [](Json& m) { m["K"] = "9"; }, "field 'K'"},
        {"channels 2", [](Json& m) { m["channels"] = 2; }, "channels"},
        {"vertices huge", [](Json& m) { m["scene"]["vertices"] = std::uint64_t(1) << 62; },
         "receivers.total"},
        {"sampler", [](Json& m) { m["sampler"] = "magic"; }, "sampler"},
        {"kind", [](Json& m) { m["transfer_kind"] = "specular"; }, "transfer kind"},
        {"glossy vectors", [](Json& m) { m["transfer_kind"] = "glossy"; },
         "transfer_kind glossy needs shape symmetric_matrix"},
        {"samples", [](Json& m) { m["samples"] = -1; }, "samples"},
        // Only unshadowed transfer has a closed form; every other kind is baked from at least one
        // direction, and the writer refuses 0 for it.
        {"samples 0", [](Json& m) { m["samples"] = 0; },
         "metadata: samples = 0 for shadowed transfer, but only unshadowed transfer"},
        {"missing K", [](Json& m) { m.erase("K"); }, "missing field 'K'"},
        {"missing sections", [](Json& m) { m.erase("sections"); }, "missing field 'sections'"},
        {"no sections", [](Json& m) { m["sections"] = Json::array(); }, "sections"},
        {"sections not array", [](Json& m) { m["sections"] = 5; }, "sections"},
        {"section renamed", [](Json& m) { m["sections"][2]["name"] = "colours"; }, "'colours'"},
        {"section swapped", [](Json& m) { std::swap(m["sections"][0], m["sections"][1]); },
         "expected"},
        {"section not object", [](Json& m) { m["sections"][3] = 1; }, "objects"},
        {"shape", [](Json& m) { m["sections"][0]["shape"] = Json::array({16}); }, "shape"},
        {"crc type", [](Json& m) { m["sections"][0]["crc32"] = "ok"; }, "crc32"},
        {"crc too big", [](Json& m) { m["sections"][0]["crc32"] = std::uint64_t(1) << 40; },
         "crc32"},
        {"offset moved",
         [](Json& m) { m["sections"][3]["offset"] = m["sections"][3]["offset"].get<int>() + 64; },
         "section 'triangles' at offset"},
        {"convention", [](Json& m) { m["convention"]["basis"] = "Sloan 2008"; }, "convention"},
        {"format", [](Json& m) { m["format"] = "other"; }, "format"},
        {"stats type",
         [](Json& m) {
             m["stats"] = Json::object({{"seconds_total", "fast"}});
         },
         "seconds_total"},
        {"scene not object", [](Json& m) { m["scene"] = "room"; }, "scene"},
        {"not an object",
         [](Json& m) {
             m = Json::array({1, 2, 3});
         },
         "not a JSON object"},
    };
    for (const Edit& e : edits) {
        Json meta = m_meta;
        e.apply(meta);
        expect_error(with_metadata(meta), e.message, e.what);
    }
    // Unshadowed transfer computed in closed form (the clamped cosine) took no samples.
    Json meta = m_meta;
    meta["samples"] = 0;
    meta["transfer_kind"] = "unshadowed";
    const std::string analytic = (m_dir / "analytic.shprt").string();
    std::ofstream(analytic, std::ios::binary) << with_metadata(meta);
    EXPECT_EQ(read_shprt(analytic).transfer.samples, 0);
}

TEST_F(IoShprtCorrupt, ProbeGridsAreCheckedBeforeTheyAreSized) {
    // The small file with a 2×2×1 grid of 4×4 matrices, probe 3 invalid.
    {
        TransferSet t = read_shprt(m_path).transfer;
        ProbeGrid& g = t.probes;
        g.counts = {2, 2, 1};
        g.K = 4;
        g.valid = {1, 1, 1, 0};
        g.matrices.assign(4 * 16, 0.5f);
        std::fill_n(g.matrices.begin() + 48, 16, 0.0f);
        write_shprt(m_path, small_mesh(), t);
        m_good = read_file(m_path);
        m_meta = Json::parse(m_good.substr(kShprtHeaderSize, header().metadata_length));
        ASSERT_EQ(read_shprt(m_path).transfer.probes, g);
    }
    const struct {
        const char* what;
        void (*apply)(Json&);
        const char* message;
    } edits[] = {
        {"counts huge",
         [](Json& m) {
             m["probes"]["counts"] = {1u << 20, 1u << 20, 1u << 20};
         },
         "metadata.probes: counts"},
        {"counts past the limit",
         [](Json& m) {
             m["probes"]["counts"] = {1024, 1024, 1024};
         },
         "probes (at most"},
        {"counts zero",
         [](Json& m) {
             m["probes"]["counts"] = {0, 2, 1};
         },
         "metadata.probes: counts"},
        {"counts too many",
         [](Json& m) {
             m["probes"]["counts"] = {4, 2, 1};
         },
         "section 'probe_matrices' has shape"},
        {"K", [](Json& m) { m["probes"]["K"] = 9; }, "section 'probe_matrices' has shape"},
        {"K huge", [](Json& m) { m["probes"]["K"] = 1u << 30; }, "field 'K'"},
        {"channels", [](Json& m) { m["probes"]["channels"] = 2; }, "channels must be 1 or 3"},
        {"spacing",
         [](Json& m) {
             m["probes"]["spacing"] = {1, 0, 1};
         },
         "'spacing' must be 3 finite positive numbers"},
        {"origin",
         [](Json& m) {
             m["probes"]["origin"] = {1, "x", 1};
         },
         "'origin' must be 3"},
        {"valid", [](Json& m) { m["probes"]["valid"] = 4; }, "3 valid probes, metadata"},
        {"no description", [](Json& m) { m.erase("probes"); },
         "section 'probe_matrices' where 'transfer' was expected"},
    };
    for (const auto& e : edits) {
        Json meta = m_meta;
        e.apply(meta);
        expect_error(with_metadata(meta), e.message, e.what);
    }
    expect_error(with_section_patch("probe_valid", [](char* p) { p[1] = 2; }),
                 "probe_valid: probe 1 is 2", "a validity of 2");
    expect_error(with_section_patch("probe_matrices",
                                    [](char* p) {
                                        const float inf = INFINITY;
                                        std::memcpy(p + 8, &inf, 4);
                                    }),
                 "probe_matrices: value 2 is not finite", "an infinite matrix entry");
}

TEST_F(IoShprtCorrupt, ProbeCpcaCodesAreChecked) {
    // The small file with a 2×2×1 grid of 4×4 matrices, probe 3 invalid, stored as a code of
    // 2 clusters × 2 vectors.
    {
        TransferSet t = read_shprt(m_path).transfer;
        ProbeGrid g;
        g.counts = {2, 2, 1};
        g.K = 4;
        g.valid = {1, 1, 1, 0};
        g.matrices.assign(4 * 16, 0.0f);
        for (int k = 0; k < 48; ++k) g.matrices[std::size_t(k)] = 0.1f * float(k % 7) - 0.2f;
        CpcaOptions options;
        options.clusters = 2;
        options.vectors = 2;
        t.probes = compress_probes(g, options).compressed;
        write_shprt(m_path, small_mesh(), t);
        m_good = read_file(m_path);
        m_meta = Json::parse(m_good.substr(kShprtHeaderSize, header().metadata_length));
        ASSERT_EQ(read_shprt(m_path).transfer.probes, t.probes);
    }
    const struct {
        const char* what;
        void (*apply)(Json&);
        const char* message;
    } edits[] = {
        {"more clusters than valid probes", [](Json& m) { m["probes"]["cpca"]["clusters"] = 4; },
         "field 'clusters'"},
        {"vectors past channels x K x K", [](Json& m) { m["probes"]["cpca"]["vectors"] = 17; },
         "field 'vectors'"},
        {"clusters changed", [](Json& m) { m["probes"]["cpca"]["clusters"] = 3; },
         "section 'probe_cpca_means' has shape"},
        {"no code described", [](Json& m) { m["probes"].erase("cpca"); },
         "section 'probe_valid' where 'probe_matrices' was expected"},
        {"a code with no valid probe", [](Json& m) { m["probes"]["valid"] = 0; },
         "a CPCA code ('cpca') with no valid probe"},
    };
    for (const auto& e : edits) {
        Json meta = m_meta;
        e.apply(meta);
        expect_error(with_metadata(meta), e.message, e.what);
    }
    expect_error(with_section_patch("probe_cpca_cluster",
                                    [](char* p) {
                                        const std::uint32_t bad = 7;
                                        std::memcpy(p + 4, &bad, 4);
                                    }),
                 "CPCA cluster 7 of receiver 1 is not below 2", "a cluster index out of range");
    expect_error(with_section_patch("probe_cpca_basis",
                                    [](char* p) {
                                        const float nan = NAN;
                                        std::memcpy(p + 12, &nan, 4);
                                    }),
                 "probe_cpca_basis: value 3 is not finite", "a NaN in the basis");
}

TEST_F(IoShprtCorrupt, BadJson) {
    const std::size_t length = header().metadata_length;
    const auto padded = [length](std::string s) {
        s.resize(length, ' ');
        return s;
    };
    expect_error(with_metadata_text(padded("{\"K\": 9,")), "invalid JSON", "unterminated");
    expect_error(with_metadata_text(padded("")), "invalid JSON", "empty");
    expect_error(with_metadata_text(padded("{\"a\": \"\xff\xfe\"}")), "invalid JSON", "bad UTF-8");
    std::string nul(length, ' ');
    nul[0] = '{';
    nul[1] = '\0';
    expect_error(with_metadata_text(nul), "invalid JSON", "NUL");
    // Deep nesting must not exhaust the stack.
    const std::size_t depth = (length - 1) / 2;
    expect_error(with_metadata_text(padded(std::string(depth, '[') + std::string(depth, ']'))),
                 "nested deeper", "deep nesting");
}

TEST_F(IoShprtCorrupt, ContentChecksBehindValidChecksums) {
    const auto put_u32 = [](char* p, std::uint32_t v) { std::memcpy(p, &v, 4); };
    const auto put_f32 = [](char* p, float v) { std::memcpy(p, &v, 4); };
    expect_error(with_section_patch("triangles", [&](char* p) { put_u32(p + 4, 16); }),
                 "triangle 0 uses vertex 16 but the file has 16 vertices", "index out of range");
    expect_error(with_section_patch("positions", [&](char* p) { put_f32(p + 8, 0.5f); }),
                 "scene hash", "hash mismatch");
    expect_error(with_section_patch("transfer", [&](char* p) { put_f32(p + 40, std::nanf("")); }),
                 "transfer: value 10 is not finite", "NaN coefficient");
    expect_error(with_section_patch("normals", [&](char* p) { put_f32(p, INFINITY); }),
                 "normals: value 0 is not finite", "inf normal");
    expect_error(with_section_patch("brdf_index", [&](char* p) { put_u32(p + 8, 2); }),
                 "brdf_index: vertex 2 has BRDF 2 but scene.brdfs lists 2", "BRDF out of range");
}

// What the writer never writes, with valid CRCs: an albedo outside [0, 1], a zero normal.
// (The scene hash, which covers both, is recomputed too: a forger's whole work.)
TEST_F(IoShprtCorrupt, AlbedoOutsideTheUnitRangeAndZeroNormalsAreRefused) {
    const auto forged = [&](const std::string& section, const auto& change) {
        Mesh mesh = small_mesh();
        change(mesh);
        Json meta = m_meta;
        meta["scene"]["hash"] = format_mesh_hash(mesh_hash(mesh));
        const auto& array = section == "albedo" ? mesh.albedo : mesh.normals;
        return with_section_patch(
            section, [&](char* p) { std::memcpy(p, array.data(), array.size() * 12); }, &meta);
    };
    expect_error(forged("albedo", [](Mesh& m) { m.albedo[1].y = 1.5f; }),
                 "albedo: vertex 1 has (0.5, 1.5, 0.125), outside [0, 1]", "albedo 1.5");
    expect_error(forged("albedo", [](Mesh& m) { m.albedo[0].x = -0.25f; }),
                 "albedo: vertex 0 has (-0.25, 0.25, 0), outside [0, 1]", "albedo -0.25");
    expect_error(forged("normals",
                        [](Mesh& m) {
                            m.normals[5] = {0, 0, 0};
                        }),
                 "normals: vertex 5 is zero", "zero normal");
    expect_error(forged("normals",
                        [](Mesh& m) {
                            m.normals.assign(16, {0, 0, 0});
                        }),
                 "normals: vertex 0 is zero", "all-zero normals");
}

TEST_F(IoShprtCorrupt, MaterialBrdfsAreChecked) {
    EXPECT_EQ(read_shprt(m_path).mesh.brdfs,
              (std::vector<Brdf>{{BrdfModel::phong, 32}, {BrdfModel::ggx, 0.25}}));
    Json meta = m_meta;
    meta["scene"]["brdfs"][1] = "ggx:7";
    expect_error(with_metadata(meta), "metadata.scene.brdfs: ggx roughness 7 must be in",
                 "bad spec");
    meta["scene"]["brdfs"][1] = "ggx:0.25:1,1,2";
    expect_error(with_metadata(meta),
                 "metadata.scene.brdfs: specular colour (1, 1, 2) must be in [0, 1]",
                 "bad specular colour");
    meta["scene"]["brdfs"][1] = 3;
    expect_error(with_metadata(meta), "metadata.scene.brdfs: 3 is not a BRDF spec", "not text");
    meta["scene"]["brdfs"] = "phong:3";
    expect_error(with_metadata(meta), "'brdfs' must be an array", "not an array");
    meta["scene"].erase("brdfs");
    expect_error(with_metadata(meta), "section 'brdf_index' and metadata scene.brdfs come together",
                 "no list");
    // Non-zero padding (triangles take 18·12 = 216 bytes, so 40 bytes of padding follow) and
    // trailing bytes.
    std::string bytes = m_good;
    const std::size_t gap = section("triangles")["offset"].get<std::size_t>() + 216;
    ASSERT_LT(gap, section("source_vertex")["offset"].get<std::size_t>());
    bytes[gap + 3] = 'x';
    expect_error(bytes, "non-zero padding byte", "padding");
    expect_error(m_good + std::string(5, '\0'), "5 unexpected bytes after the last section",
                 "trailing");
}

// Random damage: many bytes overwritten at once, anywhere. Each must be an Error, not a crash.
TEST_F(IoShprtCorrupt, RandomMultiByteDamage) {
    std::mt19937 rng(2024);
    for (int trial = 0; trial < 2000; ++trial) {
        std::string bytes = m_good;
        const int hits = 1 + int(rng() % 8);
        for (int i = 0; i < hits; ++i) bytes[rng() % bytes.size()] = char(rng());
        if (bytes == m_good) continue;
        read_error(bytes, fmt::format("trial {}", trial));
    }
}

}  // namespace
}  // namespace shprt
