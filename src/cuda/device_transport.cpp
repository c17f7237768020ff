// The bounces of an interreflected bake on the device (gpu_bake_device.hpp, DeviceTransport):
// A's blocks as cuSPARSE CSR matrices, each bounce one SpMM per block and channel.
//
// The transfer layout is receiver-major with the three channels of a receiver side by side
// (channel c of receiver v at (v·3 + c)·K), so channel c of the whole input is a row-major dense
// V × K matrix at in + c·K with leading dimension 3K, and a block's output rows likewise: cuSPARSE
// takes row-major dense matrices with ld ≥ cols, so nothing is repacked.
#include "cuda/cusparse_loader.hpp"
#include "cuda/device_buffer.hpp"
#include "cuda/gpu_bake_device.hpp"
#include "cuda/gpu_context.hpp"
#include "shprt/core/error.hpp"

#include <vector>

namespace shprt::cuda {

struct DeviceTransport::Impl {
    struct Block {
        std::size_t first = 0, rows = 0;
        DeviceBuffer<std::int32_t> row_start, column;
        DeviceBuffer<float> values[3];
        cusparseSpMatDescr_t matrix[3] = {};
    };
    int device = 0;
    int K = 0;
    std::size_t V = 0;
    MemoryTally tally;
    std::vector<std::unique_ptr<Block>> blocks;
    DeviceBuffer<float> in, out;  // V × 3K each
    DeviceBuffer<unsigned char> workspace;
    cusparseHandle_t handle = nullptr;
    cusparseDnMatDescr_t x[3] = {};  // channel c of `in`: V × K, ld 3K
    double seconds = 0;

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
};

DeviceTransport::DeviceTransport(int device, const TransportOperator& A, int K)
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
    std::size_t workspace = 0;
    const float one = 1.0f, zero = 0.0f;
    for (const TransportOperator::Block& b : A.blocks) {
        auto d = std::make_unique<Impl::Block>();
        d->first = b.first;
        d->rows = b.rows();
        d->row_start = DeviceBuffer<std::int32_t>(b.rows() + 1, &m.tally);
        d->row_start.upload(b.starts(), b.rows() + 1);
        const std::size_t nnz = b.nnz();
        d->column = DeviceBuffer<std::int32_t>(std::max<std::size_t>(nnz, 1), &m.tally);
        if (nnz) d->column.upload(b.columns(), nnz);
        for (int c = 0; c < 3; ++c) {
            d->values[c] = DeviceBuffer<float>(std::max<std::size_t>(nnz, 1), &m.tally);
            if (nnz) d->values[c].upload(b.channel(c), nnz);
            SHPRT_CUDA_CHECK(api.create_csr(
                &d->matrix[c], std::int64_t(d->rows), std::int64_t(m.V), std::int64_t(nnz),
                d->row_start.data(), d->column.data(), d->values[c].data(), CUSPARSE_INDEX_32I,
                CUSPARSE_INDEX_32I, CUSPARSE_INDEX_BASE_ZERO, CUDA_R_32F));
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

}  // namespace shprt::cuda
