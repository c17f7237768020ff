// Byte-level layout of the .shprt file (docs/file_format.md is the full specification): the
// fixed header, its encoding, and the constants readers and writers share. Most code wants
// io/shprt_file.hpp instead; this header is for tools and tests that inspect files directly.
#pragma once

#include <cstddef>
#include <cstdint>

namespace shprt {

// Little-endian fields of fixed headers (the .shprt header, the bake checkpoint's).
inline void put_u32(unsigned char* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
inline void put_u64(unsigned char* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
inline std::uint32_t get_u32(const unsigned char* p) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}
inline std::uint64_t get_u64(const unsigned char* p) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

// 12-byte magic. 0x89 (high bit set) catches 7-bit channels and marks the file as binary; "\r\n"
// catches CRLF -> LF conversion, the lone "\n" LF -> CRLF conversion; 0x1a stops DOS `type`;
// the NULs catch C-string handling.
inline constexpr unsigned char kShprtMagic[12] = {0x89, 'S',  'H',  'P',  'R', 'T',
                                                  '\r', '\n', 0x1a, '\n', 0,   0};
inline constexpr std::size_t kShprtHeaderSize = 48;  // bytes of the fixed header (version 1)
inline constexpr std::uint32_t kShprtEndianMarker = 0x01020304u;  // stored as 04 03 02 01
inline constexpr std::uint64_t kShprtAlignment = 64;  // every section starts at a multiple of 64
inline constexpr std::uint64_t kShprtMaxMetadataBytes = 16u << 20;  // sanity cap on the JSON

// The SH convention every .shprt file declares in metadata "convention"."basis" (the paper's,
// Green 2003); a reader refuses a file that declares another.
inline constexpr const char* kShprtConventionBasis =
    "real SH, Condon\u2013Shortley phase, index l(l+1)+m, theta from +Z, phi from +X toward +Y";

// The fixed header, all fields little-endian:
//   offset size field
//        0   12 magic (kShprtMagic)
//       12    4 version          uint32, kShprtFormatVersion
//       16    4 endian_marker    uint32, kShprtEndianMarker
//       20    4 header_size      uint32, 48
//       24    8 metadata_offset  uint64, 48 (the JSON follows the header)
//       32    8 metadata_length  uint64, bytes of UTF-8 JSON
//       40    4 metadata_crc32   uint32, CRC-32 (zlib) of the JSON bytes
//       44    4 header_crc32     uint32, CRC-32 of header bytes 0..43
struct ShprtHeader {
    std::uint32_t version = 0;
    std::uint32_t endian_marker = 0;
    std::uint32_t header_size = 0;
    std::uint64_t metadata_offset = 0;
    std::uint64_t metadata_length = 0;
    std::uint32_t metadata_crc32 = 0;
    std::uint32_t header_crc32 = 0;
};

// Writes the 48 header bytes (magic included) to `out`, computing header_crc32 over bytes 0..43
// (the value in `header.header_crc32` is ignored). Returns that CRC.
std::uint32_t encode_shprt_header(const ShprtHeader& header, unsigned char out[kShprtHeaderSize]);

// Decodes the fields of a 48-byte header without validating anything (the magic is not part of
// the struct; compare the first 12 bytes with kShprtMagic yourself).
ShprtHeader decode_shprt_header(const unsigned char in[kShprtHeaderSize]);

// zlib's CRC-32 (the PNG/gzip polynomial) of `size` bytes, continuing from `crc` (0 to start);
// any size, including more than 4 GiB.
std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0);

// Rounds `offset` up to the next multiple of kShprtAlignment.
constexpr std::uint64_t shprt_align(std::uint64_t offset) {
    return (offset + kShprtAlignment - 1) / kShprtAlignment * kShprtAlignment;
}

}  // namespace shprt
