#!/usr/bin/env bash
# How a sweep's wall time falls with MPI ranks on this machine, what one combination costs, and what the merge
# costs: the numbers behind the README's "Past one machine". Each wall time is the best of three runs.
# usage: bench/mpi_scaling.sh [BUILD]   (BUILD: a build with MPI, default build/)
set -euo pipefail
marchcheck=$(realpath "${1:-build}")/cli/marchcheck
# 48 combinations of lee-flat at its own size (640x360), one timed render each.
sweep="sweep lee-flat --vary marcher=sphere,relaxed --vary max_steps=16,32,64,128 --vary hit_eps=1e-2,1e-3,1e-4
       --vary normal=central,tetra --repeat 1"
combinations=48
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
# --bind-to none: Open MPI binds each of up to 2 ranks to one core, and marchcheck renders on every core it has.
mpirun="mpirun --allow-run-as-root --oversubscribe --mca btl self,vader --bind-to none"
best_of_three() {
  local best=""
  for _ in 1 2 3; do
    local start=$EPOCHREALTIME
    "$@" >/dev/null 2>&1
    best=$(awk -v s="$start" -v e="$EPOCHREALTIME" -v b="$best" 'BEGIN { t = e - s; print (b == "" || t < b) ? t : b }')
  done
  echo "$best"
}
# shellcheck disable=SC2086 # the sweep's words are meant to split
one=$(best_of_three "$marchcheck" $sweep --json "$scratch/one.json")
printf "%-34s %8.3f s  (%.1f ms a combination)\n" "one process, $combinations combinations" "$one" \
  "$(awk -v t="$one" -v n=$combinations 'BEGIN { print 1000 * t / n }')"
for ranks in 1 2 4; do
  # shellcheck disable=SC2086
  t=$(best_of_three $mpirun -n $ranks "$marchcheck" $sweep --json "$scratch/mpi.json")
  printf "%-34s %8.3f s  (%.2fx one process)\n" "mpirun -n $ranks" "$t" "$(awk -v a="$one" -v b="$t" 'BEGIN { print a / b }')"
done
for i in $(seq 0 47); do
  # shellcheck disable=SC2086
  "$marchcheck" $sweep --shard "$i/48" --json "$scratch/shard$i.json" >/dev/null
done
t=$(best_of_three "$marchcheck" merge "$scratch"/shard*.json -o "$scratch/merged.json")
printf "%-34s %8.3f s  (%.1f ms a shard)\n" "merge of 48 one-combination shards" "$t" \
  "$(awk -v t="$t" 'BEGIN { print 1000 * t / 48 }')"
