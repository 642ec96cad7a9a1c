#!/usr/bin/env bash
# How far apart compare_images (app/regress/metrics.hpp) finds frames that should be the
# same, and how far apart it finds frames with a small real change. Run from the repository root
# after building simreel and bench_regress_noise:
#
#   bash bench/regress_noise.sh [BUILD_DIR] > bench/results/regress_noise.csv
#
# (~5 min of CPU; 17 min wall on the shared 2-core VM under load.)
#
# kind = noise:   every shipped scene (2 s at 480 x 270) under the 8 llvmpipe settings
#                 LP_NUM_THREADS 1/2 x LP_NATIVE_VECTOR_WIDTH 128/256 x --gl osmesa/egl, plus
#                 --threads 2 (integration threads); all pairs of those 9 renders, frame by frame.
# kind = driver:  the same scene on softpipe (GALLIUM_DRIVER=softpipe: Mesa's other software
#                 rasterizer) against llvmpipe: a stand-in for a different Mesa or GPU, not a
#                 setting simreel check is meant to be used across.
# kind = change:  a small edit of a scene copy against the unedited scene (llvmpipe, 1 thread, 256
#                 bits, osmesa): a body moved 3 mm or 1 cm, a colour changed by 0.02 or 0.05, a
#                 small object removed. f0_* is the first frame (the edit before any dynamics).
# kind = subpixel: the camera moved 1 or 3 mm (the whole picture shifts by a fraction of a pixel).
# kind = jitter:  each scene's frames against copies with every R, G, B byte moved by a random
#                 -K..K (K = 2, 3): the drift the threshold tolerates.
# Rows ending in @720p repeat a few cases at 1280 x 720.
# Each case is measured at the thresholds 0.01, 0.02, 0.03, 0.05 and 0.1 with the default
# max_diff_ratio and max_cluster (frames_failing counts frames failing under those).
set -euo pipefail
B=${1:-build}
SIM=$B/simreel
CMP=$B/bench/bench_regress_noise
TS=${SIMREEL_REGRESS_THRESHOLDS:-0.01,0.02,0.03,0.05,0.1}
W=$(mktemp -d "${TMPDIR:-/tmp}/simreel-regress-noise.XXXXXX")
# SIMREEL_REGRESS_KEEP=1 keeps the frames (in $W, named on stderr) for a closer look.
if [[ -n ${SIMREEL_REGRESS_KEEP:-} ]]; then echo "frames in $W" >&2; else trap 'rm -rf "$W"' EXIT; fi

# render OUT SCENE SIZE [ENV=VALUE...] [-- simreel options...]
render() {
  local out=$1 scene=$2 size=$3
  shift 3
  local envs=() opts=()
  while (($#)); do
    if [[ $1 == -- ]]; then
      shift
      opts=("$@")
      break
    fi
    envs+=("$1")
    shift
  done
  env "${envs[@]}" "$SIM" render "$scene" --frames-dir "$out" --no-video --duration 2 --width "${size%x*}" \
    --height "${size#*x}" --quiet "${opts[@]}" >/dev/null 2>"$W/render.log" || { cat "$W/render.log" >&2; exit 1; }
}

# variant NEW SRC OLD NEW_TEXT: a copy of SRC with the text OLD (exactly once) replaced
variant() {
  python3 - "$@" <<'PY'
import sys
dst, src, old, new = sys.argv[1:5]
s = open(src).read()
assert s.count(old) == 1, f"{src}: {old!r} found {s.count(old)} times"
open(dst, "w").write(s.replace(old, new.replace("\\n", "\n")))
PY
}

ref_env=(LP_NUM_THREADS=1 LP_NATIVE_VECTOR_WIDTH=256)
"$CMP" header

for scene in scenes/*.yaml; do
  name=$(basename "$scene" .yaml)
  dirs=()
  for t in 1 2; do
    for v in 128 256; do
      for gl in osmesa egl; do
        d=$W/$name/t${t}_v${v}_$gl
        render "$d" "$scene" 480x270 LP_NUM_THREADS=$t LP_NATIVE_VECTOR_WIDTH=$v -- --gl $gl
        dirs+=("$d")
      done
    done
  done
  render "$W/$name/sim2" "$scene" 480x270 "${ref_env[@]}" -- --threads 2
  "$CMP" pairs "$name" noise "$TS" "${dirs[@]}" "$W/$name/sim2"
  render "$W/$name/softpipe" "$scene" 480x270 GALLIUM_DRIVER=softpipe
  "$CMP" pairs "$name/softpipe" driver "$TS" "$W/$name/t1_v256_osmesa" "$W/$name/softpipe"
  for k in 2 3; do "$CMP" jitter "$name/jitter $k" "$TS" $k "$W/$name/t1_v256_osmesa"; done
done

# change LABEL KIND SIZE SCENE OLD NEW: the edited copy against the reference render
change() {
  local label=$1 kind=$2 size=$3 scene=$4 name
  name=$(basename "$scene" .yaml)
  local ref=$W/$name/ref_$size
  [[ -d $ref ]] || render "$ref" "$scene" "$size" "${ref_env[@]}"
  mkdir -p "$W/edit"
  local copy=$W/edit/$name.yaml
  variant "$copy" "$scene" "$5" "$6"
  rm -rf "$W/edit/frames"
  render "$W/edit/frames" "$copy" "$size" "${ref_env[@]}"
  local tag=""
  [[ $size == 480x270 ]] || tag="@${size#*x}p"
  "$CMP" pairs "$label$tag" "$kind" "$TS" "$ref" "$W/edit/frames"
}

cases() {
  local s=$1
  change "dominoes/domino14 x+3mm" change "$s" scenes/dominoes.yaml "position: [4.20, 0, 0.25]" "position: [4.203, 0, 0.25]"
  change "dominoes/domino14 x+1cm" change "$s" scenes/dominoes.yaml "position: [4.20, 0, 0.25]" "position: [4.21, 0, 0.25]"
  change "slide_or_tip/tipper y+3mm" change "$s" scenes/slide_or_tip.yaml "position: [-0.888, 0.7, 1.8615]" "position: [-0.888, 0.703, 1.8615]"
  change "slide_or_tip/tipper y+1cm" change "$s" scenes/slide_or_tip.yaml "position: [-0.888, 0.7, 1.8615]" "position: [-0.888, 0.71, 1.8615]"
  change "dominoes/domino2 green+0.02" change "$s" scenes/dominoes.yaml "position: [0.60, 0, 0.25]
    color: [0.85, 0.2, 0.15]" "position: [0.60, 0, 0.25]
    color: [0.85, 0.22, 0.15]"
  change "dominoes/domino2 green+0.05" change "$s" scenes/dominoes.yaml "position: [0.60, 0, 0.25]
    color: [0.85, 0.2, 0.15]" "position: [0.60, 0, 0.25]
    color: [0.85, 0.25, 0.15]"
  change "pile/sphere1 blue-0.02" change "$s" scenes/pile.yaml "position: [-0.791, -0.009, 0.600]
    orientation: [0.870359537, -0.402228054, 0.151857844, 0.240054294]
    color: [0.2, 0.45, 0.8]" "position: [-0.791, -0.009, 0.600]
    orientation: [0.870359537, -0.402228054, 0.151857844, 0.240054294]
    color: [0.2, 0.45, 0.78]"
  change "pile/tetra5 removed" change "$s" scenes/pile.yaml "  - name: tetra5
    position: [0.009, 0.791, 0.600]
    orientation: [0.048066437, -0.429676754, 0.100849833, -0.896045097]
    color: [0.85, 0.45, 0.15]
    colliders:
      - { shape: mesh, file: tetra.off, density: 1500, position: [-0.075, -0.075, -0.075] }
" ""
  change "bowling/red dot removed" change "$s" scenes/bowling.yaml "      - { shape: sphere, radius: 0.025, mass: 0.001, collide: false, color: [0.9, 0.1, 0.1], position: [0.055, -0.055, 0.055] }
" ""
  change "dominoes/camera x+1mm" subpixel "$s" scenes/dominoes.yaml "position: [-1.2, -2.8, 1.4]" "position: [-1.199, -2.8, 1.4]"
  change "dominoes/camera x+3mm" subpixel "$s" scenes/dominoes.yaml "position: [-1.2, -2.8, 1.4]" "position: [-1.197, -2.8, 1.4]"
}
cases 480x270

# 1280 x 720 (the scenes' own size): noise for one llvmpipe pair and softpipe, then the changes.
for scene in scenes/dominoes.yaml scenes/slide_or_tip.yaml; do
  name=$(basename "$scene" .yaml)
  render "$W/$name/ref_1280x720" "$scene" 1280x720 "${ref_env[@]}"
  render "$W/$name/hd_t2_v128_egl" "$scene" 1280x720 LP_NUM_THREADS=2 LP_NATIVE_VECTOR_WIDTH=128 -- --gl egl
  "$CMP" pairs "$name@720p" noise "$TS" "$W/$name/ref_1280x720" "$W/$name/hd_t2_v128_egl"
  render "$W/$name/hd_softpipe" "$scene" 1280x720 GALLIUM_DRIVER=softpipe
  "$CMP" pairs "$name/softpipe@720p" driver "$TS" "$W/$name/ref_1280x720" "$W/$name/hd_softpipe"
done
cases 1280x720
