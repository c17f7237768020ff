// Fixed header of the .shprt file and the CRC-32 used throughout (zlib's, the PNG/gzip one).
#include "shprt/io/shprt_format.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>

namespace shprt {

// Arrays are written from memory as they are; a big-endian port would need byte swaps here and
// in the section writer/reader.
static_assert(std::endian::native == std::endian::little,
              ".shprt I/O assumes a little-endian host");

std::uint32_t encode_shprt_header(const ShprtHeader& header, unsigned char out[kShprtHeaderSize]) {
    std::memcpy(out, kShprtMagic, sizeof kShprtMagic);
    put_u32(out + 12, header.version);
    put_u32(out + 16, header.endian_marker);
    put_u32(out + 20, header.header_size);
    put_u64(out + 24, header.metadata_offset);
    put_u64(out + 32, header.metadata_length);
    put_u32(out + 40, header.metadata_crc32);
    const std::uint32_t crc = crc32(out, 44);
    put_u32(out + 44, crc);
    return crc;
}

ShprtHeader decode_shprt_header(const unsigned char in[kShprtHeaderSize]) {
    ShprtHeader h;
    h.version = get_u32(in + 12);
    h.endian_marker = get_u32(in + 16);
    h.header_size = get_u32(in + 20);
    h.metadata_offset = get_u64(in + 24);
    h.metadata_length = get_u64(in + 32);
    h.metadata_crc32 = get_u32(in + 40);
    h.header_crc32 = get_u32(in + 44);
    return h;
}

std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc) {
    // zlib takes uInt lengths; feed it in pieces so sizes past 4 GiB work.
    const auto* p = static_cast<const Bytef*>(data);
    uLong c = crc;
    while (size > 0) {
        const std::size_t n = std::min<std::size_t>(size, std::size_t(1) << 30);
        c = ::crc32(c, p, static_cast<uInt>(n));
        p += n;
        size -= n;
    }
    return static_cast<std::uint32_t>(c);
}

}  // namespace shprt
