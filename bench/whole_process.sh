#!/usr/bin/env bash
# marchcheck beside the plain OpenMP port a user writes first (../shared/bench/naive_lee.cpp, built as
# bench/naive_lee where that folder is present): lee-flat at 1280x720 with shadows and specular, on 2 threads, in
# one run of this script, one program after the other. Whole process: the wall time of each command, PNG written
# for marchcheck (the port writes nothing); in process: the render's own seconds, as each prints them. Each figure
# is the median of RUNS runs (default 9). Start-up: `marchcheck --help`.
# usage: bench/whole_process.sh [BUILD]   (default build/)
set -euo pipefail
build=$(realpath "${1:-build}")
marchcheck=$build/cli/marchcheck naive=$build/bench/naive_lee
runs=${RUNS:-9}
[[ -x $naive ]] || { echo "whole_process.sh: $naive is missing (it is built where ../shared/bench is present)" >&2; exit 2; }
export OMP_NUM_THREADS=2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# Wall seconds of one run of the command; its standard output into $scratch/out.
wall() {
  local start=$EPOCHREALTIME
  "$@" >"$scratch/out" 2>&1
  awk -v s="$start" -v e="$EPOCHREALTIME" 'BEGIN { printf "%.4f\n", e - s }'
}

startup=() product=() product_in=() port=() port_in=()
for _ in $(seq "$runs"); do
  startup+=("$(wall "$marchcheck" --help)")
  product+=("$(wall "$marchcheck" render lee-flat --size 1280x720 -o "$scratch/x.png")")
  # "lee-flat: 1280x720, 38.1 evaluations per pixel, 0.053 s -> ...": the seconds before " s ->".
  product_in+=("$(sed -n 's/.* \([0-9.]*\) s -> .*/\1/p' "$scratch/out")")
  port+=("$(wall "$naive" 1280 720)")
  # "1280x720  0.166 s  ...": the second field.
  port_in+=("$(awk '{ print $2 }' "$scratch/out")")
done
m_startup=$(printf '%s\n' "${startup[@]}" | median)
m_product=$(printf '%s\n' "${product[@]}" | median) m_port=$(printf '%s\n' "${port[@]}" | median)
m_product_in=$(printf '%s\n' "${product_in[@]}" | median) m_port_in=$(printf '%s\n' "${port_in[@]}" | median)
awk -v su="$m_startup" -v p="$m_product" -v n="$m_port" -v pi="$m_product_in" -v ni="$m_port_in" -v runs="$runs" 'BEGIN {
  printf "lee-flat 1280x720, 2 threads, median of %d runs\n", runs
  printf "  start-up (marchcheck --help)           %8.4f s   (target <= 0.020)\n", su
  printf "  whole process: marchcheck render -o png %7.4f s   naive port %.4f s   port / marchcheck %.2fx (target >= 2)\n", p, n, n / p
  printf "  in process:    marchcheck render        %7.4f s   naive port %.4f s   port / marchcheck %.2fx (target >= 6)\n", pi, ni, ni / pi
}'
