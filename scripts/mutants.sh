#!/usr/bin/env bash
# Mutation testing: applies the project's mutants (tests/mutants/*.mut, one plausible bug each) one at a time with
# ../shared/tools/mutate, rebuilding build/ and running ctest after each; every file is put back afterwards.
#   scripts/mutants.sh               all of them
#   scripts/mutants.sh --sample N    N of them, picked from the commit hash (each commit tries others): CI's run
#   scripts/mutants.sh FILE.mut...   the ones named
# Exit status: 0 every mutant killed, 1 one survived (the test suite cannot see that bug), 2 could not run.
set -euo pipefail
cd "$(dirname "$0")/.."
mutate=../shared/tools/mutate
[ -x "$mutate" ] || { echo "mutants: $mutate is absent"; exit 2; }
[ -f build/CMakeCache.txt ] || { echo "mutants: build/ is not configured (scripts/build.sh)"; exit 2; }
mapfile -t all < <(find tests/mutants -name '*.mut' | LC_ALL=C sort)
# Every mutant must still apply (its line found exactly once), whichever are sampled: a refactor that moves the
# line makes a stale mutant, which would test nothing.
stale=0
for m in "${all[@]}"; do
  file=$(sed -n 's/^file: //p' "$m")
  from=$(sed -n 's/^from: //p' "$m")
  if [ ! -f "$file" ] || [ "$(grep -cF -- "$from" "$file")" != 1 ]; then
    echo "mutants: $m: its 'from' line is not found exactly once in $file (update the mutant)"
    stale=1
  fi
done
[ "$stale" = 0 ] || exit 2
# A mutant of code only one instruction set compiles says so in a line "needs: <preprocessor condition>" (as
# "defined(__AVX512F__)"); where build/'s compiler and flags leave that code out, the mutant would change nothing and
# survive, so it is set aside, said, and not sampled.
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:FILEPATH=//p' build/CMakeCache.txt)
flags=()
grep -q '^MARCHCHECK_NATIVE:BOOL=ON' build/CMakeCache.txt && flags=(-march=native)
compiled_here() {
  local needs
  needs=$(sed -n 's/^needs: //p' "$1")
  [ -z "$needs" ] || printf '#if %s\nyes\n#endif\n' "$needs" | "$compiler" "${flags[@]}" -x c++ -E -P - | grep -qx yes
}
here=() elsewhere=()
for m in "${all[@]}"; do
  if compiled_here "$m"; then here+=("$m"); else elsewhere+=("${m##*/}"); fi
done
((${#elsewhere[@]} == 0)) || echo "mutants: not compiled for this machine's instruction set, set aside: ${elsewhere[*]}"
all=("${here[@]}")
picked=()
if [ "${1:-}" = "--sample" ]; then
  n=${2:?--sample needs a count}
  count=${#all[@]}
  # Every (count / n)-th mutant from an offset the commit gives: a rotating, reproducible sample.
  offset=$((16#$(git rev-parse HEAD | cut -c1-7) % count))
  stride=$((count / n > 0 ? count / n : 1))
  for ((k = 0; k < n && k < count; ++k)); do picked+=("${all[$(((offset + k * stride) % count))]}"); done
elif [ $# -gt 0 ]; then
  for m in "$@"; do
    if compiled_here "$m"; then picked+=("$m"); else echo "mutants: ${m##*/} is not compiled here, set aside"; fi
  done
else
  picked=("${all[@]}")
fi
((${#picked[@]} > 0)) || { echo "mutants: none to run here"; exit 0; }
echo "mutants: ${#picked[@]} of ${#all[@]}: ${picked[*]##*/}"
exec "$mutate" -b build "${picked[@]}"
