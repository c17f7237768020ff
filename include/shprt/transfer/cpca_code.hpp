// The clustered-PCA code (transfer/cpca.hpp) as data, apart from the algorithm: the transfer's
// rows and the transfer probes' matrices are both stored as one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

// A clustered-PCA code of rows (Sloan, Hall, Hart & Snyder 2003; transfer/cpca.hpp): row r ≈
// means[c] + Σ_i weights[r][i] · basis[c][i], c = cluster[r], each row D floats. The rows are a
// transfer's (TransferSet::cpca: one per receiver, D = layout.floats_per_receiver()) or transfer
// probes' (ProbeGrid::cpca: one per *valid* probe in probe order, D = channels·K²). Empty
// (clusters == 0) unless the rows came from compress_cpca / compress_probes or a file with a code;
// a file written from rows with a code stores the code instead of the rows (docs/file_format.md,
// "CPCA").
struct CpcaCode {
    int clusters = 0, vectors = 0;
    std::vector<std::uint32_t> cluster;  // rows
    std::vector<float> weights;          // rows × vectors
    std::vector<float> means;            // clusters × D
    std::vector<float> basis;            // clusters × vectors × D
    std::uint64_t seed = 0;              // the k-means++ seed
    bool empty() const { return clusters == 0; }
    bool operator==(const CpcaCode&) const = default;
};

// Error(invalid_argument) unless `code` is none (no clusters, every array empty) or a code of
// `rows` rows of D floats: at least one cluster and one vector, every array its size, every row's
// cluster below the clusters. The one check of a code's sizes: the probe grid's, the reader's and
// the reconstruction's (transfer/cpca.hpp).
void validate(const CpcaCode& code, std::size_t rows, std::size_t D);

}  // namespace shprt
