#include "shprt/core/file.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

namespace shprt {
namespace {
std::atomic<unsigned> g_counter{0};

// The temporary files alive in this process, for the termination handler: fixed slots, so that
// the handler only reads memory that stays put and calls unlink (async-signal-safe). A slot is
// free (0), being filled (1) or live (2).
constexpr std::size_t kTempSlots = 64;
std::array<std::atomic<int>, kTempSlots> g_slot_state{};
std::array<std::array<char, PATH_MAX>, kTempSlots> g_slot_path{};

// The files this process read as input (note_input_file).
std::mutex g_inputs_mutex;
std::vector<std::string> g_inputs;

// The last output renamed into place, for signal handlers (committed_output): g_renaming counts
// the renames in progress; g_committed_path is filled before g_has_committed turns true.
std::atomic<int> g_renaming{0};
std::atomic<bool> g_has_committed{false};
std::array<char, PATH_MAX> g_committed_path{};

// What `mode` is, for the refusal of a non-regular output.
const char* file_kind(mode_t mode) {
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

// Test hook (tests/cli/test_cli_late_signal.cpp): SHPRT_TEST_STOP_AT=renamed stops the process
// (SIGSTOP) right after an output's rename, while the interrupt signals are still held, so that a
// test can send one in that window.
void test_stop_after_rename() {
    const char* wanted = std::getenv("SHPRT_TEST_STOP_AT");
    if (wanted != nullptr && std::strcmp(wanted, "renamed") == 0) ::raise(SIGSTOP);
}

extern "C" void remove_temporaries_and_die(int signal) {
    remove_live_temporaries();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

// SIGTERM and SIGHUP (a job killed by its launcher, e.g. mpirun when another rank died; a closed
// terminal) remove the temporaries before the process dies of the signal. A handler the program
// set itself, or an ignored signal, is left alone.
void install_termination_handler() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int signal : {SIGTERM, SIGHUP}) {
            struct sigaction current {};
            if (::sigaction(signal, nullptr, &current) == 0 && current.sa_handler == SIG_DFL &&
                !(current.sa_flags & SA_SIGINFO))
                std::signal(signal, remove_temporaries_and_die);
        }
    });
}

// The slot now holding `path`, or kTempSlots when every slot is taken (the file is then only
// removed by the destructor).
std::size_t register_temporary(const std::string& path) {
    install_termination_handler();
    if (path.size() >= PATH_MAX) return kTempSlots;
    for (std::size_t i = 0; i < kTempSlots; ++i) {
        int expected = 0;
        if (!g_slot_state[i].compare_exchange_strong(expected, 1)) continue;
        std::memcpy(g_slot_path[i].data(), path.c_str(), path.size() + 1);
        g_slot_state[i].store(2);
        return i;
    }
    return kTempSlots;
}

void unregister_temporary(std::size_t slot) {
    if (slot < kTempSlots) g_slot_state[slot].store(0);
}

// Removes "<path>.tmp.<pid>.<n>" beside `path` whose process <pid> is not running here (kill(pid,
// 0) fails with ESRCH): what a run killed while writing the same output left.
void remove_stale_temporaries(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    const std::string prefix = target.filename().string() + ".tmp.";
    std::error_code ec;
    fs::directory_iterator it(dir, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        const std::string rest = name.substr(prefix.size());  // "<pid>.<n>"
        const std::size_t dot = rest.find('.');
        if (dot == 0 || dot == std::string::npos || dot + 1 == rest.size() ||
            rest.find_first_not_of("0123456789.") != std::string::npos ||
            rest.find('.', dot + 1) != std::string::npos || dot > 9)
            continue;
        const long pid = std::stol(rest.substr(0, dot));
        if (pid <= 0 || pid == ::getpid()) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code removed;
        if (fs::remove(it->path(), removed))
            log_warn("removed {}, left by a run that was killed while writing {}",
                     it->path().string(), path);
    }
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)) {
    SHPRT_CHECK(!m_path.empty(), invalid_argument, "output path is empty");
    check_output_path(m_path);
    remove_stale_temporaries(m_path);
    m_temp = fmt::format("{}.tmp.{}.{}", m_path, ::getpid(), g_counter++);
    m_slot = register_temporary(m_temp);
    m_file = std::fopen(m_temp.c_str(), "wb");
    if (m_file == nullptr) {
        const int err = errno;
        unregister_temporary(m_slot);
        fail(ErrorCode::io, "cannot write {}: {}", m_path, std::strerror(err));
    }
}

AtomicFile::~AtomicFile() {
    if (m_file) std::fclose(m_file);
    if (!m_committed) std::remove(m_temp.c_str());
    unregister_temporary(m_slot);
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
    // The rename and its record happen with SIGINT, SIGTERM and SIGHUP held in this thread, so
    // that a handler (in any thread: committed_output waits for the record) sees the output in
    // place exactly when it is.
    sigset_t hold, previous;
    sigemptyset(&hold);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&hold, signal);
    ::pthread_sigmask(SIG_BLOCK, &hold, &previous);
    g_renaming.fetch_add(1);
    const bool renamed = std::rename(m_temp.c_str(), m_path.c_str()) == 0;
    const int rename_error = errno;
    if (renamed && m_path.size() < PATH_MAX) {
        std::memcpy(g_committed_path.data(), m_path.c_str(), m_path.size() + 1);
        g_has_committed.store(true);
    }
    g_renaming.fetch_sub(1);
    if (renamed) test_stop_after_rename();
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    SHPRT_CHECK(renamed, io, "cannot rename {} to {}: {}", m_temp, m_path,
                std::strerror(rename_error));
    m_committed = true;
    unregister_temporary(m_slot);
    m_slot = std::size_t(-1);
    log_debug("wrote {}", m_path);
}

void remove_live_temporaries() {
    for (std::size_t i = 0; i < kTempSlots; ++i)
        if (g_slot_state[i].load() == 2) ::unlink(g_slot_path[i].data());
}

const char* committed_output() {
    while (g_renaming.load() != 0) {
        const timespec pause{0, 100'000};
        ::nanosleep(&pause, nullptr);
    }
    return g_has_committed.load() ? g_committed_path.data() : nullptr;
}

void note_input_file(const std::string& path) {
    const std::lock_guard lock(g_inputs_mutex);
    if (std::find(g_inputs.begin(), g_inputs.end(), path) == g_inputs.end())
        g_inputs.push_back(path);
}

std::vector<std::string> noted_input_files() {
    const std::lock_guard lock(g_inputs_mutex);
    return g_inputs;
}

void check_output_path(const std::string& output) {
    struct stat st {};
    if (::stat(output.c_str(), &st) == 0) {
        SHPRT_CHECK(!S_ISDIR(st.st_mode), io, "cannot write {}: it is a directory", output);
        SHPRT_CHECK(S_ISREG(st.st_mode), io,
                    "cannot write {}: it exists and is {}, not a regular file (shprt replaces "
                    "only regular files)",
                    output, file_kind(st.st_mode));
    }
    check_output_is_not_input(output, {});
}

void check_output_writable(const std::string& output) {
    check_output_path(output);
    const AtomicFile probe(output);  // throws Error(io) naming the path; removed on destruction
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
    for (const std::string& input : noted_input_files())
        SHPRT_CHECK(!same_file(output, input), invalid_argument,
                    "output {} is the file {}, which the scene reads; choose another output name",
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
