#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The measurements behind the weak-scaling projection of the PETSc back-end
# (README.md, "The PETSc back-end"): for each problem and N, the bytes the
# 2 ranks send each other during a boundary_value_bench --backend petsc run
# (Open MPI's pml monitoring: point-to-point "E" and the collectives' "I"),
# and PETSc's -log_view of the same solve on 1 rank with MUMPS, whose
# analysis (MatLUFactorSym) is sequential: on K ranks it stays one rank's
# work on the whole matrix.
#   bench/boundary_value/run_traffic.sh OUT_DIR [N ...]   # default N = 1e4 1e5
# writes OUT_DIR/traffic.jsonl and OUT_DIR/log_view_mumps-PROBLEM-N.txt;
# backend_tables.py reads them. BENCH selects the executable (default
# BUILD_DIR/bench/boundary_value_bench, BUILD_DIR as run_backend.sh's).
set -euo pipefail
build_dir=${BUILD_DIR:-/tmp/build-bvp-bench}
bench=${BENCH:-$build_dir/bench/boundary_value_bench}
out_dir=$1
shift
sizes=("$@")
((${#sizes[@]})) || sizes=(10000 100000)
mkdir -p "$out_dir"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
results="$out_dir/traffic.jsonl"
: > "$results"
for problem in lcs game; do
  for n in "${sizes[@]}"; do
    echo "load $(cut -d' ' -f1 /proc/loadavg): traffic $problem N = $n" >&2
    output=$(mpiexec --mca pml_monitoring_enable 2 --mca pml_monitoring_enable_output 1 -n 2 \
      "$bench" --problem "$problem" --steps "$n" --backend petsc 2>&1)
    line=$(grep '^{' <<<"$output" | tail -1)
    # "E|I  FROM  TO  BYTES bytes  COUNT msgs sent": rank to other rank only.
    bytes=$(awk -F'\t' '($1 == "E" || $1 == "I") && $2 != $3 {
        split($4, b, " "); split($5, c, " "); sum[$1] += b[1]; msgs[$1] += c[1] }
      END { printf "\"p2p_bytes\": %d, \"p2p_messages\": %d, \"collective_bytes\": %d, \"collective_messages\": %d",
            sum["E"], msgs["E"], sum["I"], msgs["I"] }' <<<"$output")
    echo "${line%\}}, $bytes}" >> "$results"
    echo "load $(cut -d' ' -f1 /proc/loadavg): -log_view MUMPS $problem N = $n" >&2
    PETSC_OPTIONS="-pc_factor_mat_solver_type mumps -log_view :$out_dir/log_view_mumps-$problem-$n.txt" \
      "$bench" --problem "$problem" --steps "$n" --backend petsc >/dev/null
  done
done
