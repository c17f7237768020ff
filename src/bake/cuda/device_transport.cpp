// The bounces of an interreflected bake on the device (gpu_bake_device.hpp, DeviceTransport):
// A's blocks as cuSPARSE CSR matrices, each bounce one SpMM per block and channel. The blocks that
// do not fit the device (plan_transport_residency) are copied in per bounce through one set of
// staging buffers, in order on the same stream as the products: the same products, the same bits.
//
// The transfer layout is receiver-major with the three channels of a receiver side by side
// (channel c of receiver v at (v·3 + c)·K), so channel c of the whole input is a row-major dense
// V × K matrix at in + c·K with leading dimension 3K, and a block's output rows likewise: cuSPARSE
// takes row-major dense matrices with ld ≥ cols, so nothing is repacked.
#include "bake/cuda/cusparse_loader.hpp"
#include "bake/cuda/device_buffer.hpp"
#include "bake/cuda/gpu_bake_device.hpp"
#include "bake/cuda/gpu_context.hpp"
#include "shprt/core/error.hpp"

#include <algorithm>
#include <vector>

namespace shprt::cuda {

struct DeviceTransport::Impl {
    struct Block {
        std::size_t first = 0, rows = 0, nnz = 0;
        // A resident block's arrays; a streamed block's matrices point into the staging buffers
        // and `host` is where its arrays are copied from, per bounce.
        DeviceBuffer<std::int32_t> row_start, column;
        DeviceBuffer<float> values[3];
        const TransportOperator::Block* host = nullptr;
        cusparseSpMatDescr_t matrix[3] = {};
    };
    int device = 0;
    int K = 0;
    std::size_t V = 0;
    MemoryTally tally;
    std::vector<std::unique_ptr<Block>> blocks;
    DeviceBuffer<float> in, out;  // V × 3K each
    DeviceBuffer<unsigned char> workspace;
    // The staging buffers of the streamed blocks: as large as the largest of them.
    DeviceBuffer<std::int32_t> staging_row_start, staging_column;
    DeviceBuffer<float> staging_values[3];
    cusparseHandle_t handle = nullptr;
    cusparseDnMatDescr_t x[3] = {};  // channel c of `in`: V × K, ld 3K
    double seconds = 0;
    std::uint64_t streamed_bytes = 0;  // the streamed blocks' bytes, copied in per bounce

    ~Impl() {
        const CusparseApi& api = cusparse();
        for (auto& b : blocks)
            for (cusparseSpMatDescr_t m : b->matrix)
                if (m) api.destroy_sp_mat(m);
        for (cusparseDnMatDescr_t d : x)
            if (d) api.destroy_dn_mat(d);
        if (handle) api.destroy(handle);
    }

    // The dense descriptor of channel c of rows [first, first + rows) of `buffer`.
    cusparseDnMatDescr_t dense(float* buffer, std::size_t first, std::size_t rows, int c) const {
        cusparseDnMatDescr_t d = nullptr;
        const std::size_t stride = 3 * std::size_t(K);
        SHPRT_CUDA_CHECK(cusparse().create_dn_mat(&d, std::int64_t(rows), K, std::int64_t(stride),
                                                  buffer + first * stride + std::size_t(c) * K,
                                                  CUDA_R_32F, CUSPARSE_ORDER_ROW));
        return d;
    }

    // Copies a streamed block's arrays into the staging buffers, on `stream` (after the products
    // that read the previous one: the same stream).
    void stage(const Block& b, cudaStream_t stream) {
        const TransportOperator::Block& h = *b.host;
        const auto put = [&](void* device_ptr, const void* host_ptr, std::size_t bytes) {
            if (bytes)
                SHPRT_CUDA_CHECK(
                    cudaMemcpyAsync(device_ptr, host_ptr, bytes, cudaMemcpyHostToDevice, stream));
        };
        put(staging_row_start.data(), h.starts(), (b.rows + 1) * sizeof(std::int32_t));
        put(staging_column.data(), h.columns(), b.nnz * sizeof(std::int32_t));
        for (int c = 0; c < 3; ++c)
            put(staging_values[c].data(), h.channel(c), b.nnz * sizeof(float));
    }
};

DeviceTransport::DeviceTransport(int device, const TransportOperator& A, int K,
                                 std::size_t resident_blocks)
    : m_impl(std::make_unique<Impl>()) {
    Impl& m = *m_impl;
    const CusparseApi& api = cusparse();  // throws without the library: before any allocation
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    m.device = device;
    m.K = K;
    m.V = A.vertices;
    const std::size_t floats = m.V * 3 * std::size_t(K);
    m.in = DeviceBuffer<float>(floats, &m.tally);
    m.out = DeviceBuffer<float>(floats, &m.tally);
    SHPRT_CUDA_CHECK(api.create(&m.handle));
    SHPRT_CUDA_CHECK(api.set_stream(m.handle, context.streams[0]));
    for (int c = 0; c < 3; ++c) m.x[c] = m.dense(m.in.data(), 0, m.V, c);
    // The staging buffers first, as large as the largest streamed block.
    std::size_t staging_rows = 0, staging_nnz = 0;
    for (std::size_t i = resident_blocks; i < A.blocks.size(); ++i) {
        staging_rows = std::max(staging_rows, A.blocks[i].rows());
        staging_nnz = std::max(staging_nnz, A.blocks[i].nnz());
    }
    if (resident_blocks < A.blocks.size()) {
        m.staging_row_start = DeviceBuffer<std::int32_t>(staging_rows + 1, &m.tally);
        m.staging_column =
            DeviceBuffer<std::int32_t>(std::max<std::size_t>(staging_nnz, 1), &m.tally);
        for (auto& v : m.staging_values)
            v = DeviceBuffer<float>(std::max<std::size_t>(staging_nnz, 1), &m.tally);
    }
    std::size_t workspace = 0;
    const float one = 1.0f, zero = 0.0f;
    for (std::size_t i = 0; i < A.blocks.size(); ++i) {
        const TransportOperator::Block& b = A.blocks[i];
        auto d = std::make_unique<Impl::Block>();
        d->first = b.first;
        d->rows = b.rows();
        d->nnz = b.nnz();
        const std::int32_t* row_start = m.staging_row_start.data();
        const std::int32_t* column = m.staging_column.data();
        const float* values[3] = {m.staging_values[0].data(), m.staging_values[1].data(),
                                  m.staging_values[2].data()};
        if (i < resident_blocks) {
            d->row_start = DeviceBuffer<std::int32_t>(d->rows + 1, &m.tally);
            d->row_start.upload(b.starts(), d->rows + 1);
            d->column = DeviceBuffer<std::int32_t>(std::max<std::size_t>(d->nnz, 1), &m.tally);
            d->column.upload(b.columns(), d->nnz);
            row_start = d->row_start.data();
            column = d->column.data();
            for (int c = 0; c < 3; ++c) {
                d->values[c] = DeviceBuffer<float>(std::max<std::size_t>(d->nnz, 1), &m.tally);
                d->values[c].upload(b.channel(c), d->nnz);
                values[c] = d->values[c].data();
            }
        } else {
            d->host = &b;
            m.streamed_bytes += b.bytes();
        }
        for (int c = 0; c < 3; ++c) {
            SHPRT_CUDA_CHECK(api.create_csr(
                &d->matrix[c], std::int64_t(d->rows), std::int64_t(m.V), std::int64_t(d->nnz),
                const_cast<std::int32_t*>(row_start), const_cast<std::int32_t*>(column),
                const_cast<float*>(values[c]), CUSPARSE_INDEX_32I, CUSPARSE_INDEX_32I,
                CUSPARSE_INDEX_BASE_ZERO, CUDA_R_32F));
            cusparseDnMatDescr_t y = m.dense(m.out.data(), d->first, d->rows, c);
            std::size_t bytes = 0;
            const cusparseStatus_t status = api.spmm_buffer_size(
                m.handle, CUSPARSE_OPERATION_NON_TRANSPOSE, CUSPARSE_OPERATION_NON_TRANSPOSE, &one,
                d->matrix[c], m.x[c], &zero, y, CUDA_R_32F, CUSPARSE_SPMM_ALG_DEFAULT, &bytes);
            api.destroy_dn_mat(y);
            SHPRT_CUDA_CHECK(status);
            workspace = std::max(workspace, bytes);
        }
        m.blocks.push_back(std::move(d));
    }
    m.workspace = DeviceBuffer<unsigned char>(std::max<std::size_t>(workspace, 1), &m.tally);
}

DeviceTransport::~DeviceTransport() {
    if (!m_impl) return;
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    cudaSetDevice(gpu_context(m_impl->device).device);
    m_impl.reset();
}

void DeviceTransport::apply(const float* in, float* out) {
    Impl& m = *m_impl;
    const CusparseApi& api = cusparse();
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(m.device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    const cudaStream_t stream = context.streams[0];
    const std::size_t bytes = m.in.bytes();
    SHPRT_CUDA_CHECK(cudaMemcpyAsync(m.in.data(), in, bytes, cudaMemcpyHostToDevice, stream));
    Event start, stop;
    start.record(stream);
    const float one = 1.0f, zero = 0.0f;
    for (const auto& b : m.blocks) {
        if (b->rows == 0) continue;
        if (b->host) m.stage(*b, stream);
        for (int c = 0; c < 3; ++c) {
            cusparseDnMatDescr_t y = m.dense(m.out.data(), b->first, b->rows, c);
            const cusparseStatus_t status =
                api.spmm(m.handle, CUSPARSE_OPERATION_NON_TRANSPOSE,
                         CUSPARSE_OPERATION_NON_TRANSPOSE, &one, b->matrix[c], m.x[c], &zero, y,
                         CUDA_R_32F, CUSPARSE_SPMM_ALG_DEFAULT, m.workspace.data());
            api.destroy_dn_mat(y);
            SHPRT_CUDA_CHECK(status);
        }
    }
    stop.record(stream);
    SHPRT_CUDA_CHECK(cudaMemcpyAsync(out, m.out.data(), bytes, cudaMemcpyDeviceToHost, stream));
    SHPRT_CUDA_CHECK(cudaStreamSynchronize(stream));
    m.seconds += elapsed_seconds(start, stop);
}

std::uint64_t DeviceTransport::device_bytes() const { return m_impl->tally.peak; }

double DeviceTransport::seconds() const { return m_impl->seconds; }

std::uint64_t DeviceTransport::streamed_bytes() const { return m_impl->streamed_bytes; }

}  // namespace shprt::cuda
