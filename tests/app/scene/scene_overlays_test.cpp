// Parsing of the teaching overlays: bodies' `show:` items and the `overlays:` block.
// The item names and their form are a contract; every mistake names the file, line and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

std::string write_scene(const std::string& name, const std::string& text) {
  const std::filesystem::path p = test::scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::string& text) {
  try {
    load_scene(write_scene("bad_overlay.yaml", text));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "scene was accepted:\n" << text;
  return "";
}

const char* kHead =
    "simulation: { duration: 2 }\nbodies:\n  - name: handle\n"  // a 3 s trail is fine in 2 s
    "    colliders: [ { shape: box, size: [1, 2, 3], density: 10 } ]\n";

// The contract's example, word for word: its item names and forms must keep loading.
TEST(SceneOverlays, TheContractExampleLoads) {
  const Scene s = load_scene(write_scene(
      "contract.yaml",
      std::string(kHead) +
          "    show:\n"
          "      - axes\n"
          "      - angular_momentum                                    # defaults\n"
          "      - { angular_velocity: { color: [1, 0, 1], scale: 0.2 } }   # scale: m per rad/s\n"
          "      - { trail: { point: [0.5, 0, 0], frame: body, length: 3.0 } }\n"
          "overlays:\n"
          "  hud: [\"t = {t:.2f} s\"]\n"));
  ASSERT_EQ(s.overlays.show.size(), 1u);
  const auto& items = s.overlays.show[0];
  ASSERT_EQ(items.size(), 4u);
  EXPECT_EQ(items[0].kind, ShowKind::axes);
  EXPECT_EQ(items[1].kind, ShowKind::angular_momentum);
  EXPECT_FALSE(items[1].scale.has_value());
  EXPECT_EQ(items[2].kind, ShowKind::angular_velocity);
  EXPECT_EQ(*items[2].scale, 0.2);
  EXPECT_EQ((*items[2].color)[1], 0.0f);
  EXPECT_EQ(items[3].kind, ShowKind::trail);
  EXPECT_EQ(items[3].point, Vec3(0.5, 0, 0));
  EXPECT_FALSE(items[3].point_in_world);
  EXPECT_EQ(items[3].length, 3.0);
  ASSERT_EQ(s.overlays.hud.size(), 1u);
  const HudLine& h = s.overlays.hud[0];
  EXPECT_EQ(h.text, (std::vector<std::string>{"t = ", " s"}));
  ASSERT_EQ(h.fields.size(), 1u);
  EXPECT_EQ(h.fields[0].name, "t");
  EXPECT_EQ(h.fields[0].printf, "%.2f");
  EXPECT_TRUE(s.overlays.any());
}

TEST(SceneOverlays, HudFieldsBodiesComponentsAndNorms) {
  const Scene s = load_scene(
      write_scene("hud.yaml", std::string(kHead) + "overlays:\n  title: Spin\n  text_size: 1.5\n"
                                                   "  hud:\n    corner: bottom_right\n    lines: [\"{{ "
                                                   "{handle.omega.y:+8.3e} }} {|L|} {omega} {frame}\"]\n"));
  const HudLine& h = s.overlays.hud[0];
  ASSERT_EQ(h.fields.size(), 4u);
  EXPECT_EQ(h.text[0], "{ ");
  EXPECT_EQ(h.fields[0].body, 0);
  EXPECT_EQ(h.fields[0].component, 1);
  EXPECT_EQ(h.fields[0].printf, "%+8.3e");
  EXPECT_EQ(h.text[1], " } ");
  EXPECT_TRUE(h.fields[1].norm);
  EXPECT_EQ(h.fields[1].name, "L");
  EXPECT_EQ(h.fields[2].component, -1);
  EXPECT_EQ(h.fields[3].printf, "%ld");
  EXPECT_EQ(s.overlays.hud_corner, "bottom_right");
  EXPECT_EQ(s.overlays.title, "Spin");
  EXPECT_EQ(s.overlays.text_size, 1.5);
}

TEST(SceneOverlays, TiltAndPrecessionAreNumbersOfABody) {
  const std::string hud = std::string(kHead) + "overlays: { hud: [\"";
  EXPECT_NE(error_of(hud + "{handle.tilt.x}\"] }\n").find("'tilt' is a number: no component or |...|"),
            std::string::npos);
  EXPECT_NE(error_of(hud + "{precesion}\"] }\n").find("did you mean 'precession'?"), std::string::npos);
  const Scene s = load_scene(write_scene("tilt.yaml", hud + "{tilt:.1f} {handle.precession}\"] }\n"));
  ASSERT_EQ(s.overlays.hud[0].fields.size(), 2u);
  EXPECT_EQ(s.overlays.hud[0].fields[0].body, 0);
  EXPECT_EQ(s.overlays.hud[0].fields[1].name, "precession");
}

TEST(SceneOverlays, MistakesNameFileLineAndKey) {
  const std::string show = std::string(kHead) + "    show:\n";
  EXPECT_NE(error_of(show + "      - angular_velocty\n")
                .find("bad_overlay.yaml:6:9: bodies[0].show[0]: unknown item 'angular_velocty'; did you mean "
                      "'angular_velocity'?"),
            std::string::npos)
      << error_of(show + "      - angular_velocty\n");
  EXPECT_NE(
      error_of(show + "      - { trail: { lenght: 2 } }\n")
          .find("bad_overlay.yaml:6:20: bodies[0].show[0].trail.lenght: unknown key 'lenght'; did you mean "
                "'length'?"),
      std::string::npos)
      << error_of(show + "      - { trail: { lenght: 2 } }\n");
  EXPECT_NE(error_of(show + "      - { trail: { frame: space } }\n")
                .find("bodies[0].show[0].trail.frame: expected body"),
            std::string::npos);
  EXPECT_NE(error_of(show + "      - { velocity: { scale: -1 } }\n")
                .find("bodies[0].show[0].velocity.scale: must lie in"),
            std::string::npos);
  EXPECT_NE(error_of(show + "      - { axes: { color: [1, 0, 0] } }\n").find("unknown key 'color'"),
            std::string::npos);
  EXPECT_NE(error_of(show + "      - 3\n").find("unknown item '3'"), std::string::npos);
  EXPECT_NE(
      error_of(std::string(kHead) + "overlays:\n  hud: [\"{omgea:.2f}\"]\n")
          .find(
              "bad_overlay.yaml:6:9: overlays.hud[0]: '{omgea:.2f}': unknown quantity 'omgea'; did you mean "
              "'omega'?"),
      std::string::npos)
      << error_of(std::string(kHead) + "overlays:\n  hud: [\"{omgea:.2f}\"]\n");
  EXPECT_NE(error_of(std::string(kHead) + "overlays:\n  hud: [\"{t:.2q}\"]\n").find("format '.2q'"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "overlays:\n  hud: [\"{hanlde.omega}\"]\n")
                .find("no body is named 'hanlde'; did you mean 'handle'?"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "overlays:\n  hud: [\"{t\"]\n").find("without its '}'"),
            std::string::npos);
  EXPECT_NE(
      error_of(std::string(kHead) + "overlays:\n  hud: [\"{handle.t}\"]\n").find("number of the whole scene"),
      std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "overlays:\n  hdu: []\n")
                .find("overlays.hdu: unknown key 'hdu'; did you mean 'hud'?"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "overlays:\n  hud: { lines: [a], corner: middle }\n")
                .find("overlays.hud.corner: expected top_left"),
            std::string::npos);
}

TEST(SceneOverlays, ForcesContactsCaptionsLabelsLegendAndPlotsLoad) {
  const Scene s = load_scene(write_scene(
      "more.yaml",
      std::string(kHead) +
          "    show:\n"
          "      - forces\n"
          "      - { forces: { gravity: true, anchor: tip, scale: 0.1, torque_scale: 0.2, springs: false } "
          "}\n"
          "      - { contacts: { normals: false, scale: 0.01 } }\n"
          "  - { name: other, position: [3, 0, 0], colliders: [ { shape: sphere, radius: 1 } ] }\n"
          "overlays:\n"
          "  hud: ['\\omega_{ij} = {omega.x:.1f}, \\vec{L}, x^{2}']\n"
          "  captions:\n"
          "    - { text: 'First', from: 0.5, to: 1.5 }\n"
          "    - { text: 'Second', from: 1, to: 2, fade: 0, position: top }\n"
          "  labels: [ { body: other, text: 'x_1', offset: [10, -5], color: [1, 1, 0] } ]\n"
          "  legend: { corner: bottom_right }\n"
          "  plots:\n"
          "    - { quantities: [omega_body.y, '|other.v|', E_drift], body: handle, rect: [0.1, 0.2, 0.3, "
          "0.4],\n"
          "        y_range: [-1, 2], labels: [a, b, c], title: T }\n"
          "    - { quantities: [other.position.z], y_range: auto }\n"));
  const auto& items = s.overlays.show[0];
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].kind, ShowKind::forces);
  EXPECT_FALSE(items[0].gravity);
  EXPECT_FALSE(items[0].at_tip);
  EXPECT_TRUE(items[1].gravity);
  EXPECT_TRUE(items[1].at_tip);
  EXPECT_EQ(*items[1].torque_scale, 0.2);
  EXPECT_FALSE(items[1].springs);
  EXPECT_FALSE(items[1].spring_lines);
  // `springs: line`: straight lines (strings); anything else but a bool is an error naming it.
  const Scene lines = load_scene(
      write_scene("lines.yaml", std::string(kHead) + "    show: [ { forces: { springs: line } } ]\n"));
  EXPECT_TRUE(lines.overlays.show[0][0].springs);
  EXPECT_TRUE(lines.overlays.show[0][0].spring_lines);
  EXPECT_NE(error_of(std::string(kHead) + "    show: [ { forces: { springs: coils } } ]\n")
                .find("springs: expected true, false or line"),
            std::string::npos);
  EXPECT_EQ(items[2].kind, ShowKind::contacts);
  EXPECT_FALSE(items[2].normals);
  EXPECT_TRUE(items[2].points);
  EXPECT_EQ(items[2].xray, 0.6);  // contacts lie inside bodies: drawn through them by default
  // TeX groups in a HUD line are text, not fields.
  const HudLine& h = s.overlays.hud[0];
  ASSERT_EQ(h.fields.size(), 1u);
  EXPECT_EQ(h.text[0], "\\omega_{ij} = ");
  EXPECT_EQ(h.text[1], ", \\vec{L}, x^{2}");
  ASSERT_EQ(s.overlays.captions.size(), 2u);
  EXPECT_EQ(s.overlays.captions[0].fade, 0.3);
  EXPECT_EQ(s.overlays.captions[0].position, "bottom");
  EXPECT_EQ(s.overlays.captions[1].position, "top");
  EXPECT_EQ(s.overlays.captions[1].fade, 0.0);
  ASSERT_EQ(s.overlays.labels.size(), 1u);
  EXPECT_EQ(s.overlays.labels[0].body, 1);
  EXPECT_TRUE(s.overlays.labels[0].has_offset);
  EXPECT_EQ(s.overlays.labels[0].dy, -5.0);
  EXPECT_TRUE(s.overlays.legend.shown);
  EXPECT_EQ(s.overlays.legend.corner, "bottom_right");
  ASSERT_EQ(s.overlays.plots.size(), 2u);
  const PlotSpec& p = s.overlays.plots[0];
  ASSERT_EQ(p.quantities.size(), 3u);
  EXPECT_EQ(p.quantities[0].body, 0);
  EXPECT_EQ(p.quantities[0].component, 1);
  EXPECT_EQ(p.quantities[1].body, 1);
  EXPECT_TRUE(p.quantities[1].norm);
  EXPECT_EQ(p.quantities[2].body, -1);
  EXPECT_FALSE(p.auto_range);
  EXPECT_EQ(p.y_max, 2.0);
  EXPECT_EQ(p.rect[3], 0.4);
  EXPECT_EQ(p.labels, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(s.overlays.plots[1].auto_range);
  EXPECT_EQ(s.overlays.plots[1].labels, (std::vector<std::string>{"z"}));
  EXPECT_EQ(s.overlays.plots[1].quantities[0].body, 1);
}

TEST(SceneOverlays, MistakesInTheNewKeysNameFileLineAndKey) {
  const std::string head = std::string(kHead) + "overlays:\n";
  auto has = [&](const std::string& yaml, const std::string& what) {
    const std::string e = error_of(head + yaml);
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  has("  labels: [ { body: handel, text: a } ]\n",
      "bad_overlay.yaml:6:21: overlays.labels[0].body: no body is named 'handel'; did you mean 'handle'?");
  has("  labels: [ { body: handle } ]\n", "overlays.labels[0]: missing key 'text'");
  has("  captions: [ { text: a, from: 2, to: 1 } ]\n", "overlays.captions[0].to: must come after 'from'");
  has("  captions: [ { text: a, position: left } ]\n", "overlays.captions[0].position: expected bottom, top");
  has("  captions: [ { txt: a } ]\n", "overlays.captions[0].txt: unknown key 'txt'; did you mean 'text'?");
  has("  legend: { corner: middle }\n", "overlays.legend.corner: expected top_left");
  has("  legend: { items: [ { text: a } ] }\n", "overlays.legend.items[0]: missing key 'color'");
  has("  plots: [ { quantities: [omega] } ]\n",
      "overlays.plots[0].quantities[0]: 'omega': a vector: plot a component (omega.x) or its magnitude");
  has("  plots: [ { quantities: [t] } ]\n", "plots are against time already");
  has("  plots: [ { quantities: [omgea.x] } ]\n", "unknown quantity 'omgea'; did you mean 'omega'?");
  has("  plots: [ { quantities: [E], rect: [0.8, 0, 0.5, 0.5] } ]\n", "overlays.plots[0].rect: [x, y, w, h]");
  has("  plots: [ { quantities: [E], y_range: [1, 1] } ]\n",
      "overlays.plots[0].y_range: expected auto or [min, max]");
  has("  plots: [ { quantities: [E, t_drift] } ]\n", "unknown quantity 't_drift'");
  has("  plots: [ { quantities: [E], labels: [a, b] } ]\n",
      "overlays.plots[0].labels: expected one label per quantity");
  has("  plots: [ { rect: [0, 0, 1, 1] } ]\n", "overlays.plots[0]: missing key 'quantities'");
  const std::string show = std::string(kHead) + "    show:\n";
  EXPECT_NE(error_of(show + "      - { forces: { anchor: middle } }\n")
                .find("bodies[0].show[0].forces.anchor: expected tail"),
            std::string::npos);
  EXPECT_NE(error_of(show + "      - { contacts: { gravity: true } }\n").find("unknown key 'gravity'"),
            std::string::npos);
  EXPECT_NE(
      error_of(show + "      - { forces: { torque_scale: 0 } }\n").find("forces.torque_scale: must lie in"),
      std::string::npos);
}

// A mechanism of every joint type, for the per-joint quantities and the `joints` item.
const char* kJoints =
    "simulation: { duration: 1 }\n"
    "bodies:\n"
    "  - { name: arm, position: [0.5, 0, 2], colliders: [ { shape: box, size: [1, 0.1, 0.1] } ] }\n"
    "  - { name: cart, position: [3, 0, 2], colliders: [ { shape: box, size: [0.2, 0.2, 0.2] } ] }\n"
    "  - { name: top, position: [6, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: gimbal, position: [9, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: welded, position: [12, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "  - { name: loose, position: [15, 0, 2], colliders: [ { shape: sphere, radius: 0.2 } ] }\n"
    "joints:\n"
    "  - { name: pivot, type: revolute, bodies: [world, arm], anchor: [0, 0, 2], axis: [0, 1, 0] }\n"
    "  - { name: rail, type: prismatic, bodies: [cart, world], anchor: [3, 0, 2], axis: [1, 0, 0] }\n"
    "  - { name: ball, type: spherical, bodies: [world, top], anchor: [6, 0, 2.5] }\n"
    "  - { name: cardan, type: universal, bodies: [world, gimbal], anchor: [9, 0, 2.5], axis: [0, 0, 1],\n"
    "      axis2: [1, 0, 0] }\n"
    "  - { name: weld, type: fixed, bodies: [arm, welded], anchor: [12, 0, 2] }\n";

TEST(SceneOverlays, JointQuantitiesNameAJointAndACoordinate) {
  const Scene s = load_scene(write_scene(
      "joint_hud.yaml", std::string(kJoints) +
                            "overlays:\n"
                            "  hud: ['{pivot.angle:+.3f} {pivot.speed} {period} {rail.angle} {ball.speed} "
                            "{cardan.angle2} {cardan.speed2:.2e} {cardan.period2} {angle}']\n"
                            "  plots: [ { quantities: [pivot.angle, cardan.speed2, rail.period] } ]\n"));
  const std::vector<HudField>& f = s.overlays.hud[0].fields;
  ASSERT_EQ(f.size(), 9u);
  const int want_joint[] = {0, 0, 0, 1, 2, 3, 3, 3, 0};  // no prefix: the first joint
  const int want_coord[] = {0, 0, 0, 0, 0, 1, 1, 1, 0};
  for (size_t k = 0; k < f.size(); ++k) {
    EXPECT_EQ(f[k].joint, want_joint[k]) << k;
    EXPECT_EQ(f[k].coord, want_coord[k]) << k;
    EXPECT_EQ(f[k].body, -1) << k;
  }
  EXPECT_EQ(f[0].name, "angle");
  EXPECT_EQ(f[0].printf, "%+.3f");
  EXPECT_EQ(f[2].name, "period");
  EXPECT_EQ(f[6].printf, "%.2e");
  const PlotSpec& p = s.overlays.plots[0];
  ASSERT_EQ(p.quantities.size(), 3u);
  EXPECT_EQ(p.labels, (std::vector<std::string>{"\\theta (pivot)", "\\dot\\theta_2 (cardan)", "T (rail)"}));
}

TEST(SceneOverlays, JointMistakesNameTheJointAndSuggest) {
  const std::string head = std::string(kJoints) + "overlays:\n  hud: ['";
  auto has = [&](const std::string& field, const std::string& what) {
    const std::string e = error_of(head + field + "']\n");
    EXPECT_NE(e.find(what), std::string::npos) << field << ": " << e;
  };
  has("{pivto.angle}",
      "bad_overlay.yaml:17:9: overlays.hud[0]: '{pivto.angle}': no joint is named 'pivto'; did you "
      "mean 'pivot'?");
  has("{arm.angle}",
      "no joint is named 'arm' ('arm' is a body; angle, speed, period, angle2, speed2, period2 are a "
      "joint's)");
  has("{pivot.omega}", "no body is named 'pivot' ('pivot' is a joint: its quantities are angle, speed");
  has("{pivot.angel}", "unknown quantity 'angel'; did you mean 'angle'?");
  has("{pivot.angle.x}", "'angle' is a number of a joint: no component or |...|");
  has("{|pivot.speed|}", "'speed' is a number of a joint: no component or |...|");
  has("{pivot.angle2}", "joint 'pivot' is revolute: 'angle2' is a universal joint's second coordinate");
  has("{ball.period}",
      "joint 'ball' is spherical: its angle never changes sign, so it has no period to measure");
  has("{weld.angle}", "joint 'weld' is fixed: it has no coordinate");
  // No joints at all.
  const std::string e = error_of(std::string(kHead) + "overlays:\n  hud: ['{angle}', '{p.speed}']\n");
  EXPECT_NE(
      e.find("'angle' is a joint's coordinate (angle, speed, period, angle2, speed2, period2), and the scene "
             "has no joint with one"),
      std::string::npos)
      << e;
  // In a plot, as in the HUD.
  const std::string pe =
      error_of(std::string(kJoints) + "overlays:\n  plots: [ { quantities: [pivto.speed] } ]\n");
  EXPECT_NE(pe.find("overlays.plots[0].quantities[0]: 'pivto.speed': no joint is named 'pivto'; did you mean "
                    "'pivot'?"),
            std::string::npos)
      << pe;
}

TEST(SceneOverlays, TheJointsItemIsForABodyAJointHolds) {
  // Shown on a joint's child, with its options; a joint written [child, world] counts for its child.
  std::string yaml = kJoints;
  const auto put = [&](const std::string& body, const std::string& show) {
    std::string y = yaml;
    const std::string at = "{ name: " + body + ",";
    y.insert(y.find(at) + at.size(), " show: " + show + ",");
    return y;
  };
  const Scene s = load_scene(
      write_scene("joint_item.yaml",
                  put("cart", "[ { joints: { color: [1, 0, 1], scale: 0.3, width: 2, xray: 0.2 } } ]")));
  ASSERT_EQ(s.overlays.show[1].size(), 1u);
  const ShowItem& it = s.overlays.show[1][0];
  EXPECT_EQ(it.kind, ShowKind::joints);
  EXPECT_EQ(*it.scale, 0.3);
  EXPECT_EQ(it.width, 2);
  EXPECT_EQ(it.xray, 0.2);
  EXPECT_EQ(load_scene(write_scene("joint_item2.yaml", put("arm", "[joints]"))).overlays.show[0][0].xray,
            0.5);
  EXPECT_NE(
      error_of(put("loose", "[joints]"))
          .find("bodies[5].show[0]: body 'loose' is no joint's child: `joints` draws the joint that holds a "
                "body to its parent"),
      std::string::npos)
      << error_of(put("loose", "[joints]"));
  EXPECT_NE(
      error_of(put("arm", "[ { joints: { points: false } } ]")).find("joints.points: unknown key 'points'"),
      std::string::npos);
}

TEST(SceneOverlays, TheJointForcesItemIsForABodyAJointHolds) {
  std::string yaml = kJoints;
  const auto put = [&](const std::string& body, const std::string& show) {
    std::string y = yaml;
    const std::string at = "{ name: " + body + ",";
    y.insert(y.find(at) + at.size(), " show: " + show + ",");
    return y;
  };
  const Scene s = load_scene(
      write_scene("joint_forces_item.yaml", put("gimbal",
                                                "[ joints, { joint_forces: { color: [1, 0, 1], scale: 0.01, "
                                                "torque_scale: 0.2, width: 2, xray: 0 } } ]")));
  ASSERT_EQ(s.overlays.show[3].size(), 2u);
  const ShowItem& it = s.overlays.show[3][1];
  EXPECT_EQ(it.kind, ShowKind::joint_forces);
  EXPECT_EQ(std::string(to_string(it.kind)), "joint_forces");
  EXPECT_EQ(*it.scale, 0.01);
  EXPECT_EQ(*it.torque_scale, 0.2);
  EXPECT_EQ(it.width, 2);
  EXPECT_EQ(it.xray, 0);
  // Defaults: automatic scales, xray 0.35 (as `forces`); on a joint written [child, world] too.
  const ShowItem d =
      load_scene(write_scene("joint_forces_item2.yaml", put("cart", "[joint_forces]"))).overlays.show[1][0];
  EXPECT_FALSE(d.scale);
  EXPECT_FALSE(d.torque_scale);
  EXPECT_EQ(d.xray, 0.35);
  EXPECT_NE(
      error_of(put("loose", "[joint_forces]"))
          .find("bodies[5].show[0]: body 'loose' is no joint's child: `joint_forces` draws the force and "
                "torque through the joint that holds a body to its parent"),
      std::string::npos)
      << error_of(put("loose", "[joint_forces]"));
  EXPECT_NE(error_of(put("arm", "[ { joint_forces: { gravity: true } } ]"))
                .find("joint_forces.gravity: unknown key 'gravity'"),
            std::string::npos);
  EXPECT_NE(error_of(put("arm", "[ { joint_forces: { torque_scale: 0 } } ]"))
                .find("joint_forces.torque_scale: must lie in"),
            std::string::npos);
  // An unknown item's suggestions know it.
  EXPECT_NE(error_of(put("arm", "[ joint_force ]"))
                .find("unknown item 'joint_force'; did you mean 'joint_forces'?"),
            std::string::npos)
      << error_of(put("arm", "[ joint_force ]"));
  EXPECT_NE(error_of(put("arm", "[ zzz ]"))
                .find("joints, joint_forces, momentum, angular_momentum_about, snapshot)"),
            std::string::npos)
      << error_of(put("arm", "[ zzz ]"));
}

// Ropes: a distance joint and a pulley over a wheel; none of their end bodies is a tree joint's child.
std::string ropes(const std::string& a, const std::string& b, const std::string& c, const std::string& d,
                  const std::string& wheel) {
  auto show = [](const std::string& s) { return s.empty() ? std::string() : ", show: " + s; };
  return "simulation: { duration: 1 }\n"
         "bodies:\n"
         "  - { name: a, position: [0, 0, 2], colliders: [ { shape: sphere, radius: 0.1 } ]" +
         show(a) +
         " }\n"
         "  - { name: b, position: [0, 0, 1], colliders: [ { shape: sphere, radius: 0.1 } ]" +
         show(b) +
         " }\n"
         "  - { name: c, position: [2.9, 0, 1], colliders: [ { shape: sphere, radius: 0.1 } ]" +
         show(c) +
         " }\n"
         "  - { name: d, position: [3.1, 0, 1], colliders: [ { shape: sphere, radius: 0.1 } ]" +
         show(d) +
         " }\n"
         "  - { name: wheel, position: [3, 0, 3], euler: [90, 0, 0],\n"
         "      colliders: [ { shape: cylinder, radius: 0.1, height: 0.02, collide: false } ]" +
         show(wheel) +
         " }\n"
         "joints:\n"
         "  - { name: rod, type: distance, bodies: [a, b], anchors: [[0, 0, 1.9], [0, 0, 1.1]] }\n"
         "  - { name: axle, type: revolute, bodies: [world, wheel], anchor: [3, 0, 3], axis: [0, 1, 0] }\n"
         "  - { name: rope, type: pulley, bodies: [c, d], anchors: [[2.9, 0, 1.1], [3.1, 0, 1.1]],\n"
         "      pulley_anchors: [[2.9, 0, 3], [3.1, 0, 3]], wheel: wheel }\n";
}

TEST(SceneOverlays, TheJointsItemIsForEitherEndOfARope) {
  // Either end of a distance joint and of a pulley (parent or child) shows its rope; the pulley's
  // wheel shows its axle, as any revolute joint's child.
  const Scene s = load_scene(write_scene("rope_item.yaml", ropes("[joints]", "[ { joints: { width: 2 } } ]",
                                                                 "[joints]", "[joints]", "[joints]")));
  for (size_t b = 0; b < 5; ++b) {
    ASSERT_EQ(s.overlays.show[b].size(), 1u) << b;
    EXPECT_EQ(s.overlays.show[b][0].kind, ShowKind::joints) << b;
  }
  EXPECT_EQ(s.overlays.show[1][0].width, 2);
  // Only the parent's end, only the child's.
  EXPECT_EQ(load_scene(write_scene("rope_item2.yaml", ropes("[joints]", "", "", "[joints]", "")))
                .overlays.show[3]
                .size(),
            1u);
  // `joint_forces` does not draw a rope's force: refused on a body only a rope holds, with what to
  // show instead; on the wheel it is its axle's reaction, as before.
  const std::string e = error_of(ropes("", "", "[joint_forces]", "", ""));
  EXPECT_NE(e.find("bodies[2].show[0]: body 'c' hangs on pulley joint 'rope', and `joint_forces` does not "
                   "draw a rope's force yet"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("`joints` draws the rope"), std::string::npos) << e;
  EXPECT_NE(error_of(ropes("[joint_forces]", "", "", "", "")).find("hangs on distance joint 'rod'"),
            std::string::npos);
  EXPECT_EQ(load_scene(write_scene("rope_item3.yaml", ropes("", "", "", "", "[joint_forces]")))
                .overlays.show[4][0]
                .kind,
            ShowKind::joint_forces);
}

TEST(SceneOverlays, ASceneWithoutOverlaysHasNone) {
  const Scene s = load_scene(write_scene("plain.yaml", kHead));
  EXPECT_FALSE(s.overlays.any());
}

}  // namespace
}  // namespace simreel
