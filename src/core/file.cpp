#include "shprt/core/file.hpp"

#include "shprt/core/error.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace shprt {
namespace {
std::atomic<unsigned> g_counter{0};
}

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)) {
    SHPRT_CHECK(!m_path.empty(), invalid_argument, "output path is empty");
    m_temp = fmt::format("{}.tmp.{}.{}", m_path, ::getpid(), g_counter++);
    m_file = std::fopen(m_temp.c_str(), "wb");
    SHPRT_CHECK(m_file != nullptr, io, "cannot write {}: {}", m_path, std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (m_file) std::fclose(m_file);
    if (!m_committed) std::remove(m_temp.c_str());
}

void AtomicFile::write(const void* data, std::size_t size) {
    SHPRT_CHECK(m_file != nullptr, io, "write to {} after commit", m_path);
    if (size == 0) return;
    SHPRT_CHECK(std::fwrite(data, 1, size, m_file) == size, io, "cannot write {}: {}", m_path,
                std::strerror(errno));
}

void AtomicFile::commit() {
    SHPRT_CHECK(m_file != nullptr, io, "{} committed twice", m_path);
    const bool flushed = std::fflush(m_file) == 0;
    const int err = errno;
    const bool closed = std::fclose(m_file) == 0;
    m_file = nullptr;
    SHPRT_CHECK(flushed && closed, io, "cannot write {}: {}", m_path, std::strerror(err));
    SHPRT_CHECK(std::rename(m_temp.c_str(), m_path.c_str()) == 0, io, "cannot rename {} to {}: {}",
                m_temp, m_path, std::strerror(errno));
    m_committed = true;
}

bool same_file(const std::string& a, const std::string& b) {
    struct stat sa {
    }, sb{};
    return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

void check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs) {
    for (const std::string& input : inputs)
        SHPRT_CHECK(!same_file(output, input), invalid_argument,
                    "output {} is the input file {} (the same file); choose another output name",
                    output, input);
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    SHPRT_CHECK(in.good(), io, "cannot open {}: {}", path, std::strerror(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    SHPRT_CHECK(!in.bad(), io, "cannot read {}", path);
    return ss.str();
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

void pwrite_all(int fd, const void* data, std::size_t size, std::uint64_t offset,
                const std::string& what) {
    const auto* p = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const ssize_t n = ::pwrite(fd, p, size, static_cast<off_t>(offset));
        if (n < 0 && errno == EINTR) continue;
        SHPRT_CHECK(n > 0, io, "cannot write {} at offset {}: {}", what, offset,
                    n < 0 ? std::strerror(errno) : "no progress");
        p += n;
        offset += static_cast<std::uint64_t>(n);
        size -= static_cast<std::size_t>(n);
    }
}

}  // namespace shprt
