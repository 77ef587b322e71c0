#!/usr/bin/env bash
# One command for a machine with an NVIDIA GPU: the GPU backend's tests on the
# GPU (the gtest cases that every CI run passes on cuda-on-cpu, with
# PBF_TEST_DEVICE=cuda), then `pbf bench --device cuda` at 128k, 1M and 4M
# particles, the same sizes on the cpu device for comparison, and 128k / 1M
# on cuda with surface tension and adhesion on.
#
# Two ways to get the binaries:
#   scripts/gpu_check.sh                 builds here (release preset,
#                                        PBF_CUDA=ON): needs scripts/install_deps.sh
#                                        and the CUDA toolkit on the GPU machine.
#   scripts/gpu_check.sh --pack DIR      on a machine with a CUDA build
#                                        (build/release, PBF_CUDA=ON) but no
#                                        GPU: packs pbf, pbf_tests and the
#                                        shared libraries they need (not glibc,
#                                        not the driver) into DIR/bundle.tar.xz
#                                        (about 16 MB), and stops.
#   scripts/gpu_check.sh --bundle DIR    on a GPU machine without pbf's
#                                        Debian packages (a cloud image): runs
#                                        the checks with DIR/bundle.tar.xz.
# Everything it prints is also written to OUT (default build/release/gpu_check).
# Usage: scripts/gpu_check.sh [--sizes 128k,1M,4M] [--steps N] [--out OUT] [--pack DIR | --bundle DIR]
# Put the figures in docs/performance.md ("GPU") with the GPU's name.
set -euo pipefail
cd "$(dirname "$0")/.."

sizes=128k,1M,4M
steps=20
out=build/release/gpu_check
pack=
bundle=
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --pack) pack=$2; shift 2 ;;
    --bundle) bundle=$2; shift 2 ;;
    *) echo "gpu_check: unknown argument $1" >&2; exit 2 ;;
  esac
done

if [ -n "$pack" ]; then
  grep -q 'PBF_CUDA:BOOL=ON' build/release/CMakeCache.txt ||
    { echo "gpu_check: build/release is not a CUDA build (cmake --preset release -DPBF_CUDA=ON)" >&2; exit 1; }
  staging=$(mktemp -d)
  mkdir -p "$staging/bin" "$staging/lib" "$pack"
  cp build/release/pbf build/release/tests/pbf_tests "$staging/bin/"
  # The source tree the tests read their scenes and data from (compiled-in paths).
  pwd > "$staging/source_dir"
  for b in "$staging"/bin/*; do ldd "$b"; done | awk '/=>/ {print $3}' | sort -u |
    grep -v -E '/(libc|libm|libpthread|libdl|librt|ld-linux-x86-64|libcuda)\.so' |
    while read -r lib; do cp -L "$lib" "$staging/lib/"; done
  tar -C "$staging" -cf - bin lib source_dir | xz -T0 -6 > "$pack/bundle.tar.xz"
  rm -rf "$staging"
  echo "gpu_check: packed $(du -h "$pack/bundle.tar.xz" | cut -f1) into $pack/bundle.tar.xz"
  exit 0
fi

if ! command -v nvidia-smi > /dev/null || ! nvidia-smi -L; then
  echo "gpu_check: no NVIDIA GPU here (nvidia-smi lists none)" >&2
  exit 1
fi
mkdir -p "$out"
if [ -n "$bundle" ]; then
  unpacked=$(mktemp -d)
  tar -C "$unpacked" -xJf "$bundle/bundle.tar.xz"
  export LD_LIBRARY_PATH="$unpacked/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  pbf="$unpacked/bin/pbf"
  tests_bin="$unpacked/bin/pbf_tests"
  # The tests find scenes/ and tests/data through the packing machine's path.
  source_dir=$(cat "$unpacked/source_dir")
  if [ ! -e "$source_dir" ]; then mkdir -p "$(dirname "$source_dir")"; ln -s "$PWD" "$source_dir"; fi
else
  if ! command -v nvcc > /dev/null; then
    export PATH=/usr/local/cuda/bin:$PATH
    command -v nvcc > /dev/null || { echo "gpu_check: nvcc not found (install the CUDA toolkit)" >&2; exit 1; }
  fi
  cmake --preset release -DPBF_CUDA=ON
  start=$(date +%s)
  cmake --build --preset release -j "$(nproc)" --target pbf_cli pbf_tests
  echo "gpu_check: build took $(( $(date +%s) - start )) s"
  pbf=./build/release/pbf
  tests_bin=./build/release/tests/pbf_tests
fi
export OMP_WAIT_POLICY=passive

nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv | tee "$out/gpu.txt"
"$pbf" --version | tee "$out/version.txt"
"$pbf" --version | grep -q '^  cuda  *[^ nb]' ||
  { echo "gpu_check: the cuda device is not usable (see above)" >&2; exit 1; }

# The GPU backend's tests on the GPU, and cuda-on-cpu with this machine's
# threads (the CI machines have two).
tests=0
PBF_TEST_DEVICE=cuda "$tests_bin" --gtest_filter='DeviceWorld.*:Clouds/DeviceVsReference.*' \
  > "$out/tests_cuda.txt" 2>&1 || tests=$?
"$tests_bin" --gtest_filter='DeviceThrustVersions.*:BlockCache.*:DeviceWorld.DamBreak*:DeviceWorld.SurfaceTension*' \
  > "$out/tests_cuda_on_cpu.txt" 2>&1 || tests=$?
grep -h -E '^\[  (PASSED|FAILED) ' "$out"/tests_*.txt || true

# Throughput: particle-steps per second, time per stage, device memory.
"$pbf" bench --device cuda --sizes "$sizes" --steps "$steps" 2>&1 | tee "$out/bench_cuda.txt"
"$pbf" bench --device cpu --sizes "$sizes" --steps 3 --warmup 1 2>&1 | tee "$out/bench_cpu.txt"
# Surface tension with adhesion: its cost is the growth of the `post` column
# over bench_cuda.txt's rows.
"$pbf" bench --device cuda --sizes 128k,1M --steps "$steps" \
  --set fluid.surface_tension=0.0728 --set solver.wall_adhesion=0.5 2>&1 | tee "$out/bench_cuda_surface_tension.txt"
if [ "$tests" -ne 0 ]; then
  echo "gpu_check: tests FAILED (see $out/tests_*.txt); benchmark figures above" >&2
  exit 1
fi
echo "gpu_check: done; results in $out"
