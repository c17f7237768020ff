// A mesh importer in a child process (isolated_import.hpp). The child writes its result to a pipe
// as a tag byte and length-prefixed arrays; the parent reads while the child writes (so a large
// mesh never fills the pipe and blocks), then reaps the child.
#include "isolated_import.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/sanitizers.hpp"

#include <fcntl.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <vector>

namespace shprt::detail {
namespace {

constexpr char kResultTag = 'M', kErrorTag = 'E';
// A length field above this is a broken stream, not a mesh (2^32 vertices of 12 bytes is 48 GiB).
constexpr std::uint64_t kMaxArrayBytes = std::uint64_t(1) << 40;
// The wall-clock limit is this many times the CPU-time limit: room for a loaded machine, where
// the child waits for a CPU, but still a bound for a child that waits for input forever.
constexpr unsigned kWallPerCpuSecond = 3;

// Moves `bytes` bytes with read(2) or write(2) (`io`), resuming after partial transfers and
// signals. False when the other end is gone. No allocation and no lock: safe in the child.
template <class Byte, class Io>
bool transfer_all(int fd, Byte* p, std::size_t bytes, Io io) {
    while (bytes > 0) {
        const ssize_t n = io(fd, p, bytes);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        bytes -= static_cast<std::size_t>(n);
    }
    return true;
}

// ---- Child side.

bool write_all(int fd, const void* data, std::size_t bytes) {
    return transfer_all(fd, static_cast<const char*>(data), bytes, ::write);
}

template <class T>
bool write_value(int fd, const T& value) {
    return write_all(fd, &value, sizeof value);
}

// Gives the pages of freed memory back to the system (glibc keeps the heap's free pages
// otherwise: after Assimp's import, over a gigabyte of them for a large OBJ).
void return_free_pages() {
#if defined(__GLIBC__)
    ::malloc_trim(0);
#endif
}

// Writes `v` as its byte count and bytes, then frees it: what the parent has is no longer held
// here too.
template <class T>
bool send_array(int fd, std::vector<T>& v) {
    const std::uint64_t bytes = v.size() * sizeof(T);
    const bool ok = write_value(fd, bytes) && write_all(fd, v.data(), v.size() * sizeof(T));
    std::vector<T>().swap(v);
    return_free_pages();
    return ok;
}

void write_error(int fd, ErrorCode code, const char* message) {
    const auto c = static_cast<std::uint32_t>(code);
    const std::uint64_t length = std::strlen(message);
    (void)(write_value(fd, kErrorTag) && write_value(fd, c) && write_value(fd, length) &&
           write_all(fd, message, length));
}

// The address space the process has mapped now (VmSize), in bytes; 0 if unknown.
std::uint64_t mapped_bytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long pages = 0;
    const bool ok = std::fscanf(f, "%llu", &pages) == 1;
    std::fclose(f);
    return ok ? pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE)) : 0;
}

// Lowers a resource limit's soft value to `wanted` (never raises it); the hard value too when
// `hard` is given, so that a soft limit the child ignores still ends it.
void lower_limit(int resource, rlim_t wanted, rlim_t hard = RLIM_INFINITY) {
    rlimit limit{};
    if (::getrlimit(resource, &limit) != 0) return;
    if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur > wanted) limit.rlim_cur = wanted;
    if (hard != RLIM_INFINITY && (limit.rlim_max == RLIM_INFINITY || limit.rlim_max > hard))
        limit.rlim_max = std::max(hard, limit.rlim_cur);
    ::setrlimit(resource, &limit);
}

// The file names, each ended by '\0', as one array for the pipe; and back.
std::vector<char> joined_files(const std::vector<std::string>& files) {
    std::vector<char> out;
    for (const std::string& f : files) out.insert(out.end(), f.c_str(), f.c_str() + f.size() + 1);
    return out;
}

std::vector<std::string> split_files(const std::vector<char>& joined) {
    std::vector<std::string> files;
    std::size_t begin = 0;
    for (std::size_t i = 0; i < joined.size(); ++i)
        if (joined[i] == '\0') {
            files.emplace_back(joined.data() + begin, i - begin);
            begin = i + 1;
        }
    return files;
}

// In the child, before the work: the address-space and time limits, and stdout and stderr to
// /dev/null. System calls only (async-signal-safe after fork in a threaded process).
void prepare_child(std::uint64_t address_space_limit, unsigned cpu_seconds) {
    if (!kShadowMemorySanitizer && address_space_limit > 0) {
        rlimit limit{};
        if (::getrlimit(RLIMIT_AS, &limit) == 0) {
            const rlim_t wanted = static_cast<rlim_t>(address_space_limit);
            if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur > wanted) {
                limit.rlim_cur = wanted;
                ::setrlimit(RLIMIT_AS, &limit);
            }
        }
    }
    // A crash in the importer ends the child by its signal, which the parent names: the default
    // action, not a handler inherited from the parent (a sanitizer's, which would print a report
    // and exit with status 1 instead).
    // SIGXCPU and SIGALRM (the time limits below) likewise, and unblocked: the parent may hold
    // signals while it starts (tools/shprt_main), and the child inherits its mask.
    sigset_t limits;
    ::sigemptyset(&limits);
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGXCPU, SIGALRM}) {
        struct sigaction action {};
        action.sa_handler = SIG_DFL;
        ::sigemptyset(&action.sa_mask);
        ::sigaction(sig, &action, nullptr);
        ::sigaddset(&limits, sig);
    }
    ::sigprocmask(SIG_UNBLOCK, &limits, nullptr);
    // A crash or a time limit leaves no core file in the user's folder.
    lower_limit(RLIMIT_CORE, 0);
    if (cpu_seconds > 0) {
        // CPU time (the child's own, from 0 at fork): SIGXCPU at the limit, SIGKILL a little
        // after should the signal be ignored. Wall time: SIGALRM, for a child that waits (a
        // texture named by the file that is a FIFO) rather than computes.
        lower_limit(RLIMIT_CPU, cpu_seconds, rlim_t(cpu_seconds) + 5);
        ::alarm(kWallPerCpuSecond * cpu_seconds);
    }
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
        if (null > STDERR_FILENO) ::close(null);
    }
}

[[noreturn]] void child_main(int fd, const std::function<ImportedMesh()>& work,
                             const std::string& out_of_memory_message) {
    try {
        ImportedMesh r = work();
        // The importer's scene is gone with work(): its memory goes back to the system before the
        // arrays go to the parent, and each array once sent (send_array), so that the child and
        // the parent together hold the mesh about once. (The child's peak is Assimp's own, while
        // it reads the file: 2.1 GiB for an 80 MB OBJ of 10 M faces, of which the scene it
        // returns is 0.8 GiB.)
        return_free_pages();
        Mesh& m = r.mesh;
        const std::uint8_t all_normals = r.all_normals ? 1 : 0;
        // A Brdf has padding: its fields go as five doubles (model, parameter, specular).
        std::vector<std::array<double, 5>> brdfs;
        for (const Brdf& b : m.brdfs)
            brdfs.push_back(
                {double(int(b.model)), b.parameter, b.specular.x, b.specular.y, b.specular.z});
        std::vector<char> files = joined_files(r.files);
        (void)(write_value(fd, kResultTag) && write_value(fd, all_normals) &&
               write_value(fd, r.skipped_faces) && write_value(fd, r.albedo_sources) &&
               send_array(fd, m.positions) && send_array(fd, m.normals) &&
               send_array(fd, m.albedo) && send_array(fd, m.triangles) &&
               send_array(fd, m.source_vertex) && send_array(fd, m.uvs) && send_array(fd, brdfs) &&
               send_array(fd, m.brdf_index) && send_array(fd, files));
    } catch (const Error& e) {
        write_error(fd, e.code(), e.what());
    } catch (const std::bad_alloc&) {
        write_error(fd, ErrorCode::out_of_memory, out_of_memory_message.c_str());
    } catch (const std::exception& e) {
        write_error(fd, ErrorCode::format, e.what());
    } catch (...) {
        write_error(fd, ErrorCode::format, "the importer failed");
    }
    ::close(fd);
    // No exit(): the parent's atexit handlers and stdio buffers are not the child's to run.
    ::_exit(0);
}

// ---- Parent side.

class Reader {
public:
    explicit Reader(int fd) : m_fd(fd) {}
    // False at end of stream (the child died or wrote nothing more).
    bool read(void* data, std::size_t bytes) {
        return transfer_all(m_fd, static_cast<char*>(data), bytes, ::read);
    }
    template <class T>
    bool value(T& out) {
        return read(&out, sizeof out);
    }
    template <class T>
    bool array(std::vector<T>& out) {
        std::uint64_t bytes = 0;
        if (!value(bytes) || bytes % sizeof(T) != 0 || bytes > kMaxArrayBytes) return false;
        out.resize(bytes / sizeof(T));
        return read(out.data(), bytes);
    }

private:
    int m_fd;
};

// Owns the child until it is reaped: a parent that leaves early (an exception while reading)
// kills it rather than leaving it running or a zombie.
class Child {
public:
    explicit Child(pid_t pid) : m_pid(pid) {}
    ~Child() {
        if (m_pid > 0) {
            ::kill(m_pid, SIGKILL);
            wait();
        }
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    // The child's wait status.
    int wait() {
        int status = 0;
        while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR) {
        }
        m_pid = 0;
        return status;
    }

private:
    pid_t m_pid;
};

}  // namespace

ImportedMesh run_isolated_import(const std::string& path, std::uint64_t memory_budget,
                                 const std::function<ImportedMesh()>& work, unsigned cpu_seconds) {
    // Formatted here: the child must not allocate once it is out of memory.
    const std::string out_of_memory_message = fmt::format(
        "{}: the importer needed more than {:.1f} GiB of memory (a count in the file is corrupt, "
        "or the scene is larger than the limit: set SHPRT_IMPORT_MEMORY_GIB to raise it)",
        path, double(memory_budget) / double(1ull << 30));
    const std::uint64_t mapped = mapped_bytes();
    const std::uint64_t limit = mapped > 0 ? mapped + memory_budget : 0;
    int fds[2];
    if (::pipe(fds) != 0) return work();
    const pid_t pid = ::fork();
    if (pid < 0) {  // no process to spare: import here, unprotected
        ::close(fds[0]);
        ::close(fds[1]);
        return work();
    }
    if (pid == 0) {
        ::close(fds[0]);
        prepare_child(limit, cpu_seconds);
        child_main(fds[1], work, out_of_memory_message);
    }
    ::close(fds[1]);
    Child child(pid);
    Reader in(fds[0]);
    ImportedMesh r;
    char tag = 0;
    bool complete = false;
    ErrorCode error_code = ErrorCode::format;
    std::string error_message;
    if (in.value(tag) && tag == kResultTag) {
        std::uint8_t all_normals = 0;
        Mesh& m = r.mesh;
        std::vector<std::array<double, 5>> brdfs;
        std::vector<char> files;
        complete = in.value(all_normals) && in.value(r.skipped_faces) &&
                   in.value(r.albedo_sources) && in.array(m.positions) && in.array(m.normals) &&
                   in.array(m.albedo) && in.array(m.triangles) && in.array(m.source_vertex) &&
                   in.array(m.uvs) && in.array(brdfs) && in.array(m.brdf_index) && in.array(files);
        r.files = split_files(files);
        for (const auto& [model, parameter, red, green, blue] : brdfs) {
            const bool known = model == 0 || model == 1 || model == 2;  // BrdfModel's values
            complete = complete && known;
            if (known)
                m.brdfs.push_back({static_cast<BrdfModel>(int(model)), parameter,
                                   Vec3f{float(red), float(green), float(blue)}});
        }
        r.all_normals = all_normals != 0;
    } else if (tag == kErrorTag) {
        std::uint32_t code = 0;
        std::uint64_t length = 0;
        if (in.value(code) && in.value(length) && length < (1u << 20)) {
            error_message.resize(length);
            if (in.read(error_message.data(), length) &&
                code <= static_cast<std::uint32_t>(ErrorCode::cancelled)) {
                error_code = static_cast<ErrorCode>(code);
                complete = true;
            }
        }
    }
    ::close(fds[0]);
    const int status = child.wait();
    if (!complete) {
        const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
        if (cpu_seconds > 0 && (sig == SIGXCPU || sig == SIGALRM))
            fail(ErrorCode::format,
                 "{}: the importer took more than {} s {} reading this file (a count in the file "
                 "is corrupt, or the scene is larger than the limit: set SHPRT_IMPORT_SECONDS to "
                 "raise it)",
                 path, sig == SIGXCPU ? cpu_seconds : kWallPerCpuSecond * cpu_seconds,
                 sig == SIGXCPU ? "of CPU time" : "of wall-clock time");
        if (WIFSIGNALED(status))
            fail(ErrorCode::format,
                 "{}: the importer crashed reading this file (signal {}, {}); the file is corrupt "
                 "or uses something Assimp cannot read",
                 path, WTERMSIG(status), ::strsignal(WTERMSIG(status)));
        fail(ErrorCode::format, "{}: the importer ended without a result (exit status {})", path,
             WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    }
    if (tag == kErrorTag) throw Error(error_code, error_message);
    return r;
}

}  // namespace shprt::detail
