// Private to the scene library: a strict check of a PLY header before Assimp parses the file.
// Assimp 5.2.5 hangs on a header without a clean end_header line and allocates whatever element
// counts a corrupt header declares, so load_scene vets PLY headers itself first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace shprt::detail {

// Bytes of a file read to find its header; PLY headers are far shorter.
constexpr std::size_t kMaxPlyHeader = 1 << 16;

struct PlyHeader {
    std::uint64_t vertices = 0;  // count of the "vertex" element
    bool colours_8bit = false;   // vertex red declared as an 8-bit integer: sRGB bytes (Assimp
                                 // divides them by 255); float colours are taken as linear
    bool has_material = false;   // an "element material"; otherwise Assimp's material is a white
                                 // placeholder of its own
    // Header lines that are no PLY keyword (Blender 2.47 wrote "Created by Blender3D ..." without
    // "comment"): read as comments, as Assimp reads them. How many, and the first one's number and
    // text, for the loader's warning.
    int unknown_lines = 0;
    int first_unknown_line = 0;
    std::string first_unknown;
};

// True when `prefix` (the first bytes of a file) starts with the PLY magic line.
bool looks_like_ply(const std::string& prefix);

// Parses and checks the header in `prefix` (the first min(kMaxPlyHeader, file_size) bytes of a
// file of `file_size` bytes): the magic line, a known format, known property types, identifier
// element names with decimal counts, a vertex element with x, y and z, an exact end_header line,
// and element counts that the bytes after the header can hold. A line that is no keyword is
// counted and passed over (PlyHeader::unknown_lines), unless it begins like end_header (Assimp
// never returns on a corrupt one). Throws Error(format) naming `path` and the problem.
PlyHeader check_ply_header(const std::string& path, const std::string& prefix,
                           std::uintmax_t file_size);

// The same bound for OFF files (Assimp 5.2.5 allocates the counts on an OFF file's first lines
// before it reads a vertex: a 130-byte file claiming 1e8 vertices took 1.2 GB and 1.5 s, Assimp's
// own invalid/OutOfMemory.off claims 3.5e11). When `prefix` (the first bytes of a file of
// `file_size` bytes) starts, after '#' comment lines, with the token OFF, COFF or NOFF and then
// the vertex and face counts, checks that the rest of the file can hold them: an ASCII vertex
// takes at least 6 bytes ("0 0 0\n"), a face at least 8 ("3 0 1 2\n"). Throws Error(format)
// naming `path` and the counts when it cannot; anything else (another header, unparsable counts)
// is left to Assimp.
void check_off_header(const std::string& path, const std::string& prefix, std::uintmax_t file_size);

}  // namespace shprt::detail
