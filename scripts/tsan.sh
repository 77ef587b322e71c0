#!/usr/bin/env bash
# ThreadSanitizer run of the threaded tests (preset `tsan`: clang, LLVM's
# libomp). GCC's libgomp is not TSan-instrumented (every barrier would look
# like a race), so this build uses LLVM's OpenMP runtime and loads its Archer
# tool, which reports OpenMP's synchronisation to TSan. See docs/reliability.md.
# Usage: scripts/tsan.sh [GTEST_FILTER]
set -euo pipefail
cd "$(dirname "$0")/.."

filter=${1:-'Determinism.*:NeighborSearch.*:StateGuard.*:Checkpoint.*:Physics.*'}

scripts/install_deps.sh --clang
cmake --preset tsan
cmake --build --preset tsan -j "$(nproc)" --target pbf_tests

archer=$(clang++ -print-file-name=libarcher.so)
if [ ! -e "$archer" ]; then archer=$(ls /usr/lib/llvm-*/lib/libarcher.so | tail -1); fi
export OMP_TOOL_LIBRARIES=$archer
export ARCHER_OPTIONS="verbose=1"
# ignore_noninstrumented_modules: libomp itself is not TSan-built; Archer
# annotates its synchronisation instead.
# exitcode=66: a report ends the run with 66, told apart from test failures (1).
# suppressions: oneTBB's internals (inside OpenVDB's mesh conversion), see the file.
export TSAN_OPTIONS="ignore_noninstrumented_modules=1 halt_on_error=1 exitcode=66 second_deadlock_stack=1 suppressions=$PWD/scripts/tsan.supp"
status=0
for threads in 2 4; do
    echo "tsan.sh: $threads threads, filter $filter"
    rc=0
    OMP_NUM_THREADS=$threads build/tsan/tests/pbf_tests --gtest_filter="$filter" --gtest_brief=1 || rc=$?
    if [ "$rc" -eq 66 ]; then
        echo "tsan.sh: ThreadSanitizer REPORTED A DATA RACE with $threads threads (see above)"
        exit 1
    elif [ "$rc" -ne 0 ]; then
        echo "tsan.sh: no data race with $threads threads, but tests failed (exit $rc; see above)"
        status=1
    else
        echo "tsan.sh: $threads threads: tests passed, no data race reported"
    fi
done
exit $status
