// What `shprt compress` checks of a file's transfer and probes against their CPCA options before
// the fit, and the lines a fit's result is told in (as bake/bake_summary.hpp for a bake): the
// library says them, the shell prints them.
#pragma once

#include "shprt/core/options.hpp"
#include "shprt/transfer/cpca.hpp"
#include "shprt/transfer/probes.hpp"
#include "shprt/transfer/transfer.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace shprt {

// A matrix set's matrices as they are held: "25x25 matrices", or, with a CPCA code (the rows
// rebuilt from it), "CPCA 64x8 (clusters x vectors) of 25x25 matrices".
std::string describe_matrices(const TransferSet& transfer);

// One-line Error(invalid_argument) starting with `what` (e.g. "room.shprt: --cpca 9,4"): more
// clusters than `transfer` has receivers, or more vectors than the floats of one receiver.
void check_cpca_fit(const TransferSet& transfer, const CpcaOptions& options,
                    const std::string& what);
// The same for the transfer probes: a grid without probes, more clusters than valid probes or
// more vectors than channels × K × K.
void check_probe_cpca_fit(const ProbeGrid& probes, const CpcaOptions& options,
                          const std::string& what);

// The lines of `result`, the CPCA of `transfer` (compress_transfer with `options`, float16 code
// when `half`), each ending in '\n': "cpca: ...", "size: ...", "direct part: ..." (an
// interreflected file), "error: ...", "error under LIGHT: ..." (with a light: `light_name` names
// it, e.g. "--light sky.hdr"), "worst vertices: ...".
std::string cpca_summary(const TransferSet& transfer, const CpcaResult& result,
                         const CpcaOptions& options, bool half, const std::string& light_name);
// The lines of the probes' CPCA: "probes: ..." and "probe error: ...".
std::string probe_cpca_summary(const ProbeCpcaResult& result, const CpcaOptions& options,
                               const std::string& light_name);

// `shprt compress`'s options as typed (core/options.hpp): --cpca and --probe-cpca as
// CLUSTERS,VECTORS, and what both fits share.
struct CpcaChoice {
    std::string cpca, probe_cpca;  // "CLUSTERS,VECTORS"; probe_cpca empty: the probes kept
    bool half = false;             // the code as float16 (not the probes')
    std::uint64_t seed = 1;
    int iterations = 16, threads = 0;
};
// One row per option, in the command line's help order.
const std::vector<OptionRow<CpcaChoice>>& cpca_option_table();
// The options of --cpca and of --probe-cpca (none when it is not given), each with the shared
// seed, iterations and threads. One-line Error(invalid_argument) naming the option:
// CLUSTERS,VECTORS not two whole numbers ≥ 1, iterations < 0. The threads are bake's --threads (its
// row of bake/bake_option_table.hpp checks them).
struct CpcaFits {
    CpcaOptions transfer;
    std::optional<CpcaOptions> probes;
};
CpcaFits cpca_options_from(const CpcaChoice& choice);
// The same from numbers (Python's compress()): `rows` for the transfer's rows, and the probes'
// clusters and vectors, when given, with the rows' seed, iterations and threads.
CpcaFits cpca_fits(const CpcaOptions& rows, std::optional<std::pair<int, int>> probes);

// What `shprt compress` and Python's compress() make of a set: its rows' code (compress_transfer
// with fits.transfer, float16 when `half`, the error under `light` too) and, with fits.probes,
// its probes' (compress_probes, under `probe_light`: rows.compressed.probes is then their code;
// without, the probes are kept as they are). A set without probes is refused before the rows'
// fit, and the probes' complaints start with `probe_option` (the option as the front end spells
// it).
struct SetCompression {
    CpcaResult rows;
    std::optional<ProbeCpcaResult> probes;
};
SetCompression compress_set(const TransferSet& transfer, const std::vector<Vec3f>& normals,
                            const CpcaFits& fits, bool half,
                            const std::optional<std::vector<float>>& light,
                            const std::optional<std::vector<float>>& probe_light,
                            const std::string& probe_option);
// `shprt compress`'s lines of `result`, made from `transfer` with `fits`: cpca_summary's, then,
// with the probes' code, probe_cpca_summary's.
std::string compress_summary(const TransferSet& transfer, const SetCompression& result,
                             const CpcaFits& fits, bool half, const std::string& light_name);

}  // namespace shprt
