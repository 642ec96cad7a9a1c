// simreel's URDF reader (app/import/urdf.cpp, on tinyxml2) against the reference parser, Debian's
// liburdfdom, on every corpus file liburdfdom accepts: the same links, joints, types, origins,
// axes, limits, dynamics and inertials (their rotation applied). liburdfdom is a test-only
// dependency: simreel reads URDF itself because liburdfdom refuses a whole file for one element it
// does not know and reports without line numbers (docs/import.md).
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/import/urdf.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

Quat quat(const urdf::Rotation& r) {
  return Quat(r.w, r.x, r.y, r.z);
}
Vec3 vec(const urdf::Vector3& v) {
  return Vec3(v.x, v.y, v.z);
}

TEST(UrdfdomCrosscheck, CorpusFilesReadAsTheReferenceParserReadsThem) {
  const fs::path corpus = SIMREEL_CORPUS_DIR "/bullet3/data";
  int files = 0;
  for (const char* f : {"cube.urdf", "plane.urdf", "r2d2.urdf", "cartpole.urdf", "sphere2.urdf",
                        "kuka_iiwa/model.urdf", "racecar/racecar.urdf", "toys/concave_box.urdf"}) {
    SCOPED_TRACE(f);
    std::ifstream in(corpus / f);
    std::stringstream text;
    text << in.rdbuf();
    const urdf::ModelInterfaceSharedPtr ref = urdf::parseURDF(text.str());
    ASSERT_TRUE(ref) << "liburdfdom refused it";
    const Model ours = read_urdf((corpus / f).string());
    ++files;
    ASSERT_EQ(ours.links.size(), ref->links_.size());
    ASSERT_EQ(ours.joints.size(), ref->joints_.size());
    std::map<std::string, const ModelLink*> links;
    for (const ModelLink& l : ours.links) links[l.name] = &l;
    for (const auto& [name, rl] : ref->links_) {
      SCOPED_TRACE(name);
      ASSERT_TRUE(links.count(name));
      const ModelLink& l = *links[name];
      const bool stated = rl->inertial && rl->inertial->mass > 0;
      ASSERT_EQ(l.inertial && l.inertial->mass > 0, stated);
      if (!stated) continue;
      const urdf::Inertial& ri = *rl->inertial;
      EXPECT_EQ(l.inertial->mass, ri.mass);
      EXPECT_LT((l.inertial->com - vec(ri.origin.position)).norm(), 1e-15);
      Mat3 J;
      J << ri.ixx, ri.ixy, ri.ixz, ri.ixy, ri.iyy, ri.iyz, ri.ixz, ri.iyz, ri.izz;
      const Mat3 R = quat(ri.origin.rotation).toRotationMatrix();
      EXPECT_LT((l.inertial->inertia - R * J * R.transpose()).cwiseAbs().maxCoeff(),
                1e-12 * (J.norm() + 1e-30));
    }
    for (const ModelJoint& j : ours.joints) {
      SCOPED_TRACE(j.name);
      ASSERT_TRUE(ref->joints_.count(j.name));
      const urdf::Joint& rj = *ref->joints_.at(j.name);
      EXPECT_EQ(ours.links[j.parent].name, rj.parent_link_name);
      EXPECT_EQ(ours.links[j.child].name, rj.child_link_name);
      using K = ModelJoint::Kind;
      const std::map<int, K> kinds = {
          {urdf::Joint::REVOLUTE, K::revolute},   {urdf::Joint::CONTINUOUS, K::continuous},
          {urdf::Joint::PRISMATIC, K::prismatic}, {urdf::Joint::FLOATING, K::floating},
          {urdf::Joint::PLANAR, K::planar},       {urdf::Joint::FIXED, K::fixed}};
      EXPECT_EQ(j.kind, kinds.at(rj.type));
      const ModelPose& o = ours.links[j.child].pose;
      EXPECT_LT((o.p - vec(rj.parent_to_joint_origin_transform.position)).norm(), 1e-15);
      const Quat rq = quat(rj.parent_to_joint_origin_transform.rotation);
      EXPECT_LT((o.q.toRotationMatrix() - rq.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-14);
      if (j.kind != K::fixed && j.kind != K::floating) {
        EXPECT_LT((j.axis - vec(rj.axis).normalized()).norm(), 1e-15);
      }
      if (j.limits) {
        ASSERT_TRUE(rj.limits);
        EXPECT_EQ((*j.limits)[0], rj.limits->lower);
        EXPECT_EQ((*j.limits)[1], rj.limits->upper);
        EXPECT_EQ(j.effort, rj.limits->effort);
      }
      if (rj.dynamics) {
        EXPECT_EQ(j.damping, rj.dynamics->damping);
        EXPECT_EQ(j.friction, rj.dynamics->friction);
      }
    }
  }
  EXPECT_EQ(files, 8);
}

}  // namespace
}  // namespace simreel
