#!/usr/bin/env bash
# Renders the pictures of scenes/README.md's `time`, `panes`, `variants`, `camera.frame` and `ghost`
# sections: bash docs/views/make.sh [path/to/simreel]   (from the repository root; needs the ffmpeg
# command for the film strip)
set -euo pipefail
bin=${1:-build/simreel}
out=docs/views
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# time: a ball crossing at 1 m/s, played at speed 1 to t = 1 s, held there for 1 s of video, then
# at a quarter speed: a film strip of the video every 0.5 s.
cat > "$tmp/time.yaml" <<YAML
simulation: { duration: 2.0, gravity: [0, 0, 0] }
video: { width: 256, height: 144, fps: 30 }
render: { shadows: false }
camera: { position: [0, -4.2, 0.4], look_at: [0, 0, 0.2], fov: 40 }
time:
  segments: [{ until: 1.0, speed: 1 }]
  speed: 0.25
  hold: { at: 1.0, for: 1.0 }
bodies:
  - { name: ball, position: [-1.2, 0, 0.2], linear_velocity: [1, 0, 0], color: [0.85, 0.35, 0.15],
      colliders: [{ shape: sphere, radius: 0.15 }] }
overlays: { text_size: 1.3, hud: ["video {video_t:.1f} s", "t = {t:.3f} s"] }
YAML
"$bin" render "$tmp/time.yaml" --frames 0,15,30,45,60,75,90,105 --frames-dir "$tmp/f" --no-video --quiet
ffmpeg -loglevel error -y $(for k in 00000 00015 00030 00045 00060 00075 00090 00105; do echo -i "$tmp/f/frame_$k.png"; done) \
  -filter_complex "[0][1][2][3]hstack=4[a];[4][5][6][7]hstack=4[b];[a][b]vstack" "$out/time.png"

# panes and variants: scenes/seed_vs_default.yaml at t = 3 s (past the first flip), half size.
"$bin" render scenes/seed_vs_default.yaml --at 3.0 --width 640 --height 360 -o "$out/variants.png" --quiet
# camera.frame: scenes/dzhanibekov_views.yaml just after the flip.
"$bin" render scenes/dzhanibekov_views.yaml --at 3.0 --width 640 --height 360 -o "$out/panes.png" --quiet

# ghost: a T-handle on the article's integrator (wrong: it never flips) with its ghost, the exact
# motion, which has flipped.
cat > "$tmp/ghost.yaml" <<YAML
simulation: { duration: 4, gravity: [0, 0, 0], integrator: seed }
video: { width: 320, height: 180 }
camera: { position: [1.6, -1.6, 1.0], look_at: [0, -0.15, 0], fov: 40 }
bodies:
  - name: handle
    angular_velocity: [0.02, 6.0, 0.02]
    color: [0.85, 0.35, 0.15]
    ghost: true
    colliders:
      - { shape: cylinder, radius: 0.07, height: 1.0, density: 7800, orientation: [0.7071067811865476, 0, 0.7071067811865476, 0] }
      - { shape: cylinder, radius: 0.05, height: 0.7, density: 7800, position: [0, -0.35, 0], orientation: [0.7071067811865476, -0.7071067811865476, 0, 0] }
overlays: { text_size: 1.2, hud: ["seed integrator; translucent: exact"] }
YAML
"$bin" render "$tmp/ghost.yaml" --at 2.6 -o "$out/ghost.png" --quiet
