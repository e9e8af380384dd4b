#!/usr/bin/env bash
# Quick start, command 2: install what is missing, check the formatting and clang-tidy's checks,
# build with warnings as errors, and run every test: unit + validation (Release), then the unit
# tests again under AddressSanitizer + UndefinedBehaviorSanitizer, then each fuzz target for 60 s.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

echo "== clang-format"
files=$(git ls-files '*.cpp' '*.hpp' 2>/dev/null || find src apps tests bench -name '*.[ch]pp')
clang-format --dry-run --Werror $files

echo "== clang-tidy: the checks of .clang-tidy (docs/reliability.md, Static checks)"
bash scripts/tidy.sh

echo "== layers: every include points down (docs/ARCHITECTURE.md, Layers)"
/usr/bin/python3 scripts/check_layers.py

echo "== release build + all tests"
bash scripts/build.sh release
ctest --preset release -j "$(nproc)"

echo "== asan-ubsan build + unit tests"
bash scripts/build.sh asan-ubsan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --preset asan-ubsan -j "$(nproc)"

# -- fuzzing (tests/fuzz, docs/reliability.md): the libFuzzer targets, built by the asan-ubsan
# build above (clang), 60 s each from their seeds; a crash fails the run and its input is kept
# in build/fuzz/crashes/.
echo "== fuzz targets, 60 s each"
bash scripts/fuzz.sh 60

# ThreadSanitizer: the threaded unit tests on two threads (docs/reliability.md; about 5 min).
echo "== tsan build + threaded unit tests"
bash scripts/tsan.sh
