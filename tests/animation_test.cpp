// Keyframe sampling and node poses against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "engine/scene/animation.h"
#include "engine/scene/camera.h"

using namespace ivgi::scene;

namespace {

Sampler scalar(Interpolation mode, std::vector<float> times, std::vector<float> values) {
  Sampler s;
  s.input = std::move(times);
  s.output = std::move(values);
  s.components = 1;
  s.interpolation = mode;
  return s;
}

float at(const Sampler& s, float t) {
  float v;
  sampleAt(s, t, false, &v);
  return v;
}

glm::quat axisAngle(float degrees, glm::vec3 axis) { return glm::angleAxis(glm::radians(degrees), axis); }

}  // namespace

TEST(Animation, StepHoldsEachKeyUntilTheNext) {
  Sampler s = scalar(Interpolation::Step, {0, 1, 2}, {0, 10, 20});
  EXPECT_EQ(at(s, -1.0f), 0.0f);
  EXPECT_EQ(at(s, 0.5f), 0.0f);
  EXPECT_EQ(at(s, 1.0f), 10.0f);
  EXPECT_EQ(at(s, 1.99f), 10.0f);
  EXPECT_EQ(at(s, 5.0f), 20.0f);
}

TEST(Animation, LinearInterpolatesAndClampsOutsideTheKeys) {
  Sampler s = scalar(Interpolation::Linear, {1, 2, 4}, {0, 10, 30});
  EXPECT_FLOAT_EQ(at(s, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(at(s, 1.25f), 2.5f);
  EXPECT_FLOAT_EQ(at(s, 3.0f), 20.0f);
  EXPECT_FLOAT_EQ(at(s, 9.0f), 30.0f);
}

TEST(Animation, CubicSplineFollowsTheHermiteFormOfTheSpec) {
  // Keys t = 0 and 2; per key [in-tangent, value, out-tangent]: [9, 0, 1] and [0, 1, 9].
  // At t = 1 (u = 0.5, dt = 2): (u³-2u²+u)·dt·1 + (-2u³+3u²)·1 = 0.125·2 + 0.5 = 0.75.
  Sampler s = scalar(Interpolation::CubicSpline, {0, 2}, {9, 0, 1, 0, 1, 9});
  EXPECT_FLOAT_EQ(at(s, 1.0f), 0.75f);
  EXPECT_FLOAT_EQ(at(s, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(at(s, 2.0f), 1.0f);
  // u = 0.25: h00 = 0.84375, h10 = 0.140625, h01 = 0.15625 → 0.140625·2 + 0.15625 = 0.4375.
  EXPECT_FLOAT_EQ(at(s, 0.5f), 0.4375f);
}

TEST(Animation, SlerpTakesTheShortArc) {
  glm::quat a = axisAngle(0, {0, 0, 1}), b = axisAngle(90, {0, 0, 1});
  glm::quat half = slerp(a, b, 0.5f);
  EXPECT_NEAR(half.w, std::cos(glm::radians(22.5f)), 1e-6f);
  EXPECT_NEAR(half.z, std::sin(glm::radians(22.5f)), 1e-6f);
  // The same rotation written with the opposite sign must not go the long way round.
  glm::quat viaNegated = slerp(a, -b, 0.5f);
  EXPECT_NEAR(std::abs(glm::dot(viaNegated, half)), 1.0f, 1e-6f);
  // A third of the way between 0° and 90°: 30°.
  glm::quat third = slerp(a, b, 1.0f / 3.0f);
  EXPECT_NEAR(2.0f * std::acos(third.w), glm::radians(30.0f), 1e-5f);
}

TEST(Animation, LinearRotationChannelsUseSlerp) {
  Sampler s;
  glm::quat q0 = axisAngle(0, {0, 1, 0}), q1 = axisAngle(120, {0, 1, 0});
  s.input = {0, 1};
  s.output = {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w};
  s.components = 4;
  float out[4];
  sampleAt(s, 0.5f, true, out);
  glm::quat q(out[3], out[0], out[1], out[2]);
  EXPECT_NEAR(glm::length(q), 1.0f, 1e-6f);  // a plain lerp would give length cos(30°) = 0.866
  EXPECT_NEAR(2.0f * std::acos(q.w), glm::radians(60.0f), 1e-5f);
}

TEST(Animation, PoseComposesTheHierarchyAndAppliesChannels) {
  Scene scene;
  scene.nodes.resize(2);
  scene.nodes[0].translation = {1, 0, 0};
  scene.nodes[0].children = {1};
  scene.nodes[1].parent = 0;
  scene.nodes[1].translation = {0, 2, 0};
  scene.roots = {0};
  Animation a;
  a.samplers.push_back({{0, 1}, {0, 0, 0, 0, 0, 4}, 3, Interpolation::Linear});  // child translation (0,0,0) → (0,0,4)
  glm::quat r0 = axisAngle(0, {0, 0, 1}), r1 = axisAngle(90, {0, 0, 1});
  a.samplers.push_back({{0, 1}, {r0.x, r0.y, r0.z, r0.w, r1.x, r1.y, r1.z, r1.w}, 4, Interpolation::Linear});
  a.channels.push_back({1, Path::Translation, 0});
  a.channels.push_back({0, Path::Rotation, 1});
  a.end = 1;
  scene.animations.push_back(a);

  Pose rest = evaluatePose(scene, -1, 0.5f);
  EXPECT_EQ(glm::vec3(rest.world[1][3]), glm::vec3(1, 2, 0));

  Pose end = evaluatePose(scene, 0, 1.0f);
  // Parent turned 90° about z, child at (0,0,4) local: world = (1,0,0) + Rz(90°)·(0,0,4).
  glm::vec3 p(end.world[1][3]);
  EXPECT_NEAR(p.x, 1.0f, 1e-6f);
  EXPECT_NEAR(p.y, 0.0f, 1e-6f);
  EXPECT_NEAR(p.z, 4.0f, 1e-6f);
  glm::vec3 xAxis(end.world[1][0]);
  EXPECT_NEAR(xAxis.y, 1.0f, 1e-6f);  // child's x axis now points along world y
}

TEST(Animation, AnimatedCamerasMove) {
  // A camera node animated along x, looking down -z, turned 90° about y at the end.
  Scene scene;
  scene.cameras.push_back({"cam", 0.8f, 0.1f, 0.0f, 0.0f});
  scene.nodes.resize(1);
  scene.nodes[0].camera = 0;
  scene.roots = {0};
  Animation a;
  a.samplers.push_back({{0, 2}, {0, 0, 5, 4, 0, 5}, 3, Interpolation::Linear});
  glm::quat r0 = axisAngle(0, {0, 1, 0}), r1 = axisAngle(90, {0, 1, 0});
  a.samplers.push_back({{0, 2}, {r0.x, r0.y, r0.z, r0.w, r1.x, r1.y, r1.z, r1.w}, 4, Interpolation::Linear});
  a.channels = {{0, Path::Translation, 0}, {0, Path::Rotation, 1}};
  a.end = 2;
  scene.animations.push_back(a);
  CameraView start = cameraView(scene, evaluatePose(scene, 0, 0.0f), 0);
  CameraView middle = cameraView(scene, evaluatePose(scene, 0, 1.0f), 0);
  CameraView end = cameraView(scene, evaluatePose(scene, 0, 2.0f), 0);
  EXPECT_EQ(start.origin, glm::vec3(0, 0, 5));
  EXPECT_NEAR(middle.origin.x, 2.0f, 1e-6f);
  EXPECT_NEAR(start.forward.z, -1.0f, 1e-6f);
  EXPECT_NEAR(end.forward.x, -1.0f, 1e-6f) << "-z turned 90° about y looks along -x";
  EXPECT_NEAR(middle.forward.x, -std::sin(glm::radians(45.0f)), 1e-5f);
  EXPECT_NEAR(glm::dot(end.right, end.up), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(end.yfov, 0.8f);
  // iv's receivers follow the view only where the scene moves or its cameras stand still.
  EXPECT_TRUE(animationMovesCameras(scene, 0));
  EXPECT_FALSE(animationMovesGeometry(scene, 0));
  EXPECT_FALSE(animationMovesCameras(scene, -1));
  scene.nodes.push_back(scene.nodes[0]);  // a second camera, still: the animation still moves one
  scene.nodes[1].camera = 0;
  scene.roots = {0, 1};
  EXPECT_TRUE(animationMovesCameras(scene, 0));
  scene.animations[0].channels = {{1, Path::Translation, 0}};  // now the second one moves
  EXPECT_TRUE(animationMovesCameras(scene, 0));
  scene.nodes[1].camera = -1;  // and carries no camera
  EXPECT_FALSE(animationMovesCameras(scene, 0));
}
