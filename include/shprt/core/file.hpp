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
//
// An output that exists and is not a regular file (a device such as /dev/null, a FIFO, a socket)
// is refused, never replaced: rename() would put a regular file in its place. So is an output that
// is one of the files this process has read as input (note_input_file: a scene's materials,
// textures and buffers).
//
// commit() holds SIGINT, SIGTERM and SIGHUP in the calling thread across the rename and its record
// (committed_output), so that a program's signal handler can tell, truthfully, whether the output
// is in place: committed_output() waits for a rename in progress in another thread.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

class AtomicFile {
public:
    // Opens "<path>.tmp.<pid>.<n>" for binary writing; throws Error(io) naming `path` on failure,
    // Error(invalid_argument) when `path` exists and is not a regular file or is a file this
    // process read as input (check_output_path).
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

// The target path of the last AtomicFile renamed into place in this process, or nullptr when none
// was. Async-signal-safe, for a program's signal handlers: if another thread is renaming at that
// moment, waits until it is done (the renaming thread holds the signals, so it never waits on
// itself).
const char* committed_output();

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
// output name" when same_file(output, input) for any of `inputs`, and "output OUT is the file IN,
// which the scene reads; choose another output name" for any noted input file
// (note_input_file).
void check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs);

// Records that this process read `path` as an input (the scene loader notes the scene file and
// every file its importer opened: materials, textures, buffers). check_output_is_not_input and
// every AtomicFile refuse to write over a noted file. Thread-safe.
void note_input_file(const std::string& path);
// The files noted so far, in the order noted.
std::vector<std::string> noted_input_files();

// The checks every output gets before anything is written (AtomicFile's constructor runs them; a
// command runs them first, with check_output_writable, to fail before its work):
//   * "cannot write OUT: it is a directory" (Error(io)) when OUT is a directory;
//   * "cannot write OUT: it exists and is not a regular file (a device, FIFO or socket); shprt
//     replaces only regular files" (Error(invalid_argument)) for any other non-regular file;
//   * check_output_is_not_input(OUT, noted_input_files()).
// A symbolic link is followed: a link to a regular file is replaced by the new file, as before.
void check_output_path(const std::string& output);

// check_output_path, then creates and removes the output's temporary file: fails early, before
// any work, when OUT cannot be written (a missing folder, no permission), naming OUT.
void check_output_writable(const std::string& output);

// Reads a whole file; throws Error(io) naming `path` if it cannot be opened or read.
std::string read_file(const std::string& path);

}  // namespace shprt
