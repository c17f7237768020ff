// CUDA–OpenGL interop for the viewer: an OpenGL buffer object mapped into CUDA so that a GPU bake
// (bake_gpu with device_output) writes the coefficients straight into the buffer the shaders read,
// with no trip through host memory. CUDA-free and OpenGL-free header (a buffer name is a GLuint,
// i.e. an unsigned int). In a build without CUDA every constructor throws Error(unsupported).
//
// Preconditions: the OpenGL context that owns the buffer is current on the calling thread for
// the constructor, map(), unmap() and the destructor, and it runs on the same GPU as CUDA device 0
// (query_gpu()). While mapped, OpenGL must not use the buffer.
#pragma once

#include <cstddef>

namespace shprt {

class GlBufferInterop {
public:
    // Registers the buffer object `gl_buffer` (cudaGraphicsGLRegisterBuffer, write-discard: CUDA
    // overwrites it, its old content is not preserved). Throws Error(cuda) with CUDA's message.
    explicit GlBufferInterop(unsigned int gl_buffer);
    // Unmaps if mapped and unregisters; errors are ignored (a destructor does not throw).
    ~GlBufferInterop();
    GlBufferInterop(const GlBufferInterop&) = delete;
    GlBufferInterop& operator=(const GlBufferInterop&) = delete;

    // Maps the buffer for CUDA and returns its device address; `bytes` receives its size.
    // Throws Error(cuda); Error(invalid_argument) when already mapped.
    float* map(std::size_t& bytes);
    // Ends the mapping: CUDA's writes are complete and visible to OpenGL afterwards.
    void unmap();
    bool mapped() const { return m_mapped; }

private:
    // cudaGraphicsResource_t; unused where CUDA is not built (src/bake/cuda/gl_interop.cpp is)
    [[maybe_unused]] void* m_resource = nullptr;
    bool m_mapped = false;
};

}  // namespace shprt
