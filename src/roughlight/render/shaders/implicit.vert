#version 330 core
#ifdef TABLE_SHARES
#extension GL_ARB_shading_language_420pack : require
#endif
// One flat quad. In a sweep (field_size = 0) the quad covers the framebuffer
// and every pixel is one sample of one view (implicit.frag). In a scene the
// quad is the base plane z = 0 of an N x N field of periods, placed by the
// orthographic camera `camera` (world -> clip), and each fragment carries its
// point of the base plane in periods.
// With the correction in a scene (defined SCENE_CORRECTION) every pixel sees
// the field along the same `scene_view` under the same light, so the facets'
// shares and values are the same for all of them: computed here, once a
// vertex, instead of once a pixel (implicit.frag picks one by its dither).

#include "implicit_model.glsl"

layout(location = 0) in vec3 position;

uniform mat4 camera;      // world -> clip (scene); identity (sweep: position is in NDC)

out vec2 field_pos;       // the fragment's point of the base plane z = 0, periods

#ifdef SCENE_CORRECTION
uniform vec3 scene_view;  // V, unit vector toward the detector
flat out vec4 cumulative[3];
flat out vec3 colours[10];
#endif

void main()
{
    gl_Position = camera * vec4(position, 1.0);
    field_pos = position.xy;
#ifdef SCENE_CORRECTION
    float lit_share[5];
    float shadow_share[5];
    vec3 V = model_view(scene_view);  // the table's turn of the view with the light; else the view itself
    model_shares(V, lit_share, shadow_share);
    float total = 0.0;
    for (int f = 0; f < 5; ++f) total += lit_share[f] + shadow_share[f];
    float bounds[12];
    float acc = 0.0;
    for (int f = 0; f < 5; ++f) {
        vec3 n = facet_normal(f, 2.0 * aspect);
        acc += lit_share[f];
        bounds[2 * f] = acc / total;
        colours[2 * f] = shade(n, V, true);
        acc += shadow_share[f];
        bounds[2 * f + 1] = acc / total;
        colours[2 * f + 1] = shade(n, V, false);
    }
    // only the first 9 bounds decide (u < 1 always lies below the last); the rest never passed
    bounds[9] = 2.0;
    bounds[10] = 2.0;
    bounds[11] = 2.0;
    cumulative[0] = vec4(bounds[0], bounds[1], bounds[2], bounds[3]);
    cumulative[1] = vec4(bounds[4], bounds[5], bounds[6], bounds[7]);
    cumulative[2] = vec4(bounds[8], bounds[9], bounds[10], bounds[11]);
#endif
}
