#version 330 core
// The OpenGL lighting equation of the study, per fragment, flat facets:
//   I = J (m_a A + m_d max(N.L, 0) + m_s S),
//   S = max(R.V, 0)^zeta (Phong, R = 2 (N.L) N - L) or max(N.H, 0)^zeta (Blinn),
//   S = 0 where N.L <= 0; shadowed fragments keep the ambient term only.
// Output channels (each stored as an 8-bit value by the framebuffer):
//   r = diffuse (with ambient), g = specular, b = total, a = 1 (coverage);
//   with FACET_IDS (adaptive sampling) the facet and whether it is lit instead (see the end of main).

in vec3 frag_local;
flat in vec3 frag_vertex;
in vec3 frag_normal;
in vec2 frag_cell;
flat in vec3 frag_view;
flat in float frag_facet;

uniform vec3 light_dir;            // unit vector toward the light
uniform float light;               // J / 255
uniform float ambient_term;        // m_a * A
uniform float diffuse_reflectance; // m_d
uniform float specular_reflectance;// m_s
uniform float shininess;           // zeta
uniform int specular_model;        // 0 Phong, 1 Blinn-Phong
uniform int specular_shadows;      // 1: shadows take the specular too; 0: the thesis's unshadowed specular
uniform int shadow_mode;           // 0 none, 1 periodic shadow map, 2 all in shadow (grazing light)
uniform sampler2D shadow_map;      // heights of the first surface along each light ray, one period
uniform int shadow_size;           // texels per period of the shadow map
uniform vec2 light_shear;          // (L.x / L.z, L.y / L.z)
uniform float depth_scale;
uniform float shadow_bias;         // height units

out vec4 frag_color;

float occluder_height(ivec2 texel)
{
    float ndc = 2.0 * texelFetch(shadow_map, texel, 0).r - 1.0;
    return (0.9 - ndc) / (1.8 * depth_scale);
}

void main()
{
    vec3 N = normalize(frag_normal);
    vec3 L = light_dir;
    vec3 V = frag_view;
    float ndotl = dot(N, L);
    float lit = ndotl > 0.0 ? 1.0 : 0.0;
    if (lit > 0.0 && shadow_mode == 2) {
        lit = 0.0;
    }
    if (lit > 0.0 && shadow_mode == 1) {
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
    float s = 0.0;
    float spec_lit = (specular_shadows == 1) ? lit : (ndotl > 0.0 ? 1.0 : 0.0);
    if (spec_lit > 0.0) {
        float base;
        if (specular_model == 0) {
            vec3 R = 2.0 * ndotl * N - L;
            base = max(dot(R, V), 0.0);
        } else {
            base = max(dot(N, normalize(L + V)), 0.0);
        }
        s = (shininess == 0.0) ? 1.0 : pow(base, shininess);
    }
    float diffuse = light * (ambient_term + lit * diffuse_reflectance * max(ndotl, 0.0));
    float specular = light * spec_lit * specular_reflectance * s;
#ifdef FACET_IDS
    // which facet, lit or not: id = 2 facet + lit + 1 in 16 bits (red low byte, green high byte); 0 = no surface
    float id = 2.0 * frag_facet + lit + 1.0;
    frag_color = vec4(mod(id, 256.0), floor(id / 256.0), 0.0, 255.0) / 255.0;
#else
    frag_color = vec4(diffuse, specular, diffuse + specular, 1.0);
#endif
}
