#version 430 core
// Counting pass of random tiles (roughlight.render.counting): each fragment adds one to its view's count of its
// region, the lit or the shadowed part of its facet (decided as periodic.frag decides it, periodic_shadow.glsl):
//   counts[slot * n_regions + 2 facet + (lit ? 0 : 1)].
// With COUNT_EVERY_FRAGMENT the shader runs before the depth test (it has side effects), so every fragment
// counts, while the depth buffer is drawn. Without it, early fragment tests: the depth test (GL_LEQUAL against
// that buffer) picks the visible fragments before the shader runs.
#ifndef COUNT_EVERY_FRAGMENT
layout(early_fragment_tests) in;
#endif

in vec3 frag_local;
flat in vec3 frag_vertex;
in vec3 frag_normal;
flat in float frag_facet;
flat in float frag_slot;
flat in float frag_lit_state;

uniform vec3 light_dir;            // unit vector toward the light
uniform int n_regions;             // 2 x facets a period

layout(std430, binding = 0) buffer Counts { uint counts[]; };

#include "periodic_shadow.glsl"

void main()
{
    vec3 N = normalize(frag_normal);
    float lit = lit_by_light(N, dot(N, light_dir), frag_lit_state);
    uint region = uint(2.0 * frag_facet + 1.0 - lit);
    atomicAdd(counts[uint(frag_slot) * uint(n_regions) + region], 1u);
}
