#!/usr/bin/env bash
# What `simreel check` costs: a 10 s scene checked at five moments should cost about
# the simulation plus five frames, not a full render. Times, in one run and interleaved (this VM
# drifts), the minimum of 3 runs of:
#   simulate  the physics alone
#   check     the physics + 5 frames drawn and compared (480x270, the golden size)
#   render_png    the full render at the same size, PNG frames only (no encoder)
#   render_mp4    the full render at the scene's own size to H.264
# and one frame at 480x270 (render --at) for the per-frame figure. CSV on stdout.
# Usage: bench/check_cost.sh [SIMREEL] [SCENE]   (defaults: build/simreel scenes/symmetric_top.yaml)
set -euo pipefail
bin=${1:-build/simreel}
scene=${2:-scenes/symmetric_top.yaml}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" check "$scene" --goldens "$tmp/g" --update missing --quiet > /dev/null
now() { date +%s.%N; }
declare -A best
run() {  # name, command...
  local name=$1; shift
  local t0 t1
  t0=$(now); "$@" > /dev/null 2>&1; t1=$(now)
  local t; t=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }')
  if [ -z "${best[$name]:-}" ] || awk -v t="$t" -v b="${best[$name]}" 'BEGIN { exit !(t < b) }'; then best[$name]=$t; fi
}
for r in 1 2 3; do
  run simulate "$bin" simulate "$scene" --quiet
  run check "$bin" check "$scene" --goldens "$tmp/g" --update none --quiet
  rm -rf "$tmp/png"
  run render_png "$bin" render "$scene" --width 480 --height 270 --no-video --frames-dir "$tmp/png" --quiet
  run render_mp4 "$bin" render "$scene" -o "$tmp/v.mp4" --quiet
  run one_frame "$bin" render "$scene" --width 480 --height 270 --at 0 -o "$tmp/one.png" --quiet
done
frames=$(ls "$tmp/png" | wc -l)
echo "case,seconds,note"
echo "simulate,${best[simulate]},physics only"
echo "check_5_frames,${best[check]},physics + 5 frames drawn at 480x270 + compared"
echo "render_png_all,${best[render_png]},$frames frames at 480x270 to PNG"
echo "render_mp4_all,${best[render_mp4]},the scene's own size to H.264"
echo "one_frame_at_0,${best[one_frame]},render --at 0 at 480x270: start-up + one frame"
