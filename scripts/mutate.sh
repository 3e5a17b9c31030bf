#!/usr/bin/env bash
# Mutation check: does the test suite notice plausible bugs? Each mutation in
# scripts/mutations.txt replaces one exact piece of code (it must occur exactly once) in a scratch
# copy of the committed tree; the tests named beside it must then fail. The working tree is never
# touched.
#   scripts/mutate.sh [NAME...]        default: every mutation
# Prints one line per mutation (killed / SURVIVED / does not apply) and the score; exit 0 when every
# mutation was killed, 1 otherwise. About 2-4 minutes per mutation on 2 cores (an incremental
# rebuild of one library and the tests that link it, then those tests).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
list=scripts/mutations.txt
jobs="${MUTATE_JOBS:-$(nproc)}"

scratch=$(mktemp -d /tmp/slamprep-mutate.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
git archive HEAD | tar -x -C "$scratch"
mkdir -p "$scratch/tests/formats/mcap_reader"
[ -d tests/formats/mcap_reader/node_modules ] &&
  ln -s "$root/tests/formats/mcap_reader/node_modules" "$scratch/tests/formats/mcap_reader/node_modules"
echo "mutate: building the unmutated tree in $scratch/build"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$scratch" -B "$scratch/build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  > "$scratch/configure.log"
cmake --build "$scratch/build" -j"$jobs" > "$scratch/build.log" 2>&1 ||
  { tail -30 "$scratch/build.log"; exit 2; }

# mutations.txt: blocks separated by a line "---"; each block has the lines
#   name: <name>     file: <path>     tests: <ctest -R regex>     why: <the bug it models>
#   old: <exact text, one line>      new: <replacement, one line>
python3 - "$list" > "$scratch/mutations.tsv" <<'EOF'
import sys
blocks = open(sys.argv[1]).read().split("\n---\n")
for b in blocks:
    fields = {}
    for line in b.splitlines():
        if line.startswith("#") or ":" not in line:
            continue
        key, value = line.split(":", 1)
        fields[key.strip()] = value[1:] if value.startswith(" ") else value
    if "name" in fields:
        print("\t".join(fields[k] for k in ("name", "file", "tests", "old", "new", "why")))
EOF

wanted=("$@")
killed=0
total=0
survived=()
while IFS=$'\t' read -r name file tests old new why; do
  if ((${#wanted[@]})) && [[ ! " ${wanted[*]} " =~ " $name " ]]; then continue; fi
  total=$((total + 1))
  target="$scratch/$file"
  cp "$target" "$scratch/original"
  if ! python3 - "$target" "$old" "$new" <<'EOF'; then
import sys
path, old, new = sys.argv[1:4]
text = open(path).read()
if text.count(old) != 1:
    sys.exit(1)
open(path, "w").write(text.replace(old, new))
EOF
    echo "mutate: $name: does not apply (the code in $file changed; update $list)"
    survived+=("$name (does not apply)")
    continue
  fi
  result=SURVIVED
  if ! cmake --build "$scratch/build" -j"$jobs" > "$scratch/build.log" 2>&1; then
    result="killed (does not compile)"
  elif ! ctest --test-dir "$scratch/build" -R "$tests" --timeout 600 -j"$jobs" \
    > "$scratch/ctest.log" 2>&1; then
    result="killed by $(grep -c 'Failed\|Timeout' "$scratch/ctest.log" || true) failing test(s)"
  fi
  cp "$scratch/original" "$target"
  touch "$target"
  echo "mutate: $name: $result  ($why)"
  if [ "$result" = SURVIVED ]; then survived+=("$name"); else killed=$((killed + 1)); fi
done < "$scratch/mutations.tsv"

echo "mutate: score $killed/$total killed"
((${#survived[@]})) && { printf 'mutate: survived: %s\n' "${survived[@]}"; exit 1; }
exit 0
