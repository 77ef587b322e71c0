#!/usr/bin/env bash
# One command for a machine with an NVIDIA GPU: builds pbf with CUDA
# (release preset, PBF_CUDA=ON), runs the GPU backend's tests on the GPU —
# the same CTest cases that every CI run passes on cuda-on-cpu, with
# PBF_TEST_DEVICE=cuda — then `pbf bench --device cuda` at 128k, 1M and 4M
# particles, and the same sizes on the cpu device for comparison, and 1M
# on cuda with surface tension and the physical viscosity on.
# Everything it prints is also written to build/release/gpu_check/.
# Usage: scripts/gpu_check.sh [--sizes 128k,1M,4M] [--steps N]
# Put the figures in docs/performance.md ("GPU") with the GPU's name.
set -euo pipefail
cd "$(dirname "$0")/.."

sizes=128k,1M,4M
steps=20
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    *) echo "gpu_check: unknown argument $1" >&2; exit 2 ;;
  esac
done

if ! command -v nvidia-smi > /dev/null || ! nvidia-smi -L; then
  echo "gpu_check: no NVIDIA GPU here (nvidia-smi lists none)" >&2
  exit 1
fi
if ! command -v nvcc > /dev/null; then
  export PATH=/usr/local/cuda/bin:$PATH
  command -v nvcc > /dev/null || { echo "gpu_check: nvcc not found (install the CUDA toolkit)" >&2; exit 1; }
fi

out=build/release/gpu_check
cmake --preset release -DPBF_CUDA=ON
start=$(date +%s)
# Every target: the selected tests are in pbf_tests, pbf_particle_fields_tests,
# pbf_render_tests (the viewer's worker), the CLI and the Python module.
cmake --build --preset release -j "$(nproc)"
echo "gpu_check: build took $(( $(date +%s) - start )) s"
mkdir -p "$out"
./build/release/pbf --version | tee "$out/version.txt"
./build/release/pbf --version | grep -q '^  cuda  *[^ nb]' ||
  { echo "gpu_check: the cuda device is not usable (see above)" >&2; exit 1; }

# The GPU backend's tests (gtest cases, the command-line ones, Python's device="cuda"), on the GPU.
tests=0
PBF_TEST_DEVICE=cuda ctest --preset release -R 'Device|device|^python$' -j 1 2>&1 | tee "$out/tests.txt" ||
  tests=$?

# Throughput: particle-steps per second, time per stage, device memory.
./build/release/pbf bench --device cuda --sizes "$sizes" --steps "$steps" 2>&1 | tee "$out/bench_cuda.txt"
./build/release/pbf bench --device cpu --sizes "$sizes" --steps 5 --warmup 2 2>&1 | tee "$out/bench_cpu.txt"
# The optional terms' stages (surface tension with adhesion, the physical
# viscosity) at 1M: their cost on the GPU is the growth of the `post` column
# over bench_cuda.txt's 1M row.
./build/release/pbf bench --device cuda --sizes 1M --steps "$steps" \
  --set fluid.surface_tension=0.0728 --set solver.wall_adhesion=0.5 \
  --set fluid.kinematic_viscosity=1e-6 2>&1 | tee "$out/bench_cuda_surface_tension.txt"
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv | tee "$out/gpu.txt"
if [ "$tests" -ne 0 ]; then
  echo "gpu_check: tests FAILED on the GPU (see $out/tests.txt); benchmark figures above" >&2
  exit 1
fi
echo "gpu_check: done; results in $out"
