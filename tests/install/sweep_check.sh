# Sourced by test_install.sh and test_subproject.sh: the consumer's simulator runs a sweep and,
# where mpirun is, phynjo::mpi reached the outside project: on 2 ranks the sweep gives the same
# bytes, and one run is refused (a simulator without MPI would run it on both ranks).
sweeper=$1
"$sweeper" --grid theta=0.1:1:70 --t-end 0.5 --summary "$work/one.csv"
if command -v mpirun >/dev/null; then
  # under AddressSanitizer: Open MPI's unloaded components leak at exit (test_sweep_mpi.sh)
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
  mpirun --allow-run-as-root --oversubscribe --timeout 300 -np 2 "$sweeper" --grid theta=0.1:1:70 --t-end 0.5 --summary "$work/two.csv"
  cmp "$work/one.csv" "$work/two.csv"
  if mpirun --allow-run-as-root --oversubscribe --timeout 300 -np 2 "$sweeper" --t-end 0.1 -o /dev/null 2>/dev/null; then
    echo "FAIL the consumer's simulator ran one run on 2 ranks: it was built without phynjo::mpi"; exit 1
  fi
fi
