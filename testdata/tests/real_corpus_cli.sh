#!/usr/bin/env bash
# Every detector of the ceilnav program over the real-image corpus
# (testdata/real/README.md), the way a user runs it: the frames exported as
# PNG folders, `ceilnav run` with several cameras (pitch 45, zenith, the
# recording's own lens), `ceilnav pattern` with the built-in station's lens and
# database. None of the frames shows tape or the pattern: any `ok` row fails.
# Closing line: "N passed, N failed".
set -u
CEILNAV=${CEILNAV:?set CEILNAV to the ceilnav binary}
EXPORT=${EXPORT:?set EXPORT to ceilnav_real_corpus_export}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
ok() { passed=$((passed + 1)); echo "PASS $1"; }
bad() { failed=$((failed + 1)); echo "FAIL $1"; [ -n "${2:-}" ] && echo "  $2"; }

# status_counts CSV: "N status" lines of the CSV's status column.
status_counts() {
  local col
  col=$(head -1 "$1" | tr ',' '\n' | grep -nx status | cut -d: -f1)
  [ -n "$col" ] || { echo "no status column"; return 1; }
  tail -n +2 "$1" | cut -d, -f"$col" | sort | uniq -c
}

if "$EXPORT" "$work/corpus" >"$work/export.log" 2>&1; then ok "export"; else bad "export" "$(cat "$work/export.log")"; fi
sets=$(ls "$work/corpus")

# The station's lens and database (`ceilnav pattern --out` writes both).
"$CEILNAV" pattern --out "$work/station" --quiet >/dev/null 2>&1 || bad "station scene"
for p in 45 90; do
  sed "s/^camera_pitch_deg:.*/camera_pitch_deg: $p./" "$work/station/scene.yaml" >"$work/pitch$p.yaml"
done
cp "$here/../real/cycloid_ceiltrack/camera.yaml" "$work/cycloid_lens.yaml"

# expect_no_ok NAME CSV N: the CSV has N rows and none of them is ok.
expect_no_ok() {
  local name=$1 csv=$2 n=$3 rows counts
  rows=$(($(wc -l <"$csv") - 1))
  counts=$(status_counts "$csv" | tr '\n' ' ')
  if [ "$rows" -eq "$n" ] && ! status_counts "$csv" | grep -qw ok; then
    ok "$name: no ok in $rows frames ($counts)"
  else
    bad "$name: $rows of $n rows" "$counts"
  fi
}

for set in $sets; do
  n=$(ls "$work/corpus/$set" | wc -l)
  for scene in pitch45 pitch90 cycloid_lens; do
    csv=$work/run_${set}_$scene.csv
    if "$CEILNAV" run --frames "$work/corpus/$set" --scene "$work/$scene.yaml" --out "$csv" \
        >/dev/null 2>"$work/err"; then
      expect_no_ok "run $set $scene" "$csv" "$n"
    else
      bad "run $set $scene" "$(cat "$work/err")"
    fi
  done
  out=$work/pattern_$set
  if "$CEILNAV" pattern --frames "$work/corpus/$set" --scene "$work/station/scene.yaml" \
      --database "$work/station/patterns.yaml" --out "$out" --quiet >/dev/null 2>"$work/err"; then
    expect_no_ok "pattern $set" "$out/pattern.csv" "$n"
  else
    bad "pattern $set" "$(cat "$work/err")"
  fi
done

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
