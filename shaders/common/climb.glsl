// Bottom-up over the trees in one dispatch (refit, pull-up, the receivers' reach): a dispatch a
// level would cost lavapipe a wake-up and a wait of its threads each, whatever its work. An
// invocation per node (main() below); a leaf's combines its node and climbs: a parent is combined
// by the invocation whose child arrives there last (a count per node, which that invocation sets
// back to zero for the next dispatch), so every node is combined once, after all its children.
// Which invocation combines a node differs from run to run; what it computes does not.
//
// The including shader defines CLIMB_ARRIVALS (the binding of the counts), `uvec4 treeNodeAt(uint)`
// (gpu::TreeNode: parent, first child, child count, surfel), `void combine(uint node)` and a push
// constant `push` whose `count` is the number of nodes (gpu::CountPush), and declares `coherent`
// the buffer that combine() writes and reads of children. Where it defines CLIMB_LEAVES (a binding),
// the invocations climb from the leaves listed there instead, `count` of them: every leaf below the
// nodes to combine, so that each of them sees all its children arrive.
layout(std430, binding = CLIMB_ARRIVALS) coherent buffer Arrivals { uint arrivals[]; };
#ifdef CLIMB_LEAVES
layout(binding = CLIMB_LEAVES, r32ui) readonly uniform uimageBuffer climbLeaves;
#endif

// From node `leaf` (nothing where it is not a leaf) up to where a sibling is still to come.
void climbFrom(uint leaf) {
  uvec4 t = treeNodeAt(leaf);
  if (t.z == 0u) combine(leaf);
  int parent = t.z == 0u ? int(t.x) : -1;
  while (parent >= 0) {
    if (!cpuDevice) memoryBarrierBuffer();  // the node's result before its arrival is counted
    t = treeNodeAt(uint(parent));
    if (atomicAdd(arrivals[parent], 1u) + 1u < t.z) break;
    arrivals[parent] = 0u;
    if (!cpuDevice) memoryBarrierBuffer();  // the siblings' results after the last arrival
    combine(uint(parent));
    parent = int(t.x);
  }
}

void main() {
  const uint i = itemIndex();
#ifdef CLIMB_LEAVES
  if (i < push.count) climbFrom(imageLoad(climbLeaves, int(i)).x);
#else
  if (i < push.count) climbFrom(i);
#endif
}
