// Binary little-endian PLY writer (Turk, "The PLY polygon file format", 1994).
#include "shprt/scene/ply.hpp"

#include "shprt/core/colour.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <bit>
#include <cstring>
#include <string>

namespace shprt {
namespace {

constexpr std::size_t kBufferBytes = 1 << 20;

// Appends the little-endian bytes of a 4-byte value.
template <class T>
void put32(std::string& out, T value) {
    static_assert(sizeof(T) == 4);
    std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
    char bytes[4];
    std::memcpy(bytes, &bits, 4);
    out.append(bytes, 4);
}

// PLY comments end at the newline; keep the text on one printable line.
std::string one_line(std::string_view s) {
    std::string r;
    for (char c : s) r += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    return r;
}

}  // namespace

void write_ply(const Mesh& mesh, const std::string& path,
               const std::vector<std::array<std::uint8_t, 3>>* colours, std::string_view comment,
               const std::vector<PlyFloatProperty>& floats) {
    const std::size_t nv = mesh.positions.size();
    SHPRT_CHECK(mesh.normals.empty() || mesh.normals.size() == nv, invalid_argument,
                "{}: {} normals for {} vertices", path, mesh.normals.size(), nv);
    SHPRT_CHECK(mesh.albedo.empty() || mesh.albedo.size() == nv, invalid_argument,
                "{}: {} albedo values for {} vertices", path, mesh.albedo.size(), nv);
    SHPRT_CHECK(!colours || colours->size() == nv, invalid_argument,
                "{}: {} colours for {} vertices", path, colours ? colours->size() : 0, nv);
    for (const PlyFloatProperty& f : floats)
        SHPRT_CHECK(f.values.size() == nv, invalid_argument, "{}: {} values of {} for {} vertices",
                    path, f.values.size(), f.name, nv);
    const bool has_normals = !mesh.normals.empty();
    const bool has_colours = colours || !mesh.albedo.empty();
    const bool has_uvs = mesh.uvs.size() == nv && nv > 0;

    std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by shprt";
    if (!mesh.source.empty()) header += "\ncomment source " + one_line(mesh.source);
    if (!comment.empty()) header += "\ncomment " + one_line(comment);
    header += fmt::format(
        "\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n", nv);
    if (has_normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (has_colours) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (has_uvs) header += "property float s\nproperty float t\n";  // Assimp reads them as UV set 0
    for (const PlyFloatProperty& f : floats) header += "property float " + one_line(f.name) + "\n";
    header += fmt::format("element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
                          mesh.triangles.size());

    AtomicFile file(path);
    file.write(header);
    std::string buffer;
    buffer.reserve(kBufferBytes + 64);
    auto flush_if_full = [&] {
        if (buffer.size() >= kBufferBytes) {
            file.write(buffer);
            buffer.clear();
        }
    };
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3f p = mesh.positions[v];
        put32(buffer, p.x);
        put32(buffer, p.y);
        put32(buffer, p.z);
        if (has_normals) {
            const Vec3f n = mesh.normals[v];
            put32(buffer, n.x);
            put32(buffer, n.y);
            put32(buffer, n.z);
        }
        if (has_colours) {
            std::array<std::uint8_t, 3> c;
            if (colours)
                c = (*colours)[v];
            else {
                const Vec3f a = mesh.albedo[v];
                c = {linear_to_srgb8(a.x), linear_to_srgb8(a.y), linear_to_srgb8(a.z)};
            }
            buffer.append(reinterpret_cast<const char*>(c.data()), 3);
        }
        if (has_uvs) {
            put32(buffer, mesh.uvs[v][0]);
            put32(buffer, mesh.uvs[v][1]);
        }
        for (const PlyFloatProperty& f : floats) put32(buffer, f.values[v]);
        flush_if_full();
    }
    for (const auto& t : mesh.triangles) {
        buffer.push_back(3);
        for (std::uint32_t i : t) put32(buffer, i);
        flush_if_full();
    }
    file.write(buffer);
    file.commit();
}

}  // namespace shprt
