// A receiver's gathered irradiance turned to another normal by its estimate's rotation gradient
// (gather.comp), shared by the interpolation and the receivers' refinement. The including shader
// declares gathered, rotationGradients and leafOfSurfel as texel buffers, and the node texels.

// Receiver r's irradiance turned to normal n: G + (n_r × n)·∇G per channel (at its own normal, G).
vec3 turnedIrradiance(uint r, vec3 n) {
  const vec3 g = imageLoad(gathered, int(r)).rgb;
  const vec3 turn = cross(nodeNormalCone(imageLoad(leafOfSurfel, int(r)).x).xyz, n);
  return max(g + vec3(dot(turn, imageLoad(rotationGradients, int(3u * r)).xyz),
                      dot(turn, imageLoad(rotationGradients, int(3u * r + 1u)).xyz),
                      dot(turn, imageLoad(rotationGradients, int(3u * r + 2u)).xyz)),
             vec3(0.0));
}
