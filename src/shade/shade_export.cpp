// Writers of per-vertex shading results: CSV, numpy .npy (format 1.0) and .npz (named arrays), and
// binary PLY with display-encoded vertex colours and the exact values. All through AtomicFile.
#include "shprt/shade/shade_export.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/scene/ply.hpp"
#include "shprt/shade/tonemap.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace shprt {
namespace {

// Sizes, and no inf or NaN: a non-finite result is an error, never an output (as for pictures,
// shade/save_image.hpp).
void check_result(const std::string& path, const Mesh& mesh, const ShadeResult& result) {
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(result.irradiance.size() == V && result.radiance.size() == V, invalid_argument,
                "shading result has {} / {} values for {} vertices", result.irradiance.size(),
                result.radiance.size(), V);
    const auto finite = [](Vec3f v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    for (std::size_t v = 0; v < V; ++v)
        SHPRT_CHECK(finite(result.irradiance[v]) && finite(result.radiance[v]), invalid_argument,
                    "cannot write {}: vertex {} shades to a non-finite value (the light or the "
                    "transfer overflows float)",
                    path, v);
}

// The 9 columns of one vertex: x, y, z, E_rgb, L_rgb.
void row(const Mesh& mesh, const ShadeResult& result, std::size_t v, float out[9]) {
    const Vec3f p = mesh.positions[v], e = result.irradiance[v], l = result.radiance[v];
    const float values[9] = {p.x, p.y, p.z, e.x, e.y, e.z, l.x, l.y, l.z};
    std::memcpy(out, values, sizeof(values));
}

// Host must be little-endian for the binary formats (checked once; every supported target is).
void require_little_endian() {
    const std::uint32_t one = 1;
    unsigned char b;
    std::memcpy(&b, &one, 1);
    SHPRT_CHECK(b == 1, unsupported, "binary exports need a little-endian host");
}

}  // namespace

ShadeFormat shade_format_for_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".csv") return ShadeFormat::csv;
    if (ext == ".ply") return ShadeFormat::ply;
    if (ext == ".npy") return ShadeFormat::npy;
    if (ext == ".npz") return ShadeFormat::npz;
    fail(ErrorCode::invalid_argument,
         "output {}: unknown format (expected .csv, .ply, .npy or .npz)", path);
}

void write_shade_csv(const std::string& path, const Mesh& mesh, const ShadeResult& result) {
    check_result(path, mesh, result);
    AtomicFile file(path);
    file.write("x,y,z,E_r,E_g,E_b,L_r,L_g,L_b\n");
    fmt::memory_buffer buffer;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        float r[9];
        row(mesh, result, v, r);
        fmt::format_to(std::back_inserter(buffer),
                       "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", r[0],
                       r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]);
        if (buffer.size() > (1u << 20)) {
            file.write(buffer.data(), buffer.size());
            buffer.clear();
        }
    }
    file.write(buffer.data(), buffer.size());
    file.commit();
}

namespace {

// The bytes of a NumPy .npy file (format 1.0) of float32 `data` with `shape`.
std::string npy_f32_bytes(const std::string& path, const std::vector<std::size_t>& shape,
                          const std::vector<float>& data) {
    require_little_endian();
    std::size_t count = 1;
    std::string dims;
    for (std::size_t d : shape) {
        count *= d;
        dims += fmt::format("{}, ", d);
    }
    if (shape.size() > 1) dims.resize(dims.size() - 2);  // (n,) keeps its comma; (a, b) does not
    SHPRT_CHECK(count == data.size(), invalid_argument, "{}: {} floats for an array of {}", path,
                data.size(), count);
    // Format 1.0: magic, version, uint16 header length, then a Python dict literal padded with
    // spaces and ended by '\n' so that the data starts at a multiple of 64 bytes.
    std::string header =
        fmt::format("{{'descr': '<f4', 'fortran_order': False, 'shape': ({}), }}", dims);
    const std::size_t preamble = 10;
    const std::size_t total = (preamble + header.size() + 1 + 63) / 64 * 64;
    header.append(total - preamble - header.size() - 1, ' ');
    header.push_back('\n');
    SHPRT_CHECK(header.size() <= 65535, invalid_argument, "npy header too long");
    const auto len = static_cast<std::uint16_t>(header.size());
    std::string out = "\x93NUMPY";
    out += {char(1), char(0), char(len & 0xff), char(len >> 8)};
    out += header;
    out.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(float));
    return out;
}

void put16(std::string& out, std::uint32_t x) { out += {char(x & 0xff), char((x >> 8) & 0xff)}; }
void put32(std::string& out, std::uint32_t x) {
    put16(out, x & 0xffff);
    put16(out, x >> 16);
}

// A ZIP archive of `members` stored without compression, as numpy.savez writes (.npz): local
// headers, the data, the central directory and its end record (PKWARE APPNOTE 6.3, §4.3). No
// ZIP64: an archive past 4 GiB is refused.
std::string stored_zip(const std::string& path,
                       const std::vector<std::pair<std::string, std::string>>& members) {
    std::string out, central;
    for (const auto& [name, bytes] : members) {
        SHPRT_CHECK(out.size() + bytes.size() < 0xffffffffu, invalid_argument,
                    "cannot write {}: more than the 4 GiB a .npz without ZIP64 holds", path);
        const auto crc = static_cast<std::uint32_t>(
            crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size())));
        const auto offset = static_cast<std::uint32_t>(out.size());
        const auto size = static_cast<std::uint32_t>(bytes.size());
        // version 2.0, no flags, stored, time and date 0 (1980-01-01; the same bytes every run)
        std::string fields;
        put16(fields, 20);
        put16(fields, 0);
        put16(fields, 0);
        put32(fields, 0);
        put32(fields, crc);
        put32(fields, size);
        put32(fields, size);
        put16(fields, std::uint32_t(name.size()));
        put16(fields, 0);  // extra field length
        put32(out, 0x04034b50);
        out += fields + name + bytes;
        put32(central, 0x02014b50);
        put16(central, 20);  // made by
        central += fields;
        put16(central, 0);  // comment length
        put16(central, 0);  // disk
        put16(central, 0);  // internal attributes
        put32(central, 0);  // external attributes
        put32(central, offset);
        central += name;
    }
    const auto directory = static_cast<std::uint32_t>(out.size());
    out += central;
    put32(out, 0x06054b50);
    put16(out, 0);
    put16(out, 0);
    put16(out, std::uint32_t(members.size()));
    put16(out, std::uint32_t(members.size()));
    put32(out, std::uint32_t(central.size()));
    put32(out, directory);
    put16(out, 0);
    return out;
}

std::vector<float> columns(const std::vector<Vec3f>& values) {
    std::vector<float> out(values.size() * 3);
    if (!values.empty()) std::memcpy(out.data(), values.data(), out.size() * sizeof(float));
    return out;
}

}  // namespace

void write_npy_f32(const std::string& path, const std::vector<std::size_t>& shape,
                   const std::vector<float>& data) {
    const std::string bytes = npy_f32_bytes(path, shape, data);
    AtomicFile file(path);
    file.write(bytes);
    file.commit();
}

void write_shade_npz(const std::string& path, const Mesh& mesh, const ShadeResult& result) {
    check_result(path, mesh, result);
    const std::vector<std::size_t> shape{mesh.vertex_count(), 3};
    const std::string zip = stored_zip(
        path, {{"position.npy", npy_f32_bytes(path, shape, columns(mesh.positions))},
               {"irradiance.npy", npy_f32_bytes(path, shape, columns(result.irradiance))},
               {"radiance.npy", npy_f32_bytes(path, shape, columns(result.radiance))}});
    AtomicFile file(path);
    file.write(zip);
    file.commit();
}

void write_shade_npy(const std::string& path, const Mesh& mesh, const ShadeResult& result) {
    check_result(path, mesh, result);
    const std::size_t V = mesh.vertex_count();
    std::vector<float> data(V * 9);
    for (std::size_t v = 0; v < V; ++v) row(mesh, result, v, data.data() + 9 * v);
    write_npy_f32(path, {V, 9}, data);
}

void write_shade_ply(const std::string& path, const Mesh& mesh, const ShadeResult& result,
                     float exposure) {
    check_result(path, mesh, result);
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "exposure {} must be positive", exposure);
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(mesh.normals.size() == V, invalid_argument,
                "mesh {} has {} normals for {} vertices", mesh.source, mesh.normals.size(), V);
    std::vector<std::array<std::uint8_t, 3>> colours(V);
    for (std::size_t v = 0; v < V; ++v) {
        const Vec3f l = result.radiance[v];
        colours[v] = {display_encode8(l.x, exposure), display_encode8(l.y, exposure),
                      display_encode8(l.z, exposure)};
    }
    // The exact values too, as floats (linear, no exposure): what the colours cannot hold.
    std::vector<PlyFloatProperty> floats;
    for (const auto& [quantity, values] :
         {std::pair{"irradiance", &result.irradiance}, std::pair{"radiance", &result.radiance}})
        for (int c = 0; c < 3; ++c) {
            PlyFloatProperty& f = floats.emplace_back();
            f.name = fmt::format("{}_{}", quantity, "rgb"[c]);
            f.values.resize(V);
            for (std::size_t v = 0; v < V; ++v) f.values[v] = (&(*values)[v].x)[c];
        }
    write_ply(
        mesh, path, &colours,
        fmt::format("shprt shade: colours are radiance L, filmic tone map, sRGB, exposure {}; "
                    "irradiance_* and radiance_* are E and L, linear floats",
                    exposure),
        floats);
}

void write_shade(const std::string& path, const Mesh& mesh, const ShadeResult& result,
                 float exposure) {
    switch (shade_format_for_path(path)) {
        case ShadeFormat::csv:
            write_shade_csv(path, mesh, result);
            break;
        case ShadeFormat::npy:
            write_shade_npy(path, mesh, result);
            break;
        case ShadeFormat::npz:
            write_shade_npz(path, mesh, result);
            break;
        case ShadeFormat::ply:
            write_shade_ply(path, mesh, result, exposure);
            break;
    }
}

}  // namespace shprt
