// The library's sinks (sink.hpp).
#include "shprt/transfer/sink.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/memory.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <numeric>

namespace shprt {
namespace {

void check_range(std::size_t first, std::size_t count, std::size_t begun_first,
                 std::size_t begun_count) {
    SHPRT_CHECK(
        first >= begun_first && count <= begun_count && first - begun_first <= begun_count - count,
        invalid_argument, "rows [{}, {}) outside the sink's range [{}, {})", first, first + count,
        begun_first, begun_first + begun_count);
}

}  // namespace

void HostSink::begin(const TransferLayout& layout, std::size_t first, std::size_t count) {
    layout.validate();
    m_layout = layout;
    m_first = first;
    m_count = count;
    assign_huge(m_rows, layout.floats(count));
    m_samples.clear();
    m_errors.clear();
}

float* HostSink::host_rows(std::size_t first, std::size_t count) {
    check_range(first, count, m_first, m_count);
    return m_rows.data() + m_layout.floats(first - m_first);
}

void HostSink::write(std::size_t first, std::size_t count, const float* rows) {
    float* target = host_rows(first, count);
    if (rows != nullptr && rows != target)
        std::memcpy(target, rows, m_layout.floats(count) * sizeof(float));
}

void HostSink::begin_estimates() {
    m_samples.assign(m_count, 0);
    m_errors.assign(m_count, 0.0f);
}

void HostSink::write_estimates(std::size_t first, std::size_t count, const std::uint32_t* samples,
                               const float* errors) {
    check_range(first, count, m_first, m_count);
    SHPRT_CHECK(m_samples.size() == m_count, invalid_argument,
                "host sink: estimates written before begin_estimates()");
    std::copy(samples, samples + count, m_samples.begin() + std::ptrdiff_t(first - m_first));
    std::copy(errors, errors + count, m_errors.begin() + std::ptrdiff_t(first - m_first));
}

void FileRegionSink::begin(const TransferLayout& layout, std::size_t first, std::size_t count) {
    layout.validate();
    SHPRT_CHECK(layout.encoding == TransferEncoding::f32, invalid_argument,
                "a file region sink writes float32 rows, not {}", to_string(layout.encoding));
    SHPRT_CHECK(m_fd >= 0, invalid_argument, "file region sink without an open file");
    m_layout = layout;
    m_first = first;
    m_count = count;
    m_bytes = std::uint64_t(layout.floats(count)) * sizeof(float);
}

void FileRegionSink::write(std::size_t first, std::size_t count, const float* rows) {
    check_range(first, count, m_first, m_count);
    SHPRT_CHECK(rows != nullptr, invalid_argument, "file region sink: no rows to write");
    pwrite_all(m_fd, rows, m_layout.floats(count) * sizeof(float),
               m_offset + std::uint64_t(m_layout.floats(first - m_first)) * sizeof(float),
               "transfer rows");
}

void DeviceSink::begin(const TransferLayout& layout, std::size_t first, std::size_t count) {
    layout.validate();
    SHPRT_CHECK(m_device != nullptr, invalid_argument, "device sink without a device buffer");
    SHPRT_CHECK(layout.floats(count) <= m_capacity, invalid_argument,
                "device buffer holds {} floats, the rows need {}", m_capacity,
                layout.floats(count));
    m_first = first;
    m_count = count;
    m_chunks = 0;
}

void DeviceSink::write(std::size_t first, std::size_t count, const float*) {
    check_range(first, count, m_first, m_count);
    ++m_chunks;
}

std::vector<ReceiverSpan> remaining_spans(std::size_t first, std::size_t count,
                                          std::vector<ReceiverSpan> done) {
    std::sort(done.begin(), done.end(),
              [](const ReceiverSpan& a, const ReceiverSpan& b) { return a.first < b.first; });
    std::vector<ReceiverSpan> gaps;
    std::size_t at = first;  // everything before `at` is covered or outside
    const std::size_t end = first + count;
    for (const ReceiverSpan& d : done) {
        if (d.count == 0 || d.first + d.count <= at) continue;
        if (d.first >= end) break;
        if (d.first > at) gaps.push_back({at, d.first - at});
        at = std::max(at, d.first + d.count);
    }
    if (at < end) gaps.push_back({at, end - at});
    return gaps;
}

SpanOrder order_spans(const std::vector<ReceiverSpan>& spans) {
    SpanOrder out;
    out.order.resize(spans.size());
    std::iota(out.order.begin(), out.order.end(), std::size_t(0));
    std::stable_sort(out.order.begin(), out.order.end(),
                     [&](std::size_t a, std::size_t b) { return spans[a].first < spans[b].first; });
    // The non-empty span reaching furthest so far: any later span starting before its end
    // shares a receiver with it.
    std::optional<std::size_t> reach;
    for (std::size_t i : out.order) {
        const ReceiverSpan& s = spans[i];
        if (s.count == 0) continue;
        if (reach && s.first < spans[*reach].first + spans[*reach].count) {
            out.overlap = std::pair{*reach, i};
            break;
        }
        if (!reach || s.first + s.count > spans[*reach].first + spans[*reach].count) reach = i;
    }
    return out;
}

}  // namespace shprt
