#!/usr/bin/env bash
# End-to-end tests of the ceilnav program: every command's --help, a render ->
# run round trip checked against truth, and every bad input (message, non-zero
# exit, no output file left behind). Closing line: "N passed, N failed".
set -u
CEILNAV=${CEILNAV:?set CEILNAV to the ceilnav binary}
# Backends compared with the fast path (rtl when the build has the Verilated device).
CLI_BACKENDS=${CLI_BACKENDS:-model}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0

ok() { passed=$((passed + 1)); echo "PASS $1"; }
bad() { failed=$((failed + 1)); echo "FAIL $1"; [ -n "${2:-}" ] && echo "  $2"; }

# expect_error NAME PATTERN OUTFILE -- ARGS...: non-zero exit, stderr matches
# PATTERN, OUTFILE does not exist afterwards.
expect_error() {
  local name=$1 pattern=$2 outfile=$3
  shift 4
  local err
  err=$("$CEILNAV" "$@" 2>&1 >/dev/null)
  local rc=$?
  if [ $rc -eq 0 ]; then bad "$name" "exit code 0"; return; fi
  if ! grep -qiE -- "$pattern" <<<"$err"; then bad "$name" "message '$err' lacks /$pattern/"; return; fi
  if [ -n "$outfile" ] && [ -e "$outfile" ]; then bad "$name" "left $outfile behind"; return; fi
  if [ -n "$outfile" ] && ls -a "$(dirname "$outfile")" 2>/dev/null | grep -qE '\.tmp$|^\.staging\.'; then
    bad "$name" "left a temporary file or staging folder"; return
  fi
  ok "$name"
}

for cmd in "" demo run render accuracy exposure profile pattern pattern-accuracy drive render-drive calibrate-mount corridor homing; do
  if $CEILNAV $cmd --help >"$work/help.txt" 2>&1 && grep -q -- "--" "$work/help.txt"; then
    ok "help ${cmd:-top}"
  else
    bad "help ${cmd:-top}"
  fi
done

# A good data set: rendered frames with known pose.
frames=$work/frames
if $CEILNAV render --out "$frames" --frames 6 --random-poses --seed 7 >/dev/null 2>&1; then
  ok "render"
else
  bad "render"
fi
out=$work/out.csv
if $CEILNAV run --frames "$frames" --scene "$frames/scene.yaml" --out "$out" 2>"$work/run.err"; then
  ok "run exit 0"
else
  bad "run exit 0" "$(cat "$work/run.err")"
fi
header=$(head -1 "$out" 2>/dev/null)
for col in frame status yaw_rad offset_m pitch_rad vp_u vp_v junction junction_side junction_distance_m; do
  if tr ',' '\n' <<<"$header" | grep -qx "$col"; then ok "column $col"; else bad "column $col"; fi
done
rows=$(($(wc -l <"$out") - 1))
[ "$rows" -eq 6 ] && ok "one row per frame" || bad "one row per frame" "rows=$rows"
# Compare yaw and offset with truth.csv, frame by frame (name order).
if join -t, <(tail -n +2 "$out" | cut -d, -f1-4 | sort) <(tail -n +2 "$frames/truth.csv" | cut -d, -f1-3 | sort) |
  awk -F, '{ if ($2 != "ok") exit 1; dy = $3 - $5; do_ = $4 - $6; if (dy < 0) dy = -dy; if (do_ < 0) do_ = -do_;
             if (dy > 0.0035 || do_ > 0.01) exit 1; n++ } END { exit n == 6 ? 0 : 1 }'; then
  ok "run matches truth (yaw < 0.2 deg, offset < 10 mm)"
else
  bad "run matches truth"
fi
if ! grep -qi nan "$out"; then ok "no NaN in CSV"; else bad "no NaN in CSV"; fi
# --track: random poses are no sequence. Expected statuses from truth.csv by
# the tracking rule: lock on the first frame and after a jump; a pose that
# moved more than 5 deg or 0.1 m from the held one is a jump.
if $CEILNAV run --frames "$frames" --scene "$frames/scene.yaml" --out "$work/track.csv" --track 2>/dev/null; then
  got=$(tail -n +2 "$work/track.csv" | sort | cut -d, -f2 | tr '\n' ' ')
  want=$(tail -n +2 "$frames/truth.csv" | sort | awk -F, '
    { if (!held) { s = "ok"; held = 1; y = $2; o = $3 }
      else { dy = $2 - y; do_ = $3 - o; if (dy < 0) dy = -dy; if (do_ < 0) do_ = -do_;
             if (dy > 5 * 3.14159265 / 180 || do_ > 0.1) { s = "jump"; held = 0 }
             else { s = "ok"; y = $2; o = $3 } }
      printf "%s ", s }')
  [ "$got" = "$want" ] && [[ "$got" == *jump* ]] && ok "run --track: jumps where the truth moved beyond a frame's motion" ||
    bad "run --track: jumps where the truth moved beyond a frame's motion" "got: $got want: $want"
else
  bad "run --track exit 0"
fi

# --overlay-every N: overlays/<frame name>.png beside the CSV for frames 0, N,
# 2N, ...; the CSV is the same as without it; none by default.
[ ! -e "$work/overlays" ] && ok "run writes no overlays by default" || bad "run writes no overlays by default"
mkdir -p "$work/five"; cp "$frames"/frame_000[0-4].png "$work/five/"
for n in 1 2; do
  mkdir -p "$work/ov$n"
  if $CEILNAV run --frames "$work/five" --scene "$frames/scene.yaml" --out "$work/ov$n/out.csv" \
      --overlay-every $n 2>"$work/ov$n.err" && cmp -s <(head -6 "$out") "$work/ov$n/out.csv"; then
    ok "run --overlay-every $n exit 0, same CSV"
  else
    bad "run --overlay-every $n exit 0, same CSV" "$(cat "$work/ov$n.err")"
  fi
done
got1=$(cd "$work/ov1/overlays" 2>/dev/null && ls -A | tr '\n' ' ')
[ "$got1" = "frame_0000.png frame_0001.png frame_0002.png frame_0003.png frame_0004.png " ] &&
  ok "run --overlay-every 1: 5 overlays of 5 frames" || bad "run --overlay-every 1: 5 overlays of 5 frames" "got: $got1"
got2=$(cd "$work/ov2/overlays" 2>/dev/null && ls -A | tr '\n' ' ')
[ "$got2" = "frame_0000.png frame_0002.png frame_0004.png " ] &&
  ok "run --overlay-every 2: frames 0, 2, 4" || bad "run --overlay-every 2: frames 0, 2, 4" "got: $got2"
# The PNG header (IHDR): 640 x 480, 8-bit, colour type 2 (RGB).
ihdr=$(python3 -c 'import struct, sys; d = open(sys.argv[1], "rb").read(29); print(*struct.unpack(">IIBB", d[16:26]))' \
  "$work/ov1/overlays/frame_0003.png" 2>&1)
[ "$ihdr" = "640 480 8 2" ] && ok "run overlay is a 640x480 colour PNG" || bad "run overlay is a 640x480 colour PNG" "IHDR: $ihdr"
mkdir -p "$work/ovbad"
expect_error "run --overlay-every -1" "overlay-every" "$work/ovbad/out.csv" -- run --frames "$work/five" --scene "$frames/scene.yaml" --out "$work/ovbad/out.csv" --overlay-every -1
expect_error "run --overlay-every x" "overlay-every" "$work/ovbad/out.csv" -- run --frames "$work/five" --scene "$frames/scene.yaml" --out "$work/ovbad/out.csv" --overlay-every x
[ ! -e "$work/ovbad/overlays" ] && ok "bad --overlay-every: no overlays folder" || bad "bad --overlay-every: no overlays folder"

# Clocked model gives the same CSV as the fast path.
# Every backend gives the same CSV, byte for byte (model/rtl: through the
# registers, with random gaps, back-pressure and AXI-Lite stalls).
for backend in $CLI_BACKENDS; do
  if $CEILNAV run --frames "$frames" --scene "$frames/scene.yaml" --out "$work/$backend.csv" --backend $backend \
    --gap-probability 0.2 --backpressure-probability 0.5 --seed 3 2>"$work/$backend.err" && cmp -s "$out" "$work/$backend.csv"; then
    ok "$backend == fast CSV"
  else
    bad "$backend == fast CSV" "$(cat "$work/$backend.err")"
  fi
done

# The demo: same results CSV on every backend.
if $CEILNAV demo --out "$work/demo_fast" --frames 3 >/dev/null 2>&1; then ok "demo"; else bad "demo"; fi
for backend in $CLI_BACKENDS; do
  if $CEILNAV demo --out "$work/demo_$backend" --frames 3 --backend $backend >/dev/null 2>&1 &&
    cmp -s "$work/demo_fast/results.csv" "$work/demo_$backend/results.csv"; then
    ok "demo $backend == fast CSV"
  else
    bad "demo $backend == fast CSV"
  fi
done
for f in results.csv truth.csv scene.yaml overlay.png; do
  [ -s "$work/demo_fast/$f" ] && ok "demo wrote $f" || bad "demo wrote $f"
done

# ---- bad inputs
o=$work/never.csv
expect_error "missing frames folder" "does not exist" "$o" -- run --frames "$work/nope" --scene "$frames/scene.yaml" --out "$o"
expect_error "frames is a file" "not a folder" "$o" -- run --frames "$frames/scene.yaml" --scene "$frames/scene.yaml" --out "$o"
mkdir -p "$work/empty"
expect_error "empty folder" "no PNG" "$o" -- run --frames "$work/empty" --scene "$frames/scene.yaml" --out "$o"

mkdir -p "$work/corrupt"; cp "$frames"/frame_000[0-2].png "$work/corrupt/"
head -c 200 /dev/urandom >"$work/corrupt/frame_0001.png"
expect_error "corrupt PNG" "cannot decode" "$o" -- run --frames "$work/corrupt" --scene "$frames/scene.yaml" --out "$o"

mkdir -p "$work/trunc"; cp "$frames"/frame_000[0-2].png "$work/trunc/"
head -c 3000 "$frames/frame_0003.png" >"$work/trunc/frame_0002.png"
expect_error "truncated PNG" "cannot decode" "$o" -- run --frames "$work/trunc" --scene "$frames/scene.yaml" --out "$o"

mkdir -p "$work/small"
$CEILNAV render --out "$work/small" --frames 1 --width 320 --height 240 >/dev/null 2>&1
expect_error "mis-sized frame" "320x240 but the scene says 640x480" "$o" -- run --frames "$work/small" --scene "$frames/scene.yaml" --out "$o"

# A mis-sized frame in the middle of the folder: no CSV although two frames
# before it were processed.
mkdir -p "$work/midsize"; cp "$frames"/frame_000[0-3].png "$work/midsize/"
cp "$work/small/frame_0000.png" "$work/midsize/frame_0002.png"
expect_error "mis-sized frame mid-folder" "frame_0002.png' is 320x240 but the scene says 640x480" "$o" -- run --frames "$work/midsize" --scene "$frames/scene.yaml" --out "$o"

mkdir -p "$work/deep"; cp "$here/data/grey16.png" "$work/deep/"
expect_error "16-bit frame" "16-bit" "$o" -- run --frames "$work/deep" --scene "$frames/scene.yaml" --out "$o"

# Colour frames (RGB, RGBA; red and blue differ from green so that the BT.601
# grey conversion gives the grey frame back, and swapped channels would not):
# accepted, and the CSV equals the grey frames' byte for byte.
if command -v python3 >/dev/null 2>&1; then
  for kind in rgb rgba; do
    mkdir -p "$work/$kind"
    for f in "$frames"/frame_*.png; do python3 "$here/png_colour.py" $kind "$f" "$work/$kind/$(basename "$f")"; done
    if $CEILNAV run --frames "$work/$kind" --scene "$frames/scene.yaml" --out "$work/$kind.csv" 2>"$work/$kind.err" &&
      cmp -s "$out" "$work/$kind.csv"; then
      ok "$kind frames == grey CSV"
    else
      bad "$kind frames == grey CSV" "$(cat "$work/$kind.err")"
    fi
  done
else
  bad "colour frames" "python3 (installed by scripts/setup) is needed to write them"
fi

# Scene files: garbage, missing key, mistyped key, out of range, missing file.
printf 'this: is: not: yaml: [\n' >"$work/garbage.yaml"
expect_error "garbage YAML" "garbage.yaml" "$o" -- run --frames "$frames" --scene "$work/garbage.yaml" --out "$o"
grep -v '^tape_width_m' "$frames/scene.yaml" >"$work/nokey.yaml"
expect_error "missing YAML key" "tape_width_m" "$o" -- run --frames "$frames" --scene "$work/nokey.yaml" --out "$o"
sed 's/^camera_height_m:.*/camera_height_m: "high"/' "$frames/scene.yaml" >"$work/typo.yaml"
expect_error "mistyped YAML key" "camera_height_m" "$o" -- run --frames "$frames" --scene "$work/typo.yaml" --out "$o"
# A lens whose distortion is not invertible over the image (k1 = -0.5 turns
# the radial map back at r = 0.816, r_d = 0.544, inside the corner's 0.775).
awk '/^distortion_coefficients:/ { print "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.5, 0., 0., 0., 0. ]"; skip = 1; next }
     skip && /^ / { next } { skip = 0; print }' "$frames/scene.yaml" >"$work/fold.yaml"
expect_error "non-invertible distortion" "fold.yaml.*distortion_coefficients.*not invertible over the image: .*turns back at r = 0.816.*inside the image corner r_d = 0.775" "$o" -- run --frames "$frames" --scene "$work/fold.yaml" --out "$o"
sed 's/^camera_pitch_deg:.*/camera_pitch_deg: 120./' "$frames/scene.yaml" >"$work/range.yaml"
expect_error "out-of-range pitch" "camera_pitch_deg" "$o" -- run --frames "$frames" --scene "$work/range.yaml" --out "$o"
expect_error "missing scene file" "nothere.yaml" "$o" -- run --frames "$frames" --scene "$work/nothere.yaml" --out "$o"
: >"$work/empty.yaml"
expect_error "empty scene file" "empty.yaml" "$o" -- run --frames "$frames" --scene "$work/empty.yaml" --out "$o"

# Unwritable output: folder missing, output is a folder, parent is a file.
expect_error "output folder missing" "does not exist" "$work/nodir/out.csv" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$work/nodir/out.csv"
expect_error "output is a folder" "is a folder" "" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$work/empty"
expect_error "output under a file" "cannot write" "" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$frames/scene.yaml/out.csv"
# /proc takes no new files, even from root (for whom chmod a-w changes nothing).
expect_error "run output unwritable" "cannot write '/proc/ceilnav_cli.csv'" "/proc/ceilnav_cli.csv" -- run --frames "$frames" --scene "$frames/scene.yaml" --out /proc/ceilnav_cli.csv
expect_error "render out unwritable" "cannot create output folder '/proc/ceilnav_cli'" "/proc/ceilnav_cli" -- render --out /proc/ceilnav_cli --frames 1
expect_error "render out under a file" "cannot create output folder" "" -- render --out "$frames/scene.yaml/r" --frames 1
expect_error "demo out unwritable" "cannot create output folder '/proc/ceilnav_cli'" "/proc/ceilnav_cli" -- demo --out /proc/ceilnav_cli --frames 2
expect_error "accuracy csv unwritable" "cannot write '/proc/ceilnav_cli.csv'" "/proc/ceilnav_cli.csv" -- accuracy --frames 1 --csv /proc/ceilnav_cli.csv
expect_error "accuracy csv folder missing" "does not exist" "$work/nodir/acc.csv" -- accuracy --frames 1 --csv "$work/nodir/acc.csv"
expect_error "accuracy csv is a folder" "is a folder" "" -- accuracy --frames 1 --csv "$work/empty"
# exposure: the three threshold policies on an exposure sweep, a CSV row per
# frame and policy; bad arguments refused before any output.
if $CEILNAV exposure --frames 6 --csv "$work/expo.csv" >"$work/expo.log" 2>&1 &&
    [ "$(grep -c '^first_frame \|^previous_frame \|^previous_frame_rerun ' "$work/expo.log")" -eq 6 ] &&
    [ "$(tail -n +2 "$work/expo.csv" | wc -l)" -eq 18 ]; then
  ok "exposure sweep"
else
  bad "exposure sweep" "$(cat "$work/expo.log")"
fi
expect_error "exposure one frame" "frames" "" -- exposure --frames 1
expect_error "exposure pitch 0" "pitch" "" -- exposure --pitch 0
expect_error "exposure csv unwritable" "cannot write '/proc/ceilnav_cli.csv'" "/proc/ceilnav_cli.csv" -- exposure --frames 2 --csv /proc/ceilnav_cli.csv
# A write that fails part way (a 1 KiB file size limit, SIGXFSZ ignored so
# that write() fails with EFBIG): render and demo leave no file, not even the
# folder they created; an existing folder keeps what it had.
for cmd in render demo; do
  err=$( (trap '' XFSZ; ulimit -f 1; "$CEILNAV" $cmd --out "$work/limit_$cmd/sub" --frames 2 2>&1 >/dev/null) )
  rc=$?
  if [ $rc -ne 0 ] && grep -q "error while writing" <<<"$err" && [ ! -e "$work/limit_$cmd" ]; then
    ok "$cmd write error leaves nothing"
  else
    bad "$cmd write error leaves nothing" "rc=$rc, '$err', $(ls -a "$work/limit_$cmd" 2>&1 | tr '\n' ' ')"
  fi
done
err=$( (trap '' XFSZ; ulimit -f 1; "$CEILNAV" profile --count 1 --width 32 --height 16 --sweep-frames 0 --out "$work/limit_profile/sub" 2>&1 >/dev/null) )
rc=$?
if [ $rc -ne 0 ] && grep -q "error while writing" <<<"$err" && [ ! -e "$work/limit_profile" ]; then
  ok "profile write error leaves nothing"
else
  bad "profile write error leaves nothing" "rc=$rc, '$err', $(ls -a "$work/limit_profile" 2>&1 | tr '\n' ' ')"
fi
mkdir -p "$work/keep"; echo old >"$work/keep/frame_0000.png"
err=$( (trap '' XFSZ; ulimit -f 1; "$CEILNAV" render --out "$work/keep" --frames 2 2>&1 >/dev/null) )
if [ $? -ne 0 ] && [ "$(ls -A "$work/keep")" = "frame_0000.png" ] && [ "$(cat "$work/keep/frame_0000.png")" = old ]; then
  ok "render write error keeps the folder as it was"
else
  bad "render write error keeps the folder as it was" "$err; $(ls -A "$work/keep" | tr '\n' ' ')"
fi

# Arguments.
expect_error "unknown command" "" "" -- fly
expect_error "missing --scene" "scene" "" -- run --frames "$frames" --out "$o"
expect_error "bad --frames number" "frames" "$work/d" -- demo --frames 1 --out "$work/d"
expect_error "unknown backend" "--backend: foo not in" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --backend foo
expect_error "demo unknown backend" "--backend: foo not in" "$work/d" -- demo --backend foo --out "$work/d"
if [ "$CLI_BACKENDS" = "${CLI_BACKENDS/rtl/}" ]; then
  expect_error "rtl backend not built" "built without the Verilated RTL backend" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --backend rtl
fi
# Bad numbers: NaN, inf, out of range, not a number, a negative seed.
expect_error "gap probability NaN" "--gap-probability: 'nan' is not a finite number" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --backend model --gap-probability nan
expect_error "gap probability 1" "--gap-probability: '1' is not a finite number in \[0, 0.99\]" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --backend model --gap-probability 1
expect_error "back-pressure not a number" "--backpressure-probability: 'half'" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --backpressure-probability half
expect_error "negative seed" "--seed: '-1' is not an integer" "$o" -- run --frames "$frames" --scene "$frames/scene.yaml" --out "$o" --seed -1
expect_error "render noise inf" "--noise: 'inf' is not a finite number" "$work/r" -- render --out "$work/r" --noise inf
expect_error "render blur negative" "--blur: '-1' is not a finite number" "$work/r" -- render --out "$work/r" --blur -1
expect_error "render pitch 0" "--pitch-deg: '0' is not a finite number in \[1, 90\]" "$work/r" -- render --out "$work/r" --pitch-deg 0
expect_error "render frames 0" "--frames" "$work/r" -- render --out "$work/r" --frames 0
expect_error "render width 8" "--width" "$work/r" -- render --out "$work/r" --width 8
expect_error "accuracy yaw NaN" "--yaw-max: 'nan' is not a finite number" "$work/a.csv" -- accuracy --frames 1 --yaw-max nan --csv "$work/a.csv"
expect_error "accuracy tape width 0" "--tape-width-m: '0'" "$work/a.csv" -- accuracy --frames 1 --tape-width-m 0 --csv "$work/a.csv"
expect_error "accuracy pitch-min > pitch-max" "pitch-min/--pitch-max" "$work/a.csv" -- accuracy --frames 1 --pitch-min 50 --pitch-max 40 --csv "$work/a.csv"
expect_error "accuracy ceiling below camera" "--ceiling-m must be above" "$work/a.csv" -- accuracy --frames 1 --ceiling-m 0.3 --csv "$work/a.csv"
expect_error "accuracy frames not a number" "--frames" "$work/a.csv" -- accuracy --frames many --csv "$work/a.csv"

# ---- profile: II = 1, no bubbles, CSV and plots; the same cycle figures on every backend.
# Columns of profile.csv that are cycle figures (host wall times excluded).
cycle_cols='frame,cycles,tvalid_cycles,accepted,pixels_per_valid_cycle,bubbles,pixels_counted,device_cycles,eof_to_irq_cycles,eof_to_irq_register,fifo_high_water,runs_dropped_overflow,runs_dropped_row_limit,runs_emitted,runs,run_beats,run_stall_cycles,words_read,words_written,configure_cycles,readout_cycles,host_cycles,frame_ok'
# cycle_figures CSV: those columns, by name.
cycle_figures() {
  awk -F, -v want="$cycle_cols" 'NR == 1 { n = split(want, w, ","); for (i = 1; i <= NF; i++) col[$i] = i;
    for (j = 1; j <= n; j++) if (!(w[j] in col)) { print "missing " w[j]; exit 1 } }
    { line = ""; for (j = 1; j <= n; j++) line = line (j > 1 ? "," : "") $(col[w[j]]); print line }' "$1"
}
for backend in $CLI_BACKENDS; do
  pdir=$work/profile_$backend
  if $CEILNAV profile --backend $backend --width 160 --height 120 --count 3 --blanking random \
    --backpressure 0.5 --tapes 2 --seed 4 --sweep 0,0.5 --sweep-frames 1 --out "$pdir" \
    >"$work/profile_$backend.out" 2>&1; then
    ok "profile $backend exit 0"
  else
    bad "profile $backend exit 0" "$(tail -5 "$work/profile_$backend.out")"
  fi
  for f in profile.csv profile_summary.csv latency.png fifo.png throughput.png latency.dat fifo.dat throughput.dat; do
    [ -s "$pdir/$f" ] && ok "profile $backend wrote $f" || bad "profile $backend wrote $f"
  done
  rows=$(($(wc -l <"$pdir/profile.csv" 2>/dev/null || echo 1) - 1))
  [ "$rows" -eq 3 ] && ok "profile $backend: one row per frame" || bad "profile $backend: one row per frame" "rows=$rows"
  if cycle_figures "$pdir/profile.csv" >"$work/profile_$backend.cycles" &&
    awk -F, 'NR > 1 { if ($5 != "1.000000" || $6 != 0 || $3 != $4 || $2 != $8) exit 1; n++ } END { exit n == 3 ? 0 : 1 }' \
      "$work/profile_$backend.cycles"; then
    ok "profile $backend: II = 1, 0 bubbles, CYCLES_PER_FRAME = cycles"
  else
    bad "profile $backend: II = 1, 0 bubbles, CYCLES_PER_FRAME = cycles"
  fi
  grep -q "II = 1 and 0 bubbles on every frame: MET" "$work/profile_$backend.out" &&
    ok "profile $backend summary MET" || bad "profile $backend summary MET"
  srows=$(($(wc -l <"$pdir/profile_summary.csv" 2>/dev/null || echo 1) - 1))
  [ "$srows" -eq 3 ] && ok "profile $backend: summary + 2 sweep rows" || bad "profile $backend: summary rows" "rows=$srows"
done
if [ "$CLI_BACKENDS" != "${CLI_BACKENDS/rtl/}" ]; then
  if cmp -s "$work/profile_model.cycles" "$work/profile_rtl.cycles"; then
    ok "profile: model and rtl cycle figures identical"
  else
    bad "profile: model and rtl cycle figures identical" "$(diff "$work/profile_model.cycles" "$work/profile_rtl.cycles" | head -5)"
  fi
fi
# Recorded frames (the rendered folder above, with its scene.yaml), VGA timing.
if $CEILNAV profile --frames "$frames" --count 2 --blanking vga --sweep-frames 0 >"$work/pf.out" 2>&1 &&
  grep -q "640x480, blanking vga" "$work/pf.out" && grep -q "MET" "$work/pf.out"; then
  ok "profile --frames"
else
  bad "profile --frames" "$(tail -5 "$work/pf.out")"
fi
pbad=$work/pbad
expect_error "profile width 0" "width" "$pbad" -- profile --width 0 --out "$pbad"
expect_error "profile width > 1920" "width" "$pbad" -- profile --width 1921 --out "$pbad"
expect_error "profile height > 1080" "height" "$pbad" -- profile --height 1081 --out "$pbad"
expect_error "profile unknown blanking" "blanking" "$pbad" -- profile --blanking ntsc --out "$pbad"
expect_error "profile duty 1" "backpressure" "$pbad" -- profile --backpressure 1 --out "$pbad"
expect_error "profile duty < 0" "backpressure" "$pbad" -- profile --backpressure -0.1 --out "$pbad"
expect_error "profile sweep duty 1" "sweep" "$pbad" -- profile --sweep 0,1 --out "$pbad"
expect_error "profile tapes 0" "tapes" "$pbad" -- profile --tapes 0 --out "$pbad"
expect_error "profile fast backend" "backend" "$pbad" -- profile --backend fast --out "$pbad"
expect_error "profile empty frames folder" "no PNG" "$pbad" -- profile --frames "$work/empty" --out "$pbad"
mkdir -p "$work/noscene"; cp "$frames/frame_0000.png" "$work/noscene/"
expect_error "profile frames without scene" "scene" "$pbad" -- profile --frames "$work/noscene" --out "$pbad"
expect_error "profile out under a file" "not a writable folder|not a folder" "" -- profile --count 1 --out "$frames/scene.yaml/p"
expect_error "profile out in /proc" "cannot create output folder|not a writable folder" "/proc/ceilnav_cli" -- profile --count 1 --width 32 --height 16 --sweep-frames 0 --out /proc/ceilnav_cli
chmod a-w "$work/empty"
if [ -w "$work/empty" ]; then
  echo "SKIP profile unwritable out (root can write anywhere)"
else
  expect_error "profile unwritable out" "writable" "$work/empty/p" -- profile --count 1 --out "$work/empty/p"
fi
chmod u+w "$work/empty"

# pattern: the built-in station scene (pan, find, read, centre, verify), then
# its frames again through --frames, then bad arguments and files.
pat=$work/pat
if $CEILNAV pattern --out "$pat" --quiet >"$work/pat.log" 2>&1; then ok "pattern exit 0"; else bad "pattern exit 0" "$(cat "$work/pat.log")"; fi
pheader=$(head -1 "$pat/pattern.csv" 2>/dev/null)
for col in d_m theta_deg beta_deg identity status x_m y_m heading_deg swing_deg; do
  if tr ',' '\n' <<<"$pheader" | grep -qx "$col"; then ok "pattern column $col"; else bad "pattern column $col"; fi
done
if grep -q ',ok,7,ok,' "$pat/pattern.csv" 2>/dev/null && [ -s "$pat/overlay.png" ]; then
  ok "pattern verified station 7 with overlay"
else
  bad "pattern verified station 7 with overlay"
fi
if grep -q "verified" "$work/pat.log"; then ok "pattern summary"; else bad "pattern summary"; fi
pout=$work/pout
if $CEILNAV pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$pat/patterns.yaml" \
    --out "$pout" --quiet 2>"$work/pout.err" && grep -q ',ok,7,ok,' "$pout/pattern.csv"; then
  ok "pattern --frames round trip"
else
  bad "pattern --frames round trip" "$(cat "$work/pout.err")"
fi
# Only an ok row carries a pose: on every other row d_m .. swing_deg are
# empty (the built-in run has a partial row, where a disc was seen); the
# built-in camera has no swing: |swing_deg| < 0.1 on the ok rows.
for csv in "$pat/pattern.csv" "$pout/pattern.csv"; do
  if awk -F, 'NR > 1 && $3 != "ok" { n++; if ($5 != "no_pattern") seen++; for (i = 6; i <= 12; i++) if ($i != "") wrong++ }
      NR > 1 && $3 == "ok" { if ($6 == "" || $7 == "" || $9 == "" || $10 == "" || $11 == "" || $12 == "") wrong++
                             if ($12 > 0.1 || $12 < -0.1) wrong++ }
      END { exit (wrong == 0 && n > 0 && seen > 0) ? 0 : 1 }' "$csv"; then
    ok "pattern pose columns only on ok rows ($(basename "$(dirname "$csv")"))"
  else
    bad "pattern pose columns only on ok rows ($(basename "$(dirname "$csv")"))" "$(cut -d, -f3-12 "$csv")"
  fi
done
# The pattern command needs only the lens keys; run needs the scene keys too.
grep -vE '^(camera_pitch_deg|camera_height_m|ceiling_height_m|tape_width_m):' "$pat/scene.yaml" >"$work/lens_only.yaml"
if $CEILNAV pattern --frames "$pat/frames" --scene "$work/lens_only.yaml" --database "$pat/patterns.yaml" \
    --out "$work/plens" --quiet 2>"$work/plens.err" && cmp -s "$pout/pattern.csv" "$work/plens/pattern.csv"; then
  ok "pattern --frames with a lens-only scene"
else
  bad "pattern --frames with a lens-only scene" "$(cat "$work/plens.err")"
fi
# A run that fails on a frame after overlays were drawn leaves no CSV and no
# overlays/ (staged, committed only at the end).
mkdir -p "$work/ovfail"
expect_error "run --overlay-every 1 failing mid-way" "320x240" "$work/ovfail/out.csv" -- run --frames "$work/midsize" --scene "$frames/scene.yaml" --out "$work/ovfail/out.csv" --overlay-every 1
[ ! -e "$work/ovfail/overlays" ] && ok "failed run: no overlays folder" || bad "failed run: no overlays folder" "$(ls -aR "$work/ovfail")"
expect_error "run with a lens-only scene" "lens_only.yaml.*camera_pitch_deg.*missing" "$o" -- run --frames "$frames" --scene "$work/lens_only.yaml" --out "$o"
# The pattern frames through every backend: the same CSV, byte for byte (the
# host maths works on the device's class moments and run records).
for backend in $CLI_BACKENDS; do
  if $CEILNAV pattern --out "$work/pat_$backend" --quiet --backend $backend >"$work/pat_$backend.log" 2>&1 &&
    cmp -s "$pat/pattern.csv" "$work/pat_$backend/pattern.csv"; then
    ok "pattern $backend == fast CSV"
  else
    bad "pattern $backend == fast CSV" "$(tail -3 "$work/pat_$backend.log")"
  fi
  if $CEILNAV pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$pat/patterns.yaml" \
      --out "$work/pout_$backend" --quiet --backend $backend 2>"$work/pout_$backend.err" &&
    cmp -s "$pout/pattern.csv" "$work/pout_$backend/pattern.csv"; then
    ok "pattern --frames $backend == fast CSV"
  else
    bad "pattern --frames $backend == fast CSV" "$(cat "$work/pout_$backend.err")"
  fi
done
# --overlay-every on the pattern command: overlays/<frame name>.png of frames
# 0, N, 2N, ... besides overlay.png (kept); none by default; same CSV.
[ ! -e "$pat/overlays" ] && [ ! -e "$pout/overlays" ] && ok "pattern writes no overlays by default" ||
  bad "pattern writes no overlays by default"
npat=$(ls "$pat/frames" | wc -l)
for n in 1 2; do
  if $CEILNAV pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$pat/patterns.yaml" \
      --out "$work/pov$n" --quiet --overlay-every $n 2>"$work/pov$n.err" && cmp -s "$pout/pattern.csv" "$work/pov$n/pattern.csv" &&
    [ -s "$work/pov$n/overlay.png" ]; then
    ok "pattern --frames --overlay-every $n exit 0, same CSV, overlay.png"
  else
    bad "pattern --frames --overlay-every $n exit 0, same CSV, overlay.png" "$(cat "$work/pov$n.err")"
  fi
  want=$(ls "$pat/frames" | awk -v n=$n '(NR - 1) % n == 0' | tr '\n' ' ')
  got=$(cd "$work/pov$n/overlays" 2>/dev/null && ls -A | tr '\n' ' ')
  [ "$npat" -ge 3 ] && [ "$got" = "$want" ] && ok "pattern --overlay-every $n: $(wc -w <<<"$got") of $npat frames" ||
    bad "pattern --overlay-every $n: every ${n}th of $npat frames" "want '$want' got '$got'"
done
# The last frame's overlay.png is the overlays/ file of that frame.
last=$(ls "$pat/frames" | tail -1)
cmp -s "$work/pov1/overlay.png" "$work/pov1/overlays/$last" && ok "pattern overlay.png == overlays/$last" ||
  bad "pattern overlay.png == overlays/$last"
if $CEILNAV pattern --out "$work/pbov" --quiet --overlay-every 3 >/dev/null 2>&1 && cmp -s "$pat/pattern.csv" "$work/pbov/pattern.csv"; then
  want=$(ls "$pat/frames" | awk '(NR - 1) % 3 == 0' | tr '\n' ' ')
  got=$(cd "$work/pbov/overlays" 2>/dev/null && ls -A | tr '\n' ' ')
  [ "$got" = "$want" ] && ok "pattern built-in --overlay-every 3" || bad "pattern built-in --overlay-every 3" "want '$want' got '$got'"
else
  bad "pattern built-in --overlay-every 3" "exit or CSV differs"
fi
expect_error "pattern --overlay-every -2" "overlay-every" "$work/pbadov" -- pattern --out "$work/pbadov" --overlay-every -2
expect_error "pattern --frames --overlay-every -1" "overlay-every" "$work/pbadov" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$pat/patterns.yaml" --out "$work/pbadov" --overlay-every -1
pbad2=$work/pbad2
expect_error "pattern frames without scene" "scene" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --database "$pat/patterns.yaml" --out "$pbad2"
expect_error "pattern scene without frames" "with --frames" "$pbad2/pattern.csv" -- pattern --scene "$pat/scene.yaml" --out "$pbad2"
expect_error "pattern missing database" "database" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$work/nope.yaml" --out "$pbad2"
printf '%%YAML:1.0\npatterns:\n  - { identity: 99, x_m: 1, y_m: 2, z_m: 1, facing_deg: 0 }\n' >"$work/db_bad_id.yaml"
expect_error "pattern database identity out of range" "identity" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$work/db_bad_id.yaml" --out "$pbad2"
printf '%%YAML:1.0\npatterns:\n  - { identity: 3, x_m: 1, y_m: 2 }\n' >"$work/db_no_z.yaml"
expect_error "pattern database missing key" "missing key z_m" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$work/db_no_z.yaml" --out "$pbad2"
printf '%%YAML:1.0\npatterns: []\n' >"$work/db_empty.yaml"
expect_error "pattern database without patterns" "db_empty.yaml: has no patterns" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$work/db_empty.yaml" --out "$pbad2"
expect_error "pattern non-invertible distortion" "fold.yaml.*distortion_coefficients.*not invertible" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$work/fold.yaml" --database "$pat/patterns.yaml" --out "$pbad2"
printf 'not yaml at all: [\n' >"$work/db_garbage.yaml"
expect_error "pattern database garbage" "database" "$pbad2/pattern.csv" -- pattern --frames "$pat/frames" --scene "$pat/scene.yaml" --database "$work/db_garbage.yaml" --out "$pbad2"
mkdir -p "$work/pempty"
expect_error "pattern empty frames folder" "no PNG" "$pbad2/pattern.csv" -- pattern --frames "$work/pempty" --scene "$pat/scene.yaml" --database "$pat/patterns.yaml" --out "$pbad2"
mkdir -p "$work/psmall"; cp "$frames/frame_0000.png" "$work/psmall/"
sed 's/image_width: 640/image_width: 320/' "$pat/scene.yaml" >"$work/scene320.yaml"
expect_error "pattern frame size mismatch" "size|width|320" "$pbad2/pattern.csv" -- pattern --frames "$work/psmall" --scene "$work/scene320.yaml" --database "$pat/patterns.yaml" --out "$pbad2"
expect_error "pattern negative noise" "noise" "" -- pattern --noise -1 --out "$pbad2"
expect_error "pattern without out" "out" "" -- pattern
expect_error "pattern unknown backend" "--backend: foo not in" "$pbad2/pattern.csv" -- pattern --backend foo --out "$pbad2"
expect_error "pattern-accuracy unknown backend" "--backend: foo not in" "" -- pattern-accuracy --backend foo
if [ "$CLI_BACKENDS" = "${CLI_BACKENDS/rtl/}" ]; then
  expect_error "pattern rtl backend not built" "built without the Verilated RTL backend" "$pbad2/pattern.csv" -- pattern --backend rtl --out "$pbad2"
fi
expect_error "pattern-accuracy width" "width" "" -- pattern-accuracy --width 10
expect_error "pattern-accuracy noise" "noise" "" -- pattern-accuracy --noise -2
expect_error "pattern-accuracy calib blur" "calib-blur" "" -- pattern-accuracy --calib-blur -0.5
expect_error "pattern-accuracy calib noise" "calib-noise" "" -- pattern-accuracy --calib-noise 99
expect_error "pattern-accuracy csv folder missing" "writable|folder|exist" "$work/nodir/p.csv" -- pattern-accuracy --csv "$work/nodir/p.csv"
# The camera photometry the study renders (the host self-calibrates): bad values refused.
expect_error "pattern-accuracy gain zero" "--gain" "" -- pattern-accuracy --gain 0
expect_error "pattern-accuracy gain not a number" "--gain" "" -- pattern-accuracy --gain abc
expect_error "pattern-accuracy gain too high" "--gain" "" -- pattern-accuracy --gain 5
expect_error "pattern-accuracy offset out of range" "--offset" "" -- pattern-accuracy --offset 300
expect_error "pattern-accuracy vignetting 1" "--vignetting" "" -- pattern-accuracy --vignetting 1
expect_error "pattern-accuracy vignetting negative" "--vignetting" "" -- pattern-accuracy --vignetting -0.1
expect_error "pattern-accuracy sweep with csv" "photometric-sweep.*excludes|excludes.*photometric-sweep" "$work/sweep.csv" -- pattern-accuracy --photometric-sweep --csv "$work/sweep.csv"
expect_error "pattern-accuracy sweep with plot" "photometric-sweep.*excludes|excludes.*photometric-sweep" "$work/sweep.png" -- pattern-accuracy --photometric-sweep --plot "$work/sweep.png"
expect_error "pattern-accuracy sweep with gain" "photometric-sweep.*excludes|excludes.*photometric-sweep" "" -- pattern-accuracy --photometric-sweep --gain 1.1

# run --odometry: a rendered drive towards the gap at 6 m with wheel odometry
# that reports 1 % too much travel. The tape-width height needs no odometry;
# the flow height carries the odometry's scale, which the run estimates.
drive=$work/drive
for cmd in render-drive; do
  if $CEILNAV $cmd --help >"$work/help.txt" 2>&1 && grep -q -- "--scale-error" "$work/help.txt"; then ok "help $cmd"; else bad "help $cmd"; fi
done
if $CEILNAV render-drive --out "$drive" --path curve --length 6 --scale-error 0.01 --seed 3 >/dev/null 2>&1 &&
  [ -f "$drive/odometry.csv" ] && [ -f "$drive/robot.yaml" ] && [ -f "$drive/frame_times.csv" ]; then
  ok "render-drive"
else
  bad "render-drive"
fi
# col FILE NAME: the column number of NAME in FILE's header.
col() { head -1 "$1" | tr ',' '\n' | grep -nx "$2" | cut -d: -f1; }
# last_value FILE NAME: the last non-empty value of column NAME.
last_value() { awk -F, -v c="$(col "$1" "$2")" 'NR > 1 && $c != "" { v = $c } END { print v }' "$1"; }
# within NAME VALUE WANT REL: |VALUE / WANT - 1| <= REL.
within() {
  if [ -n "$2" ] && awk -v v="$2" -v w="$3" -v r="$4" 'BEGIN { d = v / w - 1; exit !(d <= r && d >= -r) }'; then
    ok "$1 ($2, want $3)"
  else
    bad "$1" "got '$2', want $3 within $4"
  fi
}
odo_out=$work/odo/out.csv
mkdir -p "$work/odo"
if $CEILNAV run --frames "$drive/frames" --scene "$drive/scene.yaml" --out "$odo_out" \
  --odometry "$drive/odometry.csv" --robot "$drive/robot.yaml" \
  --frame-times "$drive/frame_times.csv" 2>"$work/odo.err"; then
  ok "run --odometry exit 0"
else
  bad "run --odometry exit 0" "$(cat "$work/odo.err")"
fi
for c in flow_ceiling_m flow_ceiling_se_m flow_range_m flow_frames width_ceiling_m odometry_scale; do
  if [ -n "$(col "$odo_out" "$c")" ]; then ok "column $c"; else bad "column $c"; fi
done
# Truth: 2.3 m above the camera; the odometry's scale is 1.01.
within "odometry: width height" "$(last_value "$odo_out" width_ceiling_m)" 2.3 0.005
within "odometry: flow height = c x scale" "$(last_value "$odo_out" flow_ceiling_m)" 2.323 0.005
within "odometry: scale estimate" "$(last_value "$odo_out" odometry_scale)" 1.01 0.004
# The range of the tracked tape end (6, 0) at the last frame with a fit, from
# the truth pose of that frame, times the odometry's scale.
range_row=$(awk -F, -v c="$(col "$odo_out" flow_range_m)" 'NR > 1 && $c != "" { f = $1; v = $c } END { print f, v }' "$odo_out")
range_want=$(awk -F, -v f="${range_row% *}" '$1 == f { printf "%.6f", 1.01 * ((6 - $3) * cos($5) - $4 * sin($5)) }' "$drive/truth.csv")
within "odometry: tape end range (eq. 57)" "${range_row#* }" "${range_want:-1}" 0.01
# The flow columns are empty on frames without a tracked tape end, never NaN.
if grep -qi nan "$odo_out"; then bad "odometry: no NaN"; else ok "odometry: no NaN"; fi
# Without --odometry the columns exist and are empty.
if [ "$(last_value "$out" width_ceiling_m)" = "" ] && [ -n "$(col "$out" width_ceiling_m)" ]; then
  ok "odometry columns empty without --odometry"
else
  bad "odometry columns empty without --odometry"
fi
# Body velocities from the counts (0.1 mm per count, wheel base 0.4 m), each
# row's velocity held until the next; frames at i / 2 s (--fps).
awk -F, 'BEGIN { n = 0 } NR > 1 { t[n] = $1; l[n] = $2; r[n] = $3; n++ }
  END { print "t_s,v_mps,omega_radps";
        for (i = 0; i < n; i++) {
          if (i + 1 < n) { dt = t[i + 1] - t[i]; dl = (l[i + 1] - l[i]) * 1e-4; dr = (r[i + 1] - r[i]) * 1e-4 }
          printf "%s,%.9f,%.9f\n", t[i], (dl + dr) / 2 / dt, (dr - dl) / 0.4 / dt } }' \
  "$drive/odometry.csv" >"$work/odo/velocity.csv"
if $CEILNAV run --frames "$drive/frames" --scene "$drive/scene.yaml" --out "$work/odo/vel.csv" \
  --odometry "$work/odo/velocity.csv" --fps 2 2>"$work/odo.err"; then
  ok "run --odometry velocities --fps exit 0"
else
  bad "run --odometry velocities --fps exit 0" "$(cat "$work/odo.err")"
fi
within "odometry velocities: scale estimate" "$(last_value "$work/odo/vel.csv" odometry_scale)" 1.01 0.004

# Bad odometry inputs: a message naming the problem, non-zero exit, no CSV.
ob=$work/odobad/out.csv
mkdir -p "$work/odobad"
run_odo() { echo run --frames "$drive/frames" --scene "$drive/scene.yaml" --out "$ob" "$@"; }
printf 't,left,right\n0,0,0\n1,5,5\n' >"$work/odobad/header.csv"
printf 't_s,left_ticks,right_ticks\n0,0,0\n1,5,5\n1,6,6\n' >"$work/odobad/time.csv"
printf 't_s,left_ticks,right_ticks\n0,0,0\n1,5\n' >"$work/odobad/fields.csv"
printf 't_s,v_mps,omega_radps\n0,0.5,0\n1,fast,0\n' >"$work/odobad/number.csv"
printf 't_s,v_mps,omega_radps\n0,0.5,0\n1,0.5,0\n' >"$work/odobad/short.csv"
printf 'frame,t_s\nframe_0000.png,0.01\n' >"$work/odobad/times.csv"
printf 'wheel_base_m: 0.4\nleft_m_per_count: 1e-4\n' >"$work/odobad/robot.yaml"
# shellcheck disable=SC2046
expect_error "odometry bad header" "header.csv:1: header" "$ob" -- $(run_odo --odometry "$work/odobad/header.csv" --robot "$drive/robot.yaml" --fps 2)
expect_error "odometry time not increasing" "time.csv:4: time 1 is not after" "$ob" -- $(run_odo --odometry "$work/odobad/time.csv" --robot "$drive/robot.yaml" --fps 2)
expect_error "odometry missing field" "fields.csv:3: expected 3 fields" "$ob" -- $(run_odo --odometry "$work/odobad/fields.csv" --robot "$drive/robot.yaml" --fps 2)
expect_error "odometry not a number" "number.csv:3: v_mps 'fast' is not a number" "$ob" -- $(run_odo --odometry "$work/odobad/number.csv" --fps 2)
expect_error "odometry counts without robot" "--robot" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --fps 2)
expect_error "odometry robot key missing" "robot.yaml: missing key 'right_m_per_count'" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --robot "$work/odobad/robot.yaml" --fps 2)
expect_error "odometry frames outside its span" "outside the odometry's span" "$ob" -- $(run_odo --odometry "$work/odobad/short.csv" --fps 2)
expect_error "odometry frame without a time" "no time for frame 'frame_0001.png'" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --robot "$drive/robot.yaml" --frame-times "$work/odobad/times.csv")
expect_error "odometry without frame times" "--frame-times FILE or --fps" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --robot "$drive/robot.yaml")
expect_error "odometry missing file" "cannot open" "$ob" -- $(run_odo --odometry "$work/odobad/none.csv" --fps 2)
expect_error "robot without odometry" "--robot requires --odometry" "$ob" -- $(run_odo --robot "$drive/robot.yaml")
expect_error "fps with frame times" "excludes" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --fps 2 --frame-times "$drive/frame_times.csv")
expect_error "fps zero" "--fps" "$ob" -- $(run_odo --odometry "$drive/odometry.csv" --fps 0)
expect_error "render-drive bad path" "--path" "$work/odobad/d" -- render-drive --out "$work/odobad/d" --path zigzag

# drive: a short course file (a gap, an L-turn) closed loop; its outputs;
# bad course files and arguments leave no output folder.
mkdir -p "$work/cl"
cat >"$work/cl/short.yaml" <<'YAML'
format: ceilnav_course
version: 1
name: short
ceiling: {height_m: 2.5}
tapes:
  - {name: A, width_m: 0.05, points: [[-1, 0], [4, 0], [4, 3]], gaps: [[2, 2.6]]}
start: {x_m: 0, y_m: 0, yaw_deg: 0}
route: [left]
YAML
dd=$work/cl/out
if $CEILNAV drive --course "$work/cl/short.yaml" --out "$dd" --quiet >"$work/cl/log.txt" 2>&1 &&
  [ -f "$dd/trajectory.csv" ] && [ -f "$dd/summary.json" ] && [ -f "$dd/drive.png" ] &&
  [ -f "$dd/course.yaml" ] && grep -q "\"goals_met\"" "$dd/summary.json" &&
  grep -q '"junctions_taken": 1' "$dd/summary.json" && grep -q '"gaps_crossed": 1' "$dd/summary.json" &&
  head -1 "$dd/trajectory.csv" | grep -q '^t_s,x_m,y_m,yaw_rad,est_x_m'; then
  ok "drive short course"
else
  bad "drive short course" "$(tail -3 "$work/cl/log.txt")"
fi
# The same second of the drive with a pattern station on the course on every
# backend compared: the trajectory (truth, estimate, frame statuses) is the
# fast backend's, byte for byte (the device's passes set the latency).
sed 's/^route: \[left\]/patterns: [{id: 7, x_m: 3, y_m: 1.2, yaw_rad: 0}]\nroute: [left]/' \
  "$work/cl/short.yaml" >"$work/cl/station.yaml"
if $CEILNAV drive --course "$work/cl/station.yaml" --out "$work/cl/bfast" --quiet --no-plot \
  --max-time 1 >/dev/null 2>&1 && grep -q '"fixes_accepted": [1-9]' "$work/cl/bfast/summary.json"; then
  ok "drive fixes a station within its first second"
else
  bad "drive fixes a station within its first second"
fi
for b in $CLI_BACKENDS; do
  if $CEILNAV drive --course "$work/cl/station.yaml" --out "$work/cl/b$b" --quiet --no-plot --max-time 1 \
    --backend "$b" >/dev/null 2>&1 && grep -q "\"backend\": \"$b\"" "$work/cl/b$b/summary.json" &&
    cmp -s "$work/cl/bfast/trajectory.csv" "$work/cl/b$b/trajectory.csv"; then
    ok "drive on $b drives the fast backend's trajectory"
  else
    bad "drive on $b drives the fast backend's trajectory"
  fi
done
# Dead reckoning on purpose: the robot drives the route to its end without
# vision (not stopped as lost), and the summary judges the end's error by the
# filter's own covariance.
if $CEILNAV drive --course "$work/cl/short.yaml" --out "$work/cl/blind" --quiet --no-vision --no-plot >/dev/null 2>&1 &&
  grep -q '"finished": true' "$work/cl/blind/summary.json" &&
  grep -q '"lost": false' "$work/cl/blind/summary.json" &&
  grep -q '"final_pose_nees_le_chi2_99"' "$work/cl/blind/summary.json" &&
  grep -q '"final_position_sigma_mm"' "$work/cl/blind/summary.json"; then
  ok "drive without vision dead-reckons to the end"
else
  bad "drive without vision dead-reckons to the end"
fi
sed 's/route: \[left\]/route: [right]/' "$work/cl/short.yaml" >"$work/cl/wrong_turn.yaml"
expect_error "drive impossible turn" "turn 1 \(right\) of the route does not exist" "$work/cl/bad1" -- drive --course "$work/cl/wrong_turn.yaml" --out "$work/cl/bad1" --quiet
sed 's/width_m: 0.05/width_m: -1/' "$work/cl/short.yaml" >"$work/cl/bad_width.yaml"
expect_error "drive bad course file" "width" "$work/cl/bad2" -- drive --course "$work/cl/bad_width.yaml" --out "$work/cl/bad2" --quiet
expect_error "drive missing course" "course" "$work/cl/bad3" -- drive --course "$work/cl/none.yaml" --out "$work/cl/bad3"
expect_error "drive both courses" "excludes" "$work/cl/bad4" -- drive --course "$work/cl/short.yaml" --random-course 3 --out "$work/cl/bad4"

# calibrate-mount: the calibration drive recovers the mounting yaw within
# 0.05 deg (--require), writes calibration.json and frames.csv; two seeds
# give the Monte-Carlo distributions; bad arguments leave no output folder.
mkdir -p "$work/cal"
co=$work/cal/out
if $CEILNAV calibrate-mount --out "$co" --run-length 3 --yaw -0.7 --roll 0.4 --pitch-error 0.8 \
  --seed 2 --quiet --require >"$work/cal/log.txt" 2>&1 &&
  [ -f "$co/calibration.json" ] && [ -f "$co/frames.csv" ] &&
  grep -q '"yaw_within_goal": true' "$co/calibration.json" &&
  grep -q '"roll_deg": 0.4' "$co/calibration.json" && grep -q '"filter_mount"' "$co/calibration.json" &&
  head -1 "$co/frames.csv" | grep -q '^run,t_s,distance_m,ok,yaw_rad,offset_m'; then
  ok "calibrate-mount"
else
  bad "calibrate-mount" "$(tail -3 "$work/cal/log.txt")"
fi
# The estimate follows the true yaw (a constant answer fails one of the two).
yaw_est() { sed -n '/"estimate"/,/}/p' "$1/calibration.json" | awk -F': ' '/"yaw_deg"/ { gsub(",", "", $2); print $2 }'; }
if $CEILNAV calibrate-mount --out "$work/cal/pos" --run-length 3 --yaw 0.7 --roll 0.4 --pitch-error 0.8 \
  --seed 2 --quiet >/dev/null 2>&1 &&
  awk -v a="$(yaw_est "$co")" -v b="$(yaw_est "$work/cal/pos")" 'BEGIN { exit !(a < -0.65 && a > -0.75 && b > 0.65 && b < 0.75) }'; then
  ok "calibrate-mount follows the yaw"
else
  bad "calibrate-mount follows the yaw" "$(yaw_est "$co") $(yaw_est "$work/cal/pos")"
fi
if $CEILNAV calibrate-mount --out "$work/cal/mc" --run-length 2 --monte-carlo 2 --quiet >/dev/null 2>&1 &&
  grep -q '"monte_carlo"' "$work/cal/mc/calibration.json" &&
  grep -q '"abs_yaw_error_deg"' "$work/cal/mc/calibration.json"; then
  ok "calibrate-mount monte carlo"
else
  bad "calibrate-mount monte carlo"
fi
expect_error "calibrate-mount bad yaw" "--yaw" "$work/cal/bad1" -- calibrate-mount --out "$work/cal/bad1" --yaw nan
expect_error "calibrate-mount zero runs" "--monte-carlo" "$work/cal/bad2" -- calibrate-mount --out "$work/cal/bad2" --monte-carlo 0
expect_error "calibrate-mount bad backend" "--backend" "$work/cal/bad3" -- calibrate-mount --out "$work/cal/bad3" --backend gpu
expect_error "calibrate-mount short run" "--run-length" "$work/cal/bad4" -- calibrate-mount --out "$work/cal/bad4" --run-length 0.5
expect_error "calibrate-mount heading too large" "--heading" "$work/cal/bad5" -- calibrate-mount --out "$work/cal/bad5" --heading 20

# corridor: the built-in learning drive and guided drives through the edge
# and hough blocks: every output, a model, the goals with --require (pan RMS
# <= 0.3 deg, lateral shift RMS <= 2 cm, 95 % of the guided frames ok); a frame folder with
# fewer frames than the learning drive needs, a missing or bad scene file
# and a bad angle are refused with a message and no output.
cor=$work/corridor
if $CEILNAV corridor --out "$cor" --quiet --require >/dev/null 2>"$work/corridor.err" &&
  [ -s "$cor/corridor.csv" ] && [ -s "$cor/model.json" ] && [ -s "$cor/summary.json" ] &&
  ls "$cor"/overlay_*.png >/dev/null 2>&1 && grep -q '"goals_met": true' "$cor/summary.json" &&
  ! grep -q '"model_lines": 0' "$cor/summary.json"; then
  ok "corridor"
else
  bad "corridor" "$(cat "$work/corridor.err" "$cor/summary.json" 2>/dev/null | tail -5)"
fi
mkdir -p "$work/cor_frames"
cp "$cor"/overlay_*.png "$work/cor_frames/" 2>/dev/null
# drive --corridor: the closed corridor loop over 12 m (capture from 0.2 m off
# the path; the lateral goal is over 50 m, sim/tests/corridor_drive_test.cpp
# checks the capture): its outputs;
# tape-course options, a drive past the corridor's far end and a missing
# corridor file are refused with a message and no output.
cd_out=$work/corridor_drive
if $CEILNAV drive --corridor default --length 12 --out "$cd_out" --quiet \
  >/dev/null 2>"$work/corridor_drive.err" &&
  [ -s "$cd_out/corridor_drive.csv" ] && [ -s "$cd_out/model.json" ] && [ -s "$cd_out/drive.png" ] &&
  grep -q '"completed": true' "$cd_out/summary.json" &&
  [ "$(wc -l <"$cd_out/corridor_drive.csv")" -gt 100 ]; then
  ok "drive --corridor"
else
  bad "drive --corridor" "$(cat "$work/corridor_drive.err" "$cd_out/summary.json" 2>/dev/null | tail -5)"
fi
expect_error "drive --corridor with --backend" "backend" "$work/cd_bad1" -- drive --corridor default --out "$work/cd_bad1" --backend model
expect_error "drive --corridor past the end" "far end" "$work/cd_bad2" -- drive --corridor default --out "$work/cd_bad2" --length 80
expect_error "drive --corridor missing file" "corridor" "$work/cd_bad3" -- drive --corridor "$work/nope.yaml" --out "$work/cd_bad3"
expect_error "drive --corridor with --course" "course" "$work/cd_bad4" -- drive --corridor default --course "$work/nope.yaml" --out "$work/cd_bad4"
# Two held-out corridors (docs/corridor.md, "Held-out corridors"), the two
# that lost most frames: the goals with --require.
for s in study_doors study_narrow_1p8; do
  if $CEILNAV corridor --scene "$here/../../examples/corridor/$s.yaml" --out "$work/corridor_$s" \
    --quiet --require --overlays 0 >/dev/null 2>"$work/corridor_$s.err"; then
    ok "corridor $s"
  else
    bad "corridor $s" "$(cat "$work/corridor_$s.err" "$work/corridor_$s/summary.json" 2>/dev/null | tail -8)"
  fi
done
# Frames without a corridor (the tape renders of the start of this script):
# no model, every frame not_found, no model.json; exit 0 (the answer is "not
# found", not an error).
if $CEILNAV corridor --frames "$frames" --learn-frames 3 --out "$work/corridor_none" --quiet \
  >/dev/null 2>"$work/corridor_none.err" &&
  [ ! -e "$work/corridor_none/model.json" ] && grep -q '"no_model"' "$work/corridor_none/summary.json" &&
  [ "$(grep -c ',not_found,' "$work/corridor_none/corridor.csv")" -eq 6 ]; then
  ok "corridor without a corridor"
else
  bad "corridor without a corridor" "$(cat "$work/corridor_none.err" "$work/corridor_none/corridor.csv" 2>/dev/null | tail -8)"
fi
expect_error "corridor too few frames" "learn-frames" "$work/corridor_bad1" -- corridor --out "$work/corridor_bad1" --frames "$work/cor_frames" --learn-frames 17
expect_error "corridor missing scene" "scene" "$work/corridor_bad2" -- corridor --out "$work/corridor_bad2" --scene "$work/nope.yaml"
expect_error "corridor bad tilt" "--tilt" "$work/corridor_bad3" -- corridor --out "$work/corridor_bad3" --tilt nan
printf 'format: ceilnav_corridor\nversion: 1\nbogus_key: 1\n' >"$work/bad_corridor.yaml"
expect_error "corridor bad scene" "bogus_key" "$work/corridor_bad4" -- corridor --out "$work/corridor_bad4" --scene "$work/bad_corridor.yaml"

# homing: the built-in office ceiling's three sites recorded, one loop of the
# triangle race with the goals required; then the same race on the recorded
# map (--map). A ceiling file with an unknown key or a single site, a bad
# capture site and a broken map are refused with a message and no output.
ho=$work/homing
if $CEILNAV homing --loops 1 --out "$ho" --quiet --require >/dev/null 2>"$work/homing.err" &&
  [ -s "$ho/homing_race.csv" ] && [ -s "$ho/homing_frames.csv" ] && [ -s "$ho/odometry_race.csv" ] &&
  [ -s "$ho/map/map.json" ] && [ -s "$ho/map/site_2.png" ] && [ -s "$ho/race.png" ] &&
  [ -s "$ho/ceiling.yaml" ] && grep -q '"goals_met": true' "$ho/summary.json" &&
  [ "$(grep -c ',homed,' "$ho/homing_race.csv")" -eq 3 ]; then
  ok "homing"
else
  bad "homing" "$(cat "$work/homing.err" "$ho/summary.json" 2>/dev/null | tail -8)"
fi
if $CEILNAV homing --loops 1 --map "$ho/map/map.json" --ceiling "$ho/ceiling.yaml" --out "$work/homing_map" \
  --quiet --require --no-plot >/dev/null 2>"$work/homing_map.err" && [ ! -e "$work/homing_map/map" ] &&
  grep -q '"goals_met": true' "$work/homing_map/summary.json"; then
  ok "homing --map"
else
  bad "homing --map" "$(cat "$work/homing_map.err" "$work/homing_map/summary.json" 2>/dev/null | tail -8)"
fi
# A study ceiling (docs/homing.md, "Held-out ceilings"): the hall at 3 m.
if $CEILNAV homing --loops 1 --ceiling "$here/../../examples/homing/study_hall.yaml" --out "$work/homing_hall" \
  --quiet --require --no-plot >/dev/null 2>"$work/homing_hall.err"; then
  ok "homing study_hall"
else
  bad "homing study_hall" "$(cat "$work/homing_hall.err" "$work/homing_hall/summary.json" 2>/dev/null | tail -8)"
fi
printf 'format: ceilnav_ceiling\nversion: 1\nheight_m: 3\nbogus_key: 1\n' >"$work/bad_ceiling.yaml"
expect_error "homing bad ceiling" "bogus_key" "$work/homing_bad1" -- homing --out "$work/homing_bad1" --ceiling "$work/bad_ceiling.yaml"
printf 'format: ceilnav_ceiling\nversion: 1\nheight_m: 3\nsites:\n  - {name: a, x_m: 0, y_m: 0, yaw_deg: 0}\n' >"$work/one_site.yaml"
expect_error "homing one site" "two or more sites" "$work/homing_bad2" -- homing --out "$work/homing_bad2" --ceiling "$work/one_site.yaml"
expect_error "homing capture site" "capture-site" "$work/homing_bad3" -- homing --out "$work/homing_bad3" --capture --capture-site 9
expect_error "homing capture radii" "capture-radii" "$work/homing_bad6" -- homing --out "$work/homing_bad6" --capture --capture-radii 1,0.5
expect_error "homing backend" "backend" "$work/homing_bad7" -- homing --out "$work/homing_bad7" --backend gpu
printf '{"format": "ceilnav_site_map", "version": 1, "sites": [], "paths": [{"from": 0}]}' >"$work/bad_map.json"
expect_error "homing bad map" "map" "$work/homing_bad4" -- homing --out "$work/homing_bad4" --map "$work/bad_map.json"
expect_error "homing missing ceiling" "ceiling" "$work/homing_bad5" -- homing --out "$work/homing_bad5" --ceiling "$work/nope.yaml"

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
