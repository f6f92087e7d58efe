// Surfels inside another object (shaders/gi/buried_surfels.comp): a floor's surfels under a block
// standing on it are buried; those around it, under a block floating over it, or inside a room whose
// walls face in are not. Buried senders are left unlinked (refine_links).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine/gi/frame_renderer.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;

namespace {

// A floor of 16 × 16 cells over [-1, 1]² in a closed room (walls and ceiling facing in, a lamp under
// the ceiling), each its own object; returns the grey material the room is made of.
int floorInARoom(scenes::GltfBuilder& b) {
  const int grey = b.material("grey", glm::vec3(0.6f)), light = b.material("lamp", glm::vec3(0.0f), glm::vec3(5.0f));
  scenes::MeshData floor, room, lamp;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 16, 16, {0, 1, 0});
  scenes::addQuad(room, {-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, 4, 4, {0, -1, 0});  // ceiling
  scenes::addQuad(room, {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, 4, 4, {0, 0, 1});
  scenes::addQuad(room, {-1, 0, 1}, {1, 0, 1}, {1, 2, 1}, {-1, 2, 1}, 4, 4, {0, 0, -1});
  scenes::addQuad(room, {-1, 0, -1}, {-1, 0, 1}, {-1, 2, 1}, {-1, 2, -1}, 4, 4, {1, 0, 0});
  scenes::addQuad(room, {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, 4, 4, {-1, 0, 0});
  scenes::addQuad(lamp, {-0.2f, 1.95f, -0.2f}, {0.2f, 1.95f, -0.2f}, {0.2f, 1.95f, 0.2f}, {-0.2f, 1.95f, 0.2f}, 1, 1,
                  {0, -1, 0});
  b.node("floor", b.mesh("floor", {{floor, grey}}));
  b.node("room", b.mesh("room", {{room, grey}}));
  b.node("lamp", b.mesh("lamp", {{lamp, light}}));
  return grey;
}

// floorInARoom with a box 0.6 m wide standing on the floor over x ∈ [-0.7, -0.1], z ∈ [-0.3, 0.3],
// and another floating 0.3 m over it around x = 0.5; each its own object.
tinygltf::Model boxesOnAFloor() {
  scenes::GltfBuilder b;
  const int grey = floorInARoom(b);
  scenes::MeshData standing, floating;
  scenes::addBox(standing, {-0.4f, 0.3f, 0.0f}, glm::vec3(0.3f), 4);
  scenes::addBox(floating, {0.5f, 0.5f, 0.0f}, glm::vec3(0.2f), 4);
  b.node("standing", b.mesh("standing", {{standing, grey}}));
  b.node("floating", b.mesh("floating", {{floating, grey}}));
  return b.finish();
}

// boxesOnAFloor's frame as iv solves it: the surfels, which of them are buried, each one's surviving
// links with the trees' nodes their senders name, and the solver's figures.
struct Solved {
  std::vector<scene::Surfel> surfels;
  std::vector<uint32_t> buried;
  std::vector<std::vector<gi::IvSolver::LeafLink>> links;
  std::vector<gpu::TreeNode> nodes;
  gi::IvStats stats;
};
Solved solveBoxes(const gi::IvSettings& settings) {
  const scene::Scene s = scene::sceneFromModel(boxesOnAFloor(), "boxes");
  const scene::Geometry g = scene::buildGeometry(s);
  gi::FrameRenderer r = test::ivRenderer(g, {32, 32, 1}, gi::makeIvSetup(s, g, settings));
  const auto pose = scene::evaluatePose(s, -1, 0.0f);
  const auto inputs = g.frameInputs(s, pose);
  r.render(inputs, test::framing(g, inputs), scene::worldLights(s, pose));
  const gi::IvSolver& iv = test::ivSolver(r);
  return {r.surfels(), iv.surfelBuried().read<uint32_t>(g.surfels.size()), iv.leafLinks(), iv.hierarchy().nodes,
          iv.stats()};
}

}  // namespace

TEST(Burial, AFloorUnderABlockStandingOnItIsBuriedAndNothingElse) {
  const Solved solved = solveBoxes({});
  const std::vector<scene::Surfel>& surfels = solved.surfels;
  const std::vector<uint32_t>& buried = solved.buried;
  int under = 0, around = 0, others = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    const glm::vec3 p(surfels[i].positionArea), n(surfels[i].normal);
    const bool floor = std::abs(p.y) < 1e-4f && n.y > 0.9f;
    // Within the standing box's footprint, or out of it, by half a cell (the floor's cells are 0.125).
    const float outside = std::max(std::abs(p.x + 0.4f), std::abs(p.z)) - 0.3f;
    if (floor && outside < -0.06f) {
      EXPECT_EQ(buried[i], 1u) << "the floor at " << p.x << ", " << p.z << " under the standing box";
      ++under;
    } else if (floor && outside > 0.06f) {
      EXPECT_EQ(buried[i], 0u) << "the floor at " << p.x << ", " << p.z << " (the floating box's shadow or open)";
      ++around;
    } else if (!floor) {
      EXPECT_EQ(buried[i], 0u) << "a surfel of the walls or the boxes at " << p.x << ", " << p.y << ", " << p.z;
      ++others;
    }
  }
  std::printf("[ burial ] floor surfels under the standing box %d, around it %d, others %d\n", under, around, others);
  EXPECT_EQ(under, 4 * 3);  // x at -0.625 … -0.25 (corners of the floor's cells), z at -0.125 … 0.125
  EXPECT_GT(around, 200);
  EXPECT_GT(others, 100);
}

// The floor under the standing box, buried, is no sender. Linked, its surfels survive the prune at
// surfaces outside (they win bins through the gaps between the box's faces, and a floor surfel whose
// centre is under the box reaches out in front of it); unlinked, none does, and the links and the
// prune's work fall. Every surfel a receiver, so that only the links differ.
TEST(Burial, SendersInsideAnotherObjectAreNotLinked) {
  // Summed over every unburied surfel's surviving links from buried surfels.
  auto buriedFormFactor = [](const Solved& solved) {
    double sum = 0;
    for (size_t receiver = 0; receiver < solved.links.size(); ++receiver) {  // per surfel
      if (solved.buried[receiver]) continue;
      for (const auto& link : solved.links[receiver]) {
        const int sender = solved.nodes[link.sender].surfel;
        if (sender >= 0 && solved.buried[size_t(sender)]) sum += link.formFactor;
      }
    }
    return sum;
  };
  gi::IvSettings settings{.receiverTolerance = 0.0f};
  const Solved unlinked = solveBoxes(settings);
  settings.linkBuriedSenders = true;
  const Solved linked = solveBoxes(settings);
  std::printf(
      "[ burial ] surviving form factors from buried senders %.4f (linked), %.4f (unlinked); links %u against "
      "%u, senders walked %llu against %llu\n",
      buriedFormFactor(linked), buriedFormFactor(unlinked), linked.stats.links, unlinked.stats.links,
      (unsigned long long)linked.stats.sendersWalked, (unsigned long long)unlinked.stats.sendersWalked);
  EXPECT_GT(buriedFormFactor(linked), 0.0) << "linked, buried senders win bins outside";
  EXPECT_EQ(buriedFormFactor(unlinked), 0.0);
  EXPECT_LT(unlinked.stats.links, linked.stats.links);
  EXPECT_LT(unlinked.stats.sendersWalked, linked.stats.sendersWalked);
}

namespace {

// floorInARoom with a still box standing at x = 0.5 and, animated, a box standing at x = −0.4 that
// slides 0.3 m toward it over a second.
scene::Scene slidingBox() {
  scenes::GltfBuilder b;
  const int grey = floorInARoom(b);
  scenes::MeshData still, sliding;
  scenes::addBox(still, {0.5f, 0.2f, 0.0f}, glm::vec3(0.2f), 4);
  scenes::addBox(sliding, glm::vec3(0.0f), glm::vec3(0.3f), 4);
  b.node("still", b.mesh("still", {{still, grey}}));
  const int box = b.node("sliding", b.mesh("sliding", {{sliding, grey}}), {-0.4f, 0.3f, 0.0f});
  b.animate("slide", box, "translation", {0.0f, 1.0f}, {-0.4f, 0.3f, 0.0f, -0.1f, 0.3f, 0.0f});
  return scene::sceneFromModel(b.finish(), "sliding");
}

}  // namespace

// After the first frame only what moves is posed, refit and tested for burial: a frame rendered
// after another gives, bit for bit, the surfels, the nodes and the burial of the same frame rendered
// first.
TEST(Burial, LaterFramesTestOnlyWhatMoves) {
  const scene::Scene s = slidingBox();
  const scene::Geometry g = scene::buildGeometry(s);
  const gi::IvSettings settings{};
  auto renderAt = [&](gi::FrameRenderer& r, float t) {
    const auto pose = scene::evaluatePose(s, 0, t);
    const auto inputs = g.frameInputs(s, pose);
    r.render(inputs, test::framing(g, inputs), scene::worldLights(s, pose));
  };
  gi::FrameRenderer after = test::ivRenderer(g, {16, 16, 1}, gi::makeIvSetup(s, g, settings, 0));
  renderAt(after, 0.0f);
  const std::vector<uint32_t> before = test::ivSolver(after).surfelBuried().read<uint32_t>(g.surfels.size());
  renderAt(after, 1.0f);
  gi::FrameRenderer first = test::ivRenderer(g, {16, 16, 1}, gi::makeIvSetup(s, g, settings, 0));
  renderAt(first, 1.0f);
  const gi::IvSolver &a = test::ivSolver(after), &b = test::ivSolver(first);
  const std::vector<uint32_t> buriedAfter = a.surfelBuried().read<uint32_t>(g.surfels.size()),
                              buriedFirst = b.surfelBuried().read<uint32_t>(g.surfels.size());
  const std::vector<scene::Surfel> surfels = after.surfels(), surfelsFirst = first.surfels();
  ASSERT_EQ(surfels.size(), surfelsFirst.size());
  EXPECT_EQ(std::memcmp(surfels.data(), surfelsFirst.data(), surfels.size() * sizeof(scene::Surfel)), 0);
  int stillBuried = 0, uncovered = 0, covered = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    const glm::vec3 p(surfels[i].positionArea);
    if (std::abs(p.y) > 1e-4f || surfels[i].normal.y < 0.9f) continue;  // the floor's
    const bool underStill = std::max(std::abs(p.x - 0.5f), std::abs(p.z)) < 0.14f;
    stillBuried += underStill && before[i] && buriedAfter[i];
    uncovered += before[i] && !buriedAfter[i];
    covered += !before[i] && buriedAfter[i];
  }
  std::printf(
      "[ burial ] floor surfels under the still box buried in both frames %d; uncovered by the slide %d, "
      "covered %d\n",
      stillBuried, uncovered, covered);
  EXPECT_GT(stillBuried, 0);
  EXPECT_GT(uncovered, 0) << "the slide uncovers floor";
  EXPECT_GT(covered, 0) << "and covers floor";
  EXPECT_EQ(buriedAfter, buriedFirst);
  const std::vector<gpu::NodeState> nodesAfter = a.nodeStates(), nodesFirst = b.nodeStates();
  ASSERT_EQ(nodesAfter.size(), nodesFirst.size());
  EXPECT_EQ(std::memcmp(nodesAfter.data(), nodesFirst.data(), nodesAfter.size() * sizeof(gpu::NodeState)), 0);
  // The links leave out the buried senders (the nodes' counts of them).
  EXPECT_EQ(a.stats().links, b.stats().links);
  EXPECT_EQ(a.stats().leafLinks, b.stats().leafLinks);
}

namespace {

// floorInARoom with one object of two closed boxes: a block 0.6 m wide floating over the floor (x from
// -0.6 to 0) and a knob 0.3 m wide sunk half into its +x face (x from -0.15 to 0.15, around y = 0.8,
// z = 0); and apart, a bumpy ball of 12 × 6 quads (its radius 0.25, 15 % hills and hollows). With
// `turning`, the block and knob turn 60° about the vertical through x = -0.3 over a second.
scene::Scene knobSunkIntoABlock(bool turning = false) {
  scenes::GltfBuilder b;
  const int grey = floorInARoom(b);
  scenes::MeshData block, bumpy = test::uvSphere(6, true);
  scenes::addBox(block, {0.0f, 0.0f, 0.0f}, glm::vec3(0.3f), 6);
  scenes::addBox(block, {0.3f, 0.0f, 0.0f}, glm::vec3(0.15f), 4);
  for (glm::vec3& p : bumpy.positions) p = 0.25f * p + glm::vec3(0.5f, 0.5f, 0.5f);
  const int node = b.node("block", b.mesh("block", {{block, grey}}), {-0.3f, 0.8f, 0.0f});
  b.node("ball", b.mesh("ball", {{bumpy, grey}}));
  if (turning) {
    const glm::quat turned = glm::angleAxis(glm::radians(60.0f), glm::vec3(0, 1, 0));
    b.animate("turn", node, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, turned.x, turned.y, turned.z, turned.w});
  }
  return scene::sceneFromModel(b.finish(), "knob");
}

// iv's frame at time t of `animation`, rendered after the frames at the times in `before` (by the same
// renderer): its surfels and which of them are buried.
struct Burial {
  std::vector<scene::Surfel> surfels;
  std::vector<uint32_t> buried;
};
Burial buriedAt(const scene::Scene& s, const scene::Geometry& g, int animation, float t,
                const std::vector<float>& before = {}) {
  gi::FrameRenderer r = test::ivRenderer(g, {32, 32, 1}, gi::makeIvSetup(s, g, {}, animation));
  for (float time : before) {
    const auto pose = scene::evaluatePose(s, animation, time);
    const auto inputs = g.frameInputs(s, pose);
    r.render(inputs, test::framing(g, inputs), scene::worldLights(s, pose));
  }
  const auto pose = scene::evaluatePose(s, animation, t);
  const auto inputs = g.frameInputs(s, pose);
  r.render(inputs, test::framing(g, inputs), scene::worldLights(s, pose));
  return {r.surfels(), test::ivSolver(r).surfelBuried().read<uint32_t>(g.surfels.size())};
}

}  // namespace

// Where one part of an object is sunk into another (an eyeball into a head), each part's surfels
// inside the other are buried: the knob's half inside the block, and the block's face inside the
// knob. Nothing else is: the parts' surfels out in the open, and every surfel of the bumpy ball,
// whose own surface, tiled by coarse rectangles, winds about ½ around them.
TEST(Burial, APartSunkIntoAnotherPartOfItsObjectIsBuriedThere) {
  const scene::Scene s = knobSunkIntoABlock();
  const scene::Geometry g = scene::buildGeometry(s);
  const auto [surfels, buried] = buriedAt(s, g, -1, 0.0f);
  int knobInside = 0, faceInside = 0, open = 0, ball = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    const glm::vec3 p(surfels[i].positionArea), n(surfels[i].normal);
    const bool inBlock =
        p.x > -0.6f - 1e-4f && p.x < 1e-4f && std::abs(p.y - 0.8f) < 0.3f + 1e-4f && std::abs(p.z) < 0.3f + 1e-4f;
    const bool inKnob =
        std::abs(p.x) < 0.15f + 1e-4f && std::abs(p.y - 0.8f) < 0.15f + 1e-4f && std::abs(p.z) < 0.15f + 1e-4f;
    auto onFace = [&](float within) {
      return inBlock && n.x > 0.9f && std::abs(p.y - 0.8f) < within && std::abs(p.z) < within;
    };
    if (inKnob && p.x < -0.03f) {
      EXPECT_NE(buried[i], 0u) << "the knob inside the block at " << p.x << ", " << p.y << ", " << p.z;
      ++knobInside;
    } else if (onFace(0.12f)) {
      EXPECT_NE(buried[i], 0u) << "the block's face inside the knob at " << p.y << ", " << p.z;
      ++faceInside;
    } else if (glm::distance(p, glm::vec3(0.5f)) < 0.4f) {
      EXPECT_EQ(buried[i], 0u) << "the bumpy ball at " << p.x << ", " << p.y << ", " << p.z;
      ++ball;
    } else if (!(inKnob && p.x < 0.03f) && !onFace(0.18f)) {
      EXPECT_EQ(buried[i], 0u) << "a surfel in the open at " << p.x << ", " << p.y << ", " << p.z;
      ++open;
    }
  }
  std::printf(
      "[ burial ] the knob's surfels inside the block %d, the block's inside the knob %d, the ball's %d, "
      "in the open %d\n",
      knobInside, faceInside, ball, open);
  EXPECT_GT(knobInside, 20);
  EXPECT_EQ(faceInside, 9);  // the block's face cells are 0.1 m: y 0.7 … 0.9, z -0.1 … 0.1
  EXPECT_GT(ball, 60);
  EXPECT_GT(open, 300);
}

// An object that turns keeps its shape, so the frames after the first keep what it buried of
// itself rather than test it again: they find what a renderer starting at that frame finds.
TEST(Burial, AnObjectThatTurnsKeepsWhatItBuriesOfItself) {
  const scene::Scene s = knobSunkIntoABlock(true);
  const scene::Geometry g = scene::buildGeometry(s);
  const std::vector<uint32_t> kept = buriedAt(s, g, 0, 1.0f, {0.0f}).buried, found = buriedAt(s, g, 0, 1.0f).buried;
  const auto inItself = [](const std::vector<uint32_t>& buried) {
    return std::count_if(buried.begin(), buried.end(), [](uint32_t b) { return (b & gpu::kBuriedInItself) != 0u; });
  };
  std::printf("[ burial ] surfels inside another part of their object: %td kept, %td found\n", inItself(kept),
              inItself(found));
  EXPECT_GT(inItself(found), 20);
  EXPECT_EQ(kept, found);
}
