#version 430 core
// Counting pass of random tiles (roughlight.render.counting): the tile is drawn as its regions' triangles (the lit
// and the shadowed part of each facet, exact polygons), each vertex carrying its region. Each fragment adds one to
// its view's count of its region:
//   counts[slot * n_regions + region].
// The shader has side effects and declares no early fragment tests, so it runs before the depth test: every
// fragment counts, hidden or not. The depth test (GL_LESS) then keeps the nearest fragment's region in the image,
// from which the visible pixels are counted.
// Compiled with VISIBLE_ONLY (the views nearest the horizon) it counts nothing: with no side effects and early
// fragment tests, the depth test rejects the hidden fragments before they are shaded, and only the image is kept.

flat in float frag_facet;          // here the region
flat in float frag_slot;

uniform int n_regions;             // 2 x facets a period

out vec4 frag_color;               // the region + 1 in 16 bits (red low byte, green high byte); 0 = no surface

#ifdef VISIBLE_ONLY
layout(early_fragment_tests) in;
#else
layout(std430, binding = 0) buffer Counts { uint counts[]; };
#endif

void main()
{
    uint region = uint(frag_facet + 0.5);
#ifndef VISIBLE_ONLY
    atomicAdd(counts[uint(frag_slot) * uint(n_regions) + region], 1u);
#endif
    float id = float(region) + 1.0;
    frag_color = vec4(mod(id, 256.0), floor(id / 256.0), 0.0, 255.0) / 255.0;
}
