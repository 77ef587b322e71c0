// Build-wide macros shared by every pbf header.
#pragma once

// Kernel maths is written once and compiled for CPU and, later, CUDA
// (`__host__ __device__`); the macro keeps the plain C++ build free of CUDA.
#if defined(__CUDACC__)
#define PBF_HD __host__ __device__
#else
#define PBF_HD
#endif

// Forces inlining of small helpers that take a callable (the neighbour
// stencil walk): host and device compilers spell it differently.
#if defined(__CUDACC__)
#define PBF_ALWAYS_INLINE __forceinline__
#else
#define PBF_ALWAYS_INLINE [[gnu::always_inline]] inline
#endif
