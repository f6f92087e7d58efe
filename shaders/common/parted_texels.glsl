// An array that can outgrow one texel view (maxTexelBufferElements) is declared as kTexelParts
// views of one buffer, `uniform uimageBuffer name[kTexelParts]`; vk::Program binds view p at
// texel p << texelPartBits. Element i lies in view i >> texelPartBits. The views are picked by
// constant indices only: dynamic indexing of texel-buffer arrays is an optional feature (lavapipe
// lacks it). A pass whose arrays fit one view is made with texelViews 1, which folds the choice
// away (lavapipe would otherwise load from both views).
layout(constant_id = 30) const uint texelPartBits = 27u;  // set by vk::Program from the device
layout(constant_id = 31) const uint texelViews = 1u;      // 1 or kTexelParts: set by the pass

#define texelPartOf(i) ((i) >> texelPartBits)
#define texelWithinPart(i) int((i) & ((1u << texelPartBits) - 1u))
// The element at i of the parted array a (i: an unsigned expression without side effects).
#define loadParted(a, i) \
  (texelViews == 1u || texelPartOf(i) == 0u ? imageLoad(a[0], texelWithinPart(i)) : imageLoad(a[1], texelWithinPart(i)))
#define storeParted(a, i, value)                 \
  if (texelViews == 1u || texelPartOf(i) == 0u)  \
    imageStore(a[0], texelWithinPart(i), value); \
  else                                           \
    imageStore(a[1], texelWithinPart(i), value)
