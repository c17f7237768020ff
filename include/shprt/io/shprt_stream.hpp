// A .shprt file written while its transfer rows are baked (`shprt bake --stream`): the file is
// laid out before the bake, the mesh sections written, and the bake's rows go straight into the
// transfer section of the (temporary) file through sink(), chunk by chunk, in any order. No V×K
// array is ever in memory: a bake's peak is its BVH and chunk buffers (BakeStats). commit() then
// writes the metadata (the transfer's CRC-32 is combined from the chunks' CRCs with zlib's
// crc32_combine, so nothing is read back) and the header, and renames the file into place; until
// then, and if the bake fails, nothing exists at the path (AtomicFile).
//
// The file is the same as write_shprt's for the same mesh, transfer and options, except that the
// metadata is padded with spaces to the length reserved before the bake (the reader accepts it:
// JSON allows trailing white space, and the layout stays canonical).
#pragma once

#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/transfer/sink.hpp"

#include <cstddef>
#include <memory>
#include <string>

namespace shprt {

class ShprtStreamWriter {
public:
    // Lays out the file for `mesh` and rows of receivers [first, first + count) described by
    // `info` (kind, layout with its encoding, sampling; the stats come with commit()), writes all
    // but the transfer rows into the temporary file. Throws what write_shprt throws for a bad mesh
    // or layout, Error(io) when the file cannot be written.
    ShprtStreamWriter(const std::string& path, const Mesh& mesh, const TransferInfo& info,
                      std::size_t first, std::size_t count, WriteOptions options = {});
    ~ShprtStreamWriter();
    ShprtStreamWriter(const ShprtStreamWriter&) = delete;
    ShprtStreamWriter& operator=(const ShprtStreamWriter&) = delete;

    // The sink for the bake: rows of the range above in `info`'s layout; a row with a value that
    // is not finite (or out of float16's range for float16) is refused (Error(invalid_argument)).
    TransferSink& sink();
    // Finishes the file: every row must have been written. `info` is the bake's final
    // description (the stats it returned); its kind, layout and sampling must be those given to
    // the constructor. Throws Error(invalid_argument) otherwise, Error(io) on a write failure.
    void commit(const TransferInfo& info);

private:
    struct State;
    std::unique_ptr<State> m_state;
};

}  // namespace shprt
