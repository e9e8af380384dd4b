#!/usr/bin/env bash
# clang-tidy with the checks of .clang-tidy (each chosen there, with its reason) over Sable's
# translation units in src/, apps/ and tests/, from the release preset's
# compile_commands.json (configured here, not built), $(nproc) files at a time.
#
#   bash scripts/tidy.sh
#
# Exit status: 0 when nothing is found; 1 on a finding not in KNOWN, or when one of KNOWN is
# no longer found (so that the list shrinks with the code); 2 when clang-tidy fails on a file
# without a finding (a crash). Each finding is printed once; `clang-tidy -p build/release FILE`
# shows it with its notes.
set -euo pipefail
cd "$(dirname "$0")/.."

# FILE:CHECK findings tolerated for now, each with its reason (none today).
KNOWN=()

t0=$(date +%s)
cmake --preset release >/dev/null
mapfile -t files < <(/usr/bin/python3 - build/release/compile_commands.json <<'EOF'
import json, os, sys
names = {os.path.relpath(os.path.join(e["directory"], e["file"]))
         for e in json.load(open(sys.argv[1]))}
print("\n".join(sorted(n for n in names if n.split("/")[0] in ("src", "apps", "tests"))))
EOF
)

log=$(mktemp -d)
trap 'rm -rf "$log"' EXIT
# The release build is GCC's: clang does not know some of its warning options (-Wno-restrict).
printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -I{} sh -c \
  'clang-tidy -p build/release --quiet --extra-arg=-Wno-unknown-warning-option "$1" \
     >"$2/$(echo "$1" | tr / _).log" 2>&1 || echo "$1" >>"$2/failed"' _ {} "$log"

diag='^[^ ].*:[0-9]+:[0-9]+: (warning|error): .* \[[^]]+\]$'
grep -hE "$diag" "$log"/*.log | sed "s|^$PWD/||" | sort -u >"$log/findings" || true

status=0
cp "$log/findings" "$log/new"
for k in "${KNOWN[@]}"; do
  pattern="^${k%%:*}:[0-9]+:[0-9]+: .* \[${k#*:}[],]"
  if grep -qE "$pattern" "$log/new"; then
    grep -vE "$pattern" "$log/new" >"$log/rest" || true
    mv "$log/rest" "$log/new"
  else
    echo "tidy: $k is no longer found: remove it from KNOWN in scripts/tidy.sh" >&2
    status=1
  fi
done
if [ -s "$log/new" ]; then
  cat "$log/new" >&2
  echo "tidy: $(wc -l <"$log/new") finding(s)" >&2
  status=1
fi
if [ -f "$log/failed" ]; then
  while read -r f; do
    if ! grep -qE "$diag" "$log/$(echo "$f" | tr / _).log"; then
      echo "tidy: clang-tidy failed on $f:" >&2
      cat "$log/$(echo "$f" | tr / _).log" >&2
      status=2
    fi
  done <"$log/failed"
fi
echo "tidy: ${#files[@]} files, $(($(date +%s) - t0)) s, ${#KNOWN[@]} known finding(s) left"
exit "$status"
