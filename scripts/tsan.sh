#!/usr/bin/env bash
# The ThreadSanitizer check (docs/reliability.md): install what is missing, build the `tsan`
# preset (clang, -fsanitize=thread, LLVM's libomp with its OMPT tool Archer) and run the unit
# tests that use more than one thread (ctest label `threads`) under it, on two threads.
# Exit status: 0 when every test passes with no TSan report, non-zero otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

t0=$(date +%s)
echo "== tsan build"
bash scripts/build.sh tsan
t1=$(date +%s)

# Without Archer every OpenMP barrier would look unsynchronised to TSan: the run would fail
# loudly with false reports rather than pass quietly, but say so plainly first.
echo "== Archer loaded?"
log=$(ctest --preset tsan -R '^GrainSplit\.ChunksHandOutEveryGrainOnce$' -V 2>&1) || true
if ! grep -q "Archer detected OpenMP application with TSan" <<< "$log"; then
  echo "tsan: Archer did not announce itself; is OMP_TOOL_LIBRARIES set (tests/CMakeLists.txt)?" >&2
  tail -n 20 <<< "$log" >&2
  exit 1
fi

echo "== threaded unit tests under TSan"
ctest --preset tsan -j "$(nproc)"
t2=$(date +%s)
echo "tsan: build $((t1 - t0)) s, tests $((t2 - t1)) s"
