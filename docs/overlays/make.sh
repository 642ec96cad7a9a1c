#!/usr/bin/env bash
# Renders the overlay pictures of scenes/README.md (one per `show:` item, and the HUD) from small
# scenes written here: bash docs/overlays/make.sh [path/to/simreel]   (from the repository root)
set -euo pipefail
bin=${1:-build/simreel}
out=docs/overlays
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# A T-handle tumbling in zero gravity (as scenes/dzhanibekov.yaml), seen from the side.
handle() {  # $1: show items (YAML flow list), $2: extra top-level YAML
  cat <<YAML
simulation: { duration: 4, gravity: [0, 0, 0] }
video: { width: 320, height: 180 }
camera: { position: [1.35, -1.35, 0.8], look_at: [0, -0.15, 0], fov: 40 }
bodies:
  - name: handle
    angular_velocity: [0.4, 6.0, 0.4]
    color: [0.85, 0.35, 0.15]
    show: $1
    colliders:
      - { shape: cylinder, radius: 0.07, height: 1.0, density: 7800, orientation: [0.7071067811865476, 0, 0.7071067811865476, 0] }
      - { shape: cylinder, radius: 0.05, height: 0.7, density: 7800, position: [0, -0.35, 0], orientation: [0.7071067811865476, -0.7071067811865476, 0, 0] }
$2
YAML
}
# A capsule thrown over a ground (as scenes/projectile.yaml).
thrown() {  # $1: show items
  cat <<YAML
simulation: { duration: 1.3 }
video: { width: 320, height: 180 }
camera: { position: [1.3, -4.5, 1.6], look_at: [1.3, 0, 1.5], fov: 45 }
render: { ground: true }
bodies:
  - name: capsule
    position: [0, 0, 0.3]
    linear_velocity: [2.5, 0, 6]
    angular_velocity: [0, 5, 0]
    color: [0.2, 0.45, 0.8]
    show: $1
    colliders: [ { shape: capsule, radius: 0.15, height: 0.8, density: 500, orientation: [0.7071067811865476, 0.7071067811865476, 0, 0] } ]
YAML
}

render() {  # $1: name, $2: time
  "$bin" render "$tmp/$1.yaml" --quiet --at "$2" -o "$out/$1.png" > /dev/null
}

handle "[ { axes: { xray: true, scale: 0.45 } } ]" "" > "$tmp/axes.yaml" && render axes 0.2
handle "[ { angular_velocity: { xray: true } } ]" "" > "$tmp/angular_velocity.yaml" && render angular_velocity 2.6
handle "[ { angular_momentum: { xray: true } } ]" "" > "$tmp/angular_momentum.yaml" && render angular_momentum 2.6
handle "[ { center_of_mass: { xray: 0.8, color: [0.9, 0.6, 0] } }, { axes: { opacity: 0.5 } } ]" "" > "$tmp/center_of_mass.yaml" &&
  render center_of_mass 1.0
handle "[ inertia_box ]" "" > "$tmp/inertia_box.yaml" && render inertia_box 1.0
handle "[ inertia_ellipsoid ]" "" > "$tmp/inertia_ellipsoid.yaml" && render inertia_ellipsoid 1.0
cat > "$tmp/cones.yaml" <<YAML
simulation: { duration: 2, gravity: [0, 0, 0] }
video: { width: 320, height: 180 }
camera: { position: [2.0, -2.0, 1.5], look_at: [0, 0, 0.3], fov: 40 }
bodies:
  - name: disc
    orientation: [0.9659258262890683, 0.25881904510252074, 0, 0]
    angular_velocity: [0, 0, 4]
    color: [0.2, 0.6, 0.35]
    show: [ { cones: { scale: 0.8 } }, { angular_velocity: { scale: 0.2 } } ]
    colliders: [ { shape: cylinder, radius: 0.6, height: 0.08 } ]
YAML
render cones 1.0
cat > "$tmp/poinsot.yaml" <<YAML
simulation: { duration: 6, gravity: [0, 0, 0] }
video: { width: 320, height: 180 }
camera: { position: [2.8, -3.6, 2.4], look_at: [0, 0, 0.25], fov: 40 }
bodies:
  - name: brick
    angular_velocity: [0.9, 0.7, 3.0]
    color: [0.75, 0.7, 0.6]
    show: [ poinsot ]
    colliders: [ { shape: box, size: [0.8, 0.5, 0.25], density: 600 } ]
YAML
render poinsot 5.0
thrown "[ { velocity: { scale: 0.15 } }, { trail: { length: 0.3, width: 2 } } ]" > "$tmp/velocity.yaml" && render velocity 0.3
thrown "[ { trail: { point: [0, 0, 0.3], length: 1.0 } }, { trail: { point: [0, 0, 0], length: 1.0, color: [0.8, 0.1, 0.1] } } ]" \
  > "$tmp/trail.yaml" && render trail 1.0
handle "[ angular_momentum, angular_velocity ]" '
overlays:
  title: "Title"
  hud: ["t = {t:.2f} s", "ω₂ = {omega_body.y:+.2f} rad/s", "E/E₀ − 1 = {E_drift:+.1e}"]' > "$tmp/hud.yaml" && render hud 2.6
# Forces: a box pushed off-centre by a world force and turned by a torque, on a spring to an
# anchor, under drag, its weight drawn.
cat > "$tmp/forces.yaml" <<YAML
simulation: { duration: 2 }
video: { width: 320, height: 180 }
camera: { position: [0.7, -2.6, 1.3], look_at: [0.0, 0, 1.0], fov: 40 }
bodies:
  - name: box
    position: [0, 0, 0.9]
    color: [0.75, 0.7, 0.6]
    linear_velocity: [0, 0, -1.2]
    show: [ { forces: { gravity: true } } ]
    colliders: [ { shape: box, size: [0.4, 0.3, 0.3], density: 300 } ]
forces:
  - { type: force, body: box, vector: [30, 0, 0], at: [0.2, 0, -0.1] }
  - { type: torque, body: box, vector: [2, -1, 1.5] }
  - { type: spring, body: box, point: [0, 0, 0.15], anchor: [-0.8, 0, 1.9], stiffness: 60, rest_length: 0.5 }
  - { type: drag, body: box, linear: 8 }
YAML
render forces 0.05
# Contacts: a box resting on a larger one on the ground, a ball against them.
cat > "$tmp/contacts.yaml" <<YAML
simulation: { duration: 1.5, contacts: { rolling_resistance: 0.2 } }
video: { width: 320, height: 180 }
camera: { position: [1.05, -1.35, 0.8], look_at: [0.1, 0, 0.22], fov: 40 }
ground: { height: 0, tile: 0.5 }
bodies:
  - { name: low, position: [0, 0, 0.15], color: [0.8, 0.25, 0.2], show: [ contacts ],
      colliders: [ { shape: box, size: [0.6, 0.5, 0.3], density: 500 } ] }
  - { name: top, position: [0.05, 0, 0.42], color: [0.6, 0.35, 0.7], show: [ contacts ],
      colliders: [ { shape: box, size: [0.3, 0.3, 0.24], density: 800 } ] }
  - { name: ball, position: [0.45, -0.1, 0.15], color: [0.2, 0.45, 0.8], show: [ contacts ],
      colliders: [ { shape: sphere, radius: 0.15, density: 1000 } ] }
YAML
render contacts 1.2
# Joints: a double pendulum (as scenes/double_pendulum.yaml) whose bars show their joints, the elbow
# with limits (its range an arc, fixed in the upper bar, the angle a needle), a cart sliding down a
# rail with limits (its range a bar), and a bob on a universal joint (both axes drawn).
cat > "$tmp/joints.yaml" <<YAML
simulation: { duration: 2 }
video: { width: 320, height: 180 }
camera: { position: [1.45, -1.9, 2.45], look_at: [0.85, 0, 1.78], fov: 40 }
bodies:
  - { name: upper, position: [0.3, 0, 2.0], color: [0.85, 0.35, 0.2], show: [ { joints: { scale: 0.3 } } ],
      colliders: [ { shape: box, size: [0.6, 0.05, 0.03], density: 7850 } ] }
  - { name: lower, position: [0.9, 0, 2.0], color: [0.2, 0.45, 0.85], show: [ { joints: { scale: 0.3 } } ],
      colliders: [ { shape: box, size: [0.6, 0.05, 0.03], density: 7850 } ] }
  - { name: bob, position: [1.7, 0.10565, 1.77342], euler: [25, 0, 0], angular_velocity: [0, 0, 2],
      color: [0.3, 0.65, 0.35], show: [ { joints: { scale: 0.3 } } ],
      colliders: [ { shape: capsule, radius: 0.035, height: 0.5, density: 2000 } ] }
  - { name: cart, position: [1.05, 0, 1.5], color: [0.75, 0.7, 0.6], show: [ { joints: { scale: 0.3 } } ],
      colliders: [ { shape: box, size: [0.12, 0.08, 0.07], density: 500 } ] }
joints:
  - { name: shoulder, type: revolute, bodies: [world, upper], anchor: [0, 0, 2.0], axis: [0, 1, 0] }
  - { name: elbow, type: revolute, bodies: [upper, lower], anchor: [0.6, 0, 2.0], axis: [0, 1, 0], limits: [-1.2, 2.0] }
  - { name: cardan, type: universal, bodies: [world, bob], anchor: [1.7, 0, 2.0], axis: [0, 0, 1], axis2: [1, 0, 0] }
  - { name: rail, type: prismatic, bodies: [world, cart], anchor: [1.05, 0, 1.5], axis: [0.95, 0, -0.31], limits: [-0.2, 0.35] }
YAML
render joints 0.4
# Joint forces: a rod set slanted on a vertical shaft and spun, a rotor out of balance. Through its
# hinge the shaft holds it up (the force: its weight, upwards) and turns its angular momentum round
# (the torque dL/dt = omega x L, across the shaft, turning with the rod).
cat > "$tmp/joint_forces.yaml" <<YAML
simulation: { duration: 1 }
video: { width: 320, height: 180 }
camera: { position: [0.95, -1.25, 1.45], look_at: [-0.08, 0, 1.12], fov: 40 }
bodies:
  - { name: rotor, position: [0, 0, 1.0], euler: [30, 0, 0], angular_velocity: [0, 0, 6], color: [0.3, 0.65, 0.35],
      show: [ joints, { joint_forces: { scale: 0.013, torque_scale: 0.15 } } ],
      colliders: [ { shape: capsule, radius: 0.03, height: 0.8, density: 2000 } ] }
joints:
  - { name: shaft, type: revolute, bodies: [world, rotor], anchor: [0, 0, 1.0], axis: [0, 0, 1] }
YAML
render joint_forces 0.25
# The 2D layer: a caption, a label, a legend, an inset plot, TeX in every text.
handle_at() {  # $1: width, $2: height, $3: show items, $4: overlays (YAML)
  handle "$3" "$4" | sed -e "s/width: 320, height: 180/width: $1, height: $2/" \
    -e "s/position: \[1.35, -1.35, 0.8\], look_at: \[0, -0.15, 0\]/position: [2.3, -2.3, 1.3], look_at: [0.45, 0.1, -0.35]/"
}
handle_at 640 360 "[ angular_momentum, angular_velocity, { trail: { point: [0, -0.7, 0], length: 1.0 } } ]" '
overlays:
  title: "The Dzhanibekov effect: \\vec{L} stands still"
  captions: [ { text: "the stem flips: \\omega_2 \\to -\\omega_2", from: 2, to: 4 } ]
  labels: [ { body: handle, text: "I_1 < I_2 < I_3" } ]
  legend: { corner: bottom_left }
  plots:
    - quantities: [omega_body.x, omega_body.y, omega_body.z]
      rect: [0.57, 0.15, 0.41, 0.42]
      title: "\\omega on e_1 e_2 e_3"' > "$tmp/screen.yaml" && render screen 2.6
# TeX in text: subscripts, superscripts, accents and symbols, large.
cat > "$tmp/tex.yaml" <<'YAML'
simulation: { duration: 1, gravity: [0, 0, 0] }
video: { width: 640, height: 200 }
bodies: [ { name: b, colliders: [ { shape: sphere, radius: 0.1 } ] } ]
camera: { position: [0, -5, 0], look_at: [0, 0, 3] }
overlays:
  text_size: 4
  hud: ['\vec{L} = I\vec\omega,  \omega \cdot L,  \dot\theta_1,  r^2,  I_{xx}', "plain: omega_body E_drift"]
YAML
render tex 0.5
# A title wider than the frame is set smaller.
handle "[ axes ]" '
overlays:
  title: "A title much wider than this small frame is set smaller instead of cut"' > "$tmp/title.yaml" && render title 0.5
# The demos of expressions, systems, snapshots, placement and overlaid variants, at 640 x 360.
demo() {  # $1: scene, $2: picture name, $3: time
  "$bin" render "scenes/$1.yaml" --quiet --at "$3" --width 640 --height 360 -o "$out/$2.png" > /dev/null
}
demo momentum system 1.8
demo ramp_race place 1.2
demo chaos_overlay variants_overlay 11
ls -l "$out"/*.png
