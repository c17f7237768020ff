// Output files are never left half-written: AtomicFile writes to a temporary file beside the
// target and renames it into place on commit(); if commit() is never reached (an exception, a
// cancel), the destructor removes the temporary file and the target is untouched. A process
// terminated by SIGTERM or SIGHUP (default disposition) removes its live temporaries first; a
// program with its own handlers calls remove_live_temporaries() from them.
//
// A run killed outright (SIGKILL, a crash, the machine) leaves its temporary behind: the next
// AtomicFile for the same path removes every "<path>.tmp.<pid>.<n>" whose process no longer runs
// on this machine, and warns once for each (log_warn: "removed ... left by a run that was
// killed").
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

class AtomicFile {
public:
    // Opens "<path>.tmp.<pid>.<n>" for binary writing; throws Error(io) naming `path` on failure.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Appends bytes; throws Error(io) naming the target path on a short write.
    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }
    std::FILE* handle() { return m_file; }  // for libraries that write through a FILE*
    const std::string& temp_path() const { return m_temp; }
    // Flushes, closes and renames over the target; throws Error(io) on failure.
    void commit();

private:
    std::string m_path, m_temp;
    std::FILE* m_file = nullptr;
    bool m_committed = false;
    std::size_t m_slot = std::size_t(-1);  // the termination handler's record of m_temp
};

// Removes the temporary file of every AtomicFile alive in this process. Async-signal-safe (unlink
// only): for a program's own signal handlers, before the process ends.
void remove_live_temporaries();

// Writes all `size` bytes at byte `offset` of the open file `fd` (pwrite, retried on EINTR and
// short writes; thread-safe for disjoint regions). Throws Error(io) naming `what` on failure.
void pwrite_all(int fd, const void* data, std::size_t size, std::uint64_t offset,
                const std::string& what);

// The extension of `path`'s file name in lower case, with its dot (".png"); "" when it has none.
// How every reader and writer chooses a format by name.
std::string lower_extension(const std::string& path);

// True when `a` and `b` name the same existing file: the same device and inode, so a symbolic
// link to it or a hard link of it counts. False when either does not exist (or cannot be
// examined).
bool same_file(const std::string& a, const std::string& b);

// Refuses, before any work, to write `output` over one of the files a command reads: throws
// Error(invalid_argument) "output OUT is the input file IN (the same file); choose another
// output name" when same_file(output, input) for any of `inputs`.
void check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs);

// Reads a whole file; throws Error(io) naming `path` if it cannot be opened or read.
std::string read_file(const std::string& path);

}  // namespace shprt
