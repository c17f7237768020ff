# CUDA is optional and found automatically: SHPRT_CUDA=AUTO builds the CUDA backend when nvcc
# exists (no GPU needed to build), ON insists, OFF skips. Architectures are explicit, never
# "native", because build machines may have nvcc but no GPU.
set(SHPRT_HAS_CUDA 0)
set(SHPRT_CUDA_LIB "")
if(NOT SHPRT_CUDA STREQUAL "OFF")
    if(NOT CMAKE_CUDA_COMPILER AND EXISTS /usr/local/cuda/bin/nvcc)
        set(CMAKE_CUDA_COMPILER /usr/local/cuda/bin/nvcc)
    endif()
    include(CheckLanguage)
    check_language(CUDA)
    if(CMAKE_CUDA_COMPILER)
        if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
            set(CMAKE_CUDA_ARCHITECTURES 75 80 86 89 90)
        endif()
        enable_language(CUDA)
        # C++17 for .cu files: CMake 3.25 has no -std=c++20 flag for nvcc (it stops at "CUDA20
        # not supported"). The kernels and the SHPRT_HD headers they include are C++17; the
        # backend's host .cpp files are C++20 like the rest.
        set(CMAKE_CUDA_STANDARD 17)
        set(CMAKE_CUDA_STANDARD_REQUIRED ON)
        find_package(CUDAToolkit REQUIRED)
        set(SHPRT_HAS_CUDA 1)
    elseif(SHPRT_CUDA STREQUAL "ON")
        message(FATAL_ERROR "SHPRT_CUDA=ON but no CUDA compiler was found")
    endif()
endif()

if(SHPRT_HAS_CUDA)
    # Kernels and launchers are .cu (nvcc); the host side of the CUDA backend (device buffers,
    # streams, cuBLAS) is .cpp compiled by the host compiler: nvcc cannot parse fmt's headers.
    file(GLOB shprt_cuda_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/bake/cuda/*.cu
                                                   ${PROJECT_SOURCE_DIR}/src/bake/cuda/*.cpp)
    if(shprt_cuda_sources)
        add_library(shprt_cuda STATIC ${shprt_cuda_sources})
        target_include_directories(shprt_cuda PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                                                     $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
                                              PRIVATE ${PROJECT_SOURCE_DIR}/src)
        # cuBLAS and cuSPARSE are not linked but opened on first use (src/bake/cuda/cublas_loader.hpp,
        # cusparse_loader.hpp): linking them costs every program ~0.3 s of start-up. Their
        # headers come with the toolkit's includes.
        target_link_libraries(shprt_cuda PUBLIC CUDA::cudart_static fmt::fmt ${CMAKE_DL_LIBS}
                                         PRIVATE shprt_warnings)
        target_compile_definitions(shprt_cuda PRIVATE SHPRT_CUDA_LIBRARY_DIR="${CUDAToolkit_LIBRARY_DIR}")
        # --fmad=false: no contraction of a*b+c into FMA in device code, so the SHPRT_HD traversal
        # and transfer math round exactly as on the host (the CPU emulation tests rely on it).
        target_compile_options(shprt_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--expt-relaxed-constexpr -lineinfo --fmad=false>)
        set_target_properties(shprt_cuda PROPERTIES POSITION_INDEPENDENT_CODE ON CUDA_SEPARABLE_COMPILATION OFF)
        set(SHPRT_CUDA_LIB shprt_cuda)
    endif()
    message(STATUS "shprt: CUDA backend ON (nvcc ${CMAKE_CUDA_COMPILER_VERSION}, architectures ${CMAKE_CUDA_ARCHITECTURES})")
else()
    # Why not, in the words of device 'cuda's error and query_gpu()'s reason (the bake area's
    # SHPRT_NO_CUDA_REASON, src/bake/gpu_fallback.cpp): nvcc is looked for whatever SHPRT_CUDA says
    # (where check_language looks too: PATH and /usr/local/cuda/bin), so that the message says
    # what is true of this machine and what to do about it. No semicolons (a CMake list).
    find_program(shprt_nvcc nvcc PATHS /usr/local/cuda/bin NO_CACHE)
    if(SHPRT_CUDA STREQUAL "OFF" AND shprt_nvcc)
        set(SHPRT_NO_CUDA_REASON "configured with SHPRT_CUDA=OFF although nvcc is at ${shprt_nvcc}: reconfigure with -DSHPRT_CUDA=AUTO")
    elseif(SHPRT_CUDA STREQUAL "OFF")
        set(SHPRT_NO_CUDA_REASON "configured with SHPRT_CUDA=OFF, and no nvcc was found: install the CUDA toolkit, then reconfigure with -DSHPRT_CUDA=AUTO")
    elseif(shprt_nvcc)
        set(SHPRT_NO_CUDA_REASON "nvcc at ${shprt_nvcc} failed CMake's CUDA check at configure time: see the configure log, set CUDAHOSTCXX to a host compiler it supports and reconfigure")
    else()
        set(SHPRT_NO_CUDA_REASON "no nvcc was found at configure time, on PATH or in /usr/local/cuda/bin: install the CUDA toolkit or set CUDACXX to nvcc, and reconfigure")
    endif()
    message(STATUS "shprt: CUDA backend OFF (${SHPRT_NO_CUDA_REASON})")
endif()
