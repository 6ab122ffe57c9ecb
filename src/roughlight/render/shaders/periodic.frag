#version 330 core
// The OpenGL lighting equation of the study (lighting.glsl), per fragment, flat facets; shadowed fragments keep the
// ambient term only (periodic_shadow.glsl).
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

out vec4 frag_color;

#include "lighting.glsl"
#include "periodic_shadow.glsl"

void main()
{
    vec3 N = normalize(frag_normal);
    vec3 L = light_dir;
    vec3 V = frag_view;
    float ndotl = dot(N, L);
    float lit = lit_by_light(N, ndotl, 0.0);
    float spec_lit = (specular_shadows == 1) ? lit : (ndotl > 0.0 ? 1.0 : 0.0);
    float s = (spec_lit > 0.0) ? specular_power(N, L, V, ndotl, specular_model == 1, shininess) : 0.0;
    vec3 I = lit_components(light, ambient_term, diffuse_reflectance, specular_reflectance, lit, max(ndotl, 0.0),
                            spec_lit, s);
#ifdef FACET_IDS
    // which facet, lit or not: id = 2 facet + lit + 1 in 16 bits (red low byte, green high byte); 0 = no surface
    float id = 2.0 * frag_facet + lit + 1.0;
    frag_color = vec4(mod(id, 256.0), floor(id / 256.0), 0.0, 255.0) / 255.0;
#else
    frag_color = vec4(I, 1.0);
#endif
}
