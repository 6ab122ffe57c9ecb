// Is this point of the surface lit? The periodic shadow map's test of periodic.frag (values and facet
// identities); kept apart so that every program testing the shadow map decides every fragment alike. The includer
// declares frag_local (the point within the period) and frag_vertex (a vertex of its facet, flat).

uniform int shadow_mode;           // 0 none, 1 periodic shadow map, 2 all in shadow (grazing light)
uniform sampler2D shadow_map;      // heights of the first surface along each light ray, one period
uniform int shadow_size;           // texels per period of the shadow map
uniform vec2 light_shear;          // (L.x / L.z, L.y / L.z)
uniform float depth_scale;
uniform float shadow_bias;         // height units

float occluder_height(ivec2 texel)
{
    float ndc = 2.0 * texelFetch(shadow_map, texel, 0).r - 1.0;
    return (0.9 - ndc) / (1.8 * depth_scale);
}

// 1.0 where the light reaches this point of a facet with unit normal N (ndotl = N.L), else 0.0.
// lit_state: 0 test the shadow map, 1 the facet is known wholly lit, 2 known wholly in shadow.
float lit_by_light(vec3 N, float ndotl, float lit_state)
{
    float lit = ndotl > 0.0 ? 1.0 : 0.0;
    if (lit > 0.0 && (shadow_mode == 2 || lit_state > 1.5)) {
        lit = 0.0;
    }
    if (lit > 0.0 && shadow_mode == 1 && lit_state < 0.5) {
        // light-oblique coordinates of this point (periodic with the lattice)
        float size = float(shadow_size);
        vec2 st = (frag_local.xy - frag_local.z * light_shear) * size;
        vec2 texel_corner = floor(st);
        ivec2 texel = ivec2(mod(texel_corner, size));
        // receiver plane: this facet's height at the texel centre, so that a
        // facet never shadows itself (no acne) whatever its slope. Taken from
        // the plane through a vertex (flat), not from the interpolated point:
        // interpolated x, y and z drift apart by ~1e-6 far out in a large
        // framebuffer, which on a low surface is more than the bias
        vec2 slope = vec2(-N.x / N.z, -N.y / N.z);
        vec2 grad = slope / (1.0 - dot(slope, light_shear));
        vec2 vertex_oblique = frag_vertex.xy - frag_vertex.z * light_shear;
        float z_receiver = frag_vertex.z + dot(grad, (texel_corner + 0.5) / size - vertex_oblique);
        lit = (z_receiver >= occluder_height(texel) - shadow_bias) ? 1.0 : 0.0;
    }
    return lit;
}
