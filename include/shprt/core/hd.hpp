// The one host/device macro. Headers of pure math (vectors, SH basis, samplers, ray-triangle,
// the flat BVH and its traversal) mark their functions SHPRT_HD so that the same code runs in
// CUDA kernels and, in the CPU tests, on the host. Such headers use no std::vector, exceptions,
// virtual functions or iostreams: raw pointers and explicit counts only.
#pragma once

#if defined(__CUDACC__)
#define SHPRT_HD __host__ __device__
#define SHPRT_HD_INLINE __host__ __device__ __forceinline__
#else
#define SHPRT_HD
#define SHPRT_HD_INLINE inline
#endif
