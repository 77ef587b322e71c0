# The GPU backend (src/backend/gpu, docs/architecture.md): one source, two builds.
#
#   cuda-on-cpu  the C++ compiler with Thrust's OpenMP device system: built
#                whenever Thrust headers are found (the CUDA toolkit's CCCL, else
#                Debian's libthrust-dev / libcub-dev), tested by every CTest run.
#   cuda         nvcc for NVIDIA GPUs: PBF_CUDA, ON when check_language(CUDA)
#                finds nvcc. sm_90 machine code plus compute_90 PTX (newer GPUs
#                JIT-compile it); override with -DCMAKE_CUDA_ARCHITECTURES.
#
# The sanitizer presets (asan, tsan, fuzz) set PBF_CUDA=OFF: nvcc code is not
# instrumented, and the release build already compiles it; they test the
# cuda-on-cpu build.
#
# Without either, pbf builds without that device: `--device cuda` says why,
# and the device's tests skip with a message.
include(CheckLanguage)
check_language(CUDA)
if(CMAKE_CUDA_COMPILER)
  set(pbf_cuda_default ON)
else()
  set(pbf_cuda_default OFF)
endif()
option(PBF_CUDA "Build the GPU backend for NVIDIA GPUs with nvcc (--device cuda)" ${pbf_cuda_default})

if(PBF_CUDA)
  if(NOT CMAKE_CUDA_COMPILER)
    message(FATAL_ERROR "PBF_CUDA is ON but no CUDA compiler was found (install the CUDA "
                        "toolkit, put nvcc on the PATH, or -DPBF_CUDA=OFF)")
  endif()
  if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
    set(CMAKE_CUDA_ARCHITECTURES 90)  # sm_90 SASS + compute_90 PTX
  endif()
  enable_language(CUDA)
  find_package(CUDAToolkit REQUIRED)
  # CMake 3.25 knows no C++20 flag for nvcc (12.0 and later accept -std=c++20).
  if(NOT CMAKE_CUDA20_STANDARD_COMPILE_OPTION)
    set(CMAKE_CUDA20_STANDARD_COMPILE_OPTION "-std=c++20")
    set(CMAKE_CUDA20_EXTENSION_COMPILE_OPTION "-std=c++20")
  endif()
  # The oldest architecture built for: older GPUs are refused by name.
  set(pbf_cuda_min_arch 1000)
  foreach(arch IN LISTS CMAKE_CUDA_ARCHITECTURES)
    string(REGEX MATCH "^[0-9]+" number "${arch}")
    if(number AND number LESS pbf_cuda_min_arch)
      set(pbf_cuda_min_arch ${number})
    endif()
  endforeach()
  message(STATUS "pbf: GPU backend for NVIDIA GPUs (nvcc ${CMAKE_CUDA_COMPILER_VERSION}, "
                 "architectures ${CMAKE_CUDA_ARCHITECTURES})")
endif()

# Thrust headers for the CPU build: the toolkit's CCCL (Thrust 2/3), else
# Debian's (Thrust 1.17, /usr/include). -DPBF_THRUST_INCLUDE_DIR=... picks one.
set(pbf_cccl_hints)
if(CUDAToolkit_INCLUDE_DIRS)
  foreach(dir IN LISTS CUDAToolkit_INCLUDE_DIRS)
    list(APPEND pbf_cccl_hints ${dir}/cccl)
  endforeach()
endif()
find_path(PBF_THRUST_INCLUDE_DIR thrust/version.h
          HINTS ${pbf_cccl_hints} /usr/local/cuda/include/cccl
          DOC "Thrust headers for the GPU backend's CPU build (cuda-on-cpu)")
if(PBF_THRUST_INCLUDE_DIR)
  file(STRINGS ${PBF_THRUST_INCLUDE_DIR}/thrust/version.h pbf_thrust_version_line
       REGEX "^#define THRUST_VERSION +[0-9]+")
  string(REGEX MATCH "THRUST_VERSION +([0-9]+)" pbf_unused "${pbf_thrust_version_line}")
  set(pbf_thrust_version "${CMAKE_MATCH_1}")
  math(EXPR pbf_thrust_major "${pbf_thrust_version} / 100000")
  math(EXPR pbf_thrust_minor "(${pbf_thrust_version} / 100) % 1000")
  message(STATUS "pbf: GPU backend's CPU build (cuda-on-cpu) with Thrust "
                 "${pbf_thrust_major}.${pbf_thrust_minor} from ${PBF_THRUST_INCLUDE_DIR}")
else()
  message(STATUS "pbf: no Thrust headers (CUDA toolkit, or apt-get install libthrust-dev "
                 "libcub-dev): building without the cuda-on-cpu device")
endif()

# Compiles `source` as the GPU backend's CPU build into `target` with the
# Thrust headers in `include_dir` (an extra -isystem unless they are in
# /usr/include, which is searched anyway: naming it would break
# libstdc++'s #include_next). Further arguments: extra definitions.
function(pbf_add_thrust_omp_source target source include_dir)
  set(options)
  if(NOT include_dir STREQUAL "/usr/include")
    list(APPEND options -isystem ${include_dir})
  endif()
  # Thrust binds references through null pointers in its OpenMP algorithms
  # (NVIDIA/cccl#1645): UBSan's null check would stop every run. Thrust
  # 1.17's trivial copy also passes null to memmove for empty ranges
  # (thrust/system/detail/sequential/trivial_copy.h): nonnull-attribute.
  if(PBF_SANITIZE MATCHES "undefined")
    list(APPEND options -fno-sanitize=null,nonnull-attribute)
  endif()
  set_source_files_properties(${source} TARGET_DIRECTORY ${target} PROPERTIES
                              COMPILE_DEFINITIONS "THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP;${ARGN}"
                              COMPILE_OPTIONS "${options}")
endfunction()
