#version 430 core
// Counting pass of random tiles (roughlight.render.counting): each fragment adds one to its view's count of its
// region, the lit or the shadowed part of its facet (decided as periodic.frag decides it, periodic_shadow.glsl):
//   counts[slot * n_regions + 2 facet + (lit ? 0 : 1)].
// The shader has side effects and declares no early fragment tests, so it runs before the depth test: every
// fragment counts, hidden or not. The depth test (GL_LESS) then keeps the nearest fragment's region in the image,
// from which the visible pixels are counted.

in vec3 frag_local;
flat in vec3 frag_vertex;
in vec3 frag_normal;
flat in float frag_facet;
flat in float frag_slot;
flat in float frag_lit_state;

uniform vec3 light_dir;            // unit vector toward the light
uniform int n_regions;             // 2 x facets a period

out vec4 frag_color;               // the region + 1 in 16 bits (red low byte, green high byte); 0 = no surface

layout(std430, binding = 0) buffer Counts { uint counts[]; };

#include "periodic_shadow.glsl"

void main()
{
    vec3 N = normalize(frag_normal);
    float lit = lit_by_light(N, dot(N, light_dir), frag_lit_state);
    uint region = uint(2.0 * frag_facet + 1.0 - lit);
    atomicAdd(counts[uint(frag_slot) * uint(n_regions) + region], 1u);
    float id = float(region) + 1.0;
    frag_color = vec4(mod(id, 256.0), floor(id / 256.0), 0.0, 255.0) / 255.0;
}
