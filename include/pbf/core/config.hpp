// Build-wide macros shared by every pbf header.
#pragma once

// Kernel maths is written once and compiled for CPU and, later, CUDA
// (`__host__ __device__`); the macro keeps the plain C++ build free of CUDA.
#if defined(__CUDACC__)
#define PBF_HD __host__ __device__
#else
#define PBF_HD
#endif
