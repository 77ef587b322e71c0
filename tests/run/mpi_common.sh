# Shared by the MPI test scripts (sourced): arguments, the skip without MPI,
# a fresh work directory and the mpirun command line.
# Arguments: PBF WORKDIR SOURCE_DIR MPI_BUILT MPIRUN
pbf=$1
work=$2
src=$3
built=$4
mpirun=${5:-}
if [ "$built" != "ON" ] || [ -z "$mpirun" ] || [ ! -x "$mpirun" ]; then
    echo "SKIP: pbf was built without MPI (PBF_MPI=$built) or mpirun is missing; install" \
         "libopenmpi-dev openmpi-bin and reconfigure to run the distributed tests"
    exit 77
fi
rm -rf "$work"
mkdir -p "$work"
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
mpi=("$mpirun" --oversubscribe --allow-run-as-root --mca btl self,vader)
fail() { echo "FAIL: $*" >&2; exit 1; }
