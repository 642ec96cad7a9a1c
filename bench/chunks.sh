#!/usr/bin/env bash
# Chunked rendering: CPU seconds of a straight render against the same clip in N = 1, 2, 4 chunks,
# each chunk simulating from t = 0 ("replay") or resuming from `plan --checkpoints` ("checkpoints").
# This 2-core machine cannot show the wall-clock gain of N machines, so every process runs alone, one
# after another, and the figures are CPU seconds (user + sys) per process; the makespan on N idle
# machines is then modelled from them: the slowest chunk, plus the plan before and the join after.
#
#   bash bench/chunks.sh [BUILD_DIR] > bench/results/chunks.csv      # ~10 min CPU
#
# Scenes: scenes/pile.yaml at 1920x1080 for 16 s (render-bound: 27 bodies) and a pile of 800 boxes
# at 640x360 for 8 s written here (physics-bound). Both are 8 keyframe intervals long exactly (480
# and 240 frames at 30 fps, a keyframe every 60), so 1, 2 and 4 chunks are even: chunks are whole
# intervals, and a clip one frame longer would leave the last chunk one frame. Also printed: S, the fixed cost of a process (load, GL
# context, the first frame: `render --at 0`), P, the physics (`simulate`), and R = straight - P - S.
set -euo pipefail
BUILD=${1:-build}
SIMREEL=$(realpath "$BUILD/simreel")
cd "$(dirname "$0")/.."
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# 800 boxes in a loose 10 x 10 x 8 lattice dropped on the ground: contacts on every body for most of
# the 8 s.
python3 - "$TMP/heavy.yaml" <<'EOF'
import sys
rows = ["# 800 boxes dropped in a lattice (bench/chunks.sh)",
        "simulation: { duration: 7.95, timestep: 0.004166666666666667 }",
        "video: { width: 640, height: 360, fps: 30 }",
        "camera: { position: [9, -9, 6], look_at: [0, 0, 1.5], up: [0, 0, 1], fov: 45 }",
        "ground: { size: 20 }", "bodies:"]
for k in range(8):
    for j in range(10):
        for i in range(10):
            rows.append("  - { name: b%d_%d_%d, position: [%.2f, %.2f, %.2f], color: [0.%d, 0.5, 0.7], "
                        "colliders: [ { shape: box, size: [0.3, 0.3, 0.3], density: 500 } ] }"
                        % (i, j, k, (i - 4.5) * 0.45, (j - 4.5) * 0.45 + 0.05 * k, 0.3 + 0.45 * k, 2 + k))
open(sys.argv[1], "w").write("\n".join(rows) + "\n")
EOF

TIMEFORMAT='%U %S'
# CPU seconds (user + sys) of one command; its output thrown away.
cpu() {
  local t
  t=$( { time "$@" >/dev/null 2>&1; } 2>&1 | tail -1)
  awk -v u="${t% *}" -v s="${t#* }" 'BEGIN { printf "%.3f", u + s }'
}

echo "scene,size,mode,chunks,plan_cpu_s,chunk_cpu_max_s,chunk_cpu_sum_s,join_cpu_s,total_cpu_s,straight_cpu_s,S_s,P_s,R_s,makespan_s,speedup,cpu_ratio"
run_scene() {
  local name=$1 scene=$2 w=$3 h=$4
  local size="--width $w --height $h ${5:-}"
  local straight S P R
  straight=$(cpu "$SIMREEL" render "$scene" $size --quiet -o "$TMP/straight.mp4")
  S=$(cpu "$SIMREEL" render "$scene" $size --quiet --at 0 -o "$TMP/first.png")
  P=$(cpu "$SIMREEL" simulate "$scene" ${5:-} --quiet)
  R=$(awk -v a="$straight" -v p="$P" -v s="$S" 'BEGIN { printf "%.3f", a - p - s }')
  for mode in replay checkpoints; do
    for n in 1 2 4; do
      rm -rf "$TMP/parts" "$TMP/ck"
      local plan=0 ck=""
      if [ $mode = checkpoints ]; then
        plan=$(cpu "$SIMREEL" plan "$scene" $size --chunks $n --quiet --checkpoints "$TMP/ck")
        ck="--checkpoints $TMP/ck"
      fi
      local max=0 sum=0 c
      for ((i = 0; i < n; i++)); do
        c=$(cpu "$SIMREEL" render "$scene" $size --quiet --chunk $i/$n $ck -o "$TMP/parts/")
        max=$(awk -v a="$max" -v b="$c" 'BEGIN { print (b > a) ? b : a }')
        sum=$(awk -v a="$sum" -v b="$c" 'BEGIN { printf "%.3f", a + b }')
      done
      local join
      join=$(cpu "$SIMREEL" join "$TMP/parts" -o "$TMP/joined.mp4" --quiet)
      awk -v name="$name" -v size="${w}x$h" -v mode=$mode -v n=$n -v plan="$plan" -v max="$max" -v sum="$sum" \
        -v join="$join" -v straight="$straight" -v S="$S" -v P="$P" -v R="$R" 'BEGIN {
          total = plan + sum + join; makespan = plan + max + join
          printf "%s,%s,%s,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f\n", name, size, mode, n,
                 plan, max, sum, join, total, straight, S, P, R, makespan, straight / makespan, total / straight }'
    done
  done
}
run_scene pile scenes/pile.yaml 1920 1080 "--duration 15.95"
run_scene heavy800 "$TMP/heavy.yaml" 640 360
