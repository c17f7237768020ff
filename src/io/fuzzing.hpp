// For the .shprt reader's fuzz target only (tests/fuzz/fuzz_shprt_read.cpp), not part of the
// public API: every byte of a .shprt file is under a CRC, so a mutated file would almost always
// stop at the first checksum. The fuzz target turns the checksums advisory, and the reader goes on
// past a mismatch to the checks behind it; every other check stays. A run-time switch, not a
// build flag, so that one sanitizer build serves both the fuzz targets and the test suite, whose
// corrupt-file tests need the checksums (scripts/test, docs/fuzzing.md).
#pragma once

namespace shprt::io_fuzzing {

// Off until the fuzz target turns it on; read by every read_shprt* call.
void set_checksums_advisory(bool advisory) noexcept;
bool checksums_advisory() noexcept;

}  // namespace shprt::io_fuzzing
