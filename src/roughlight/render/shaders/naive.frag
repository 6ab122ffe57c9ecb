#version 330 core
// The study's lighting equation as a drop-in for pyrender's mesh.frag, for
// the `naive` method: pyrender's own render loop (its mesh.vert, its per-render
// directional shadow map with its PCF and bias) draws a finite patch; only the
// shading equation is ours. pyrender sets no uniforms of ours, so the
// material's factors carry the settings:
//   material.base_color_factor = (m_d, m_s, m_a * A, shininess / 128)
//   material.metallic_factor   = 0 Phong, 1 Blinn-Phong
// and the light's intensity is J / 255. Output channels as the fast method:
// r = diffuse (with ambient), g = specular, b = total.

struct DirectionalLight {
    vec3 color;
    float intensity;
    vec3 direction;
#ifdef DIRECTIONAL_LIGHT_SHADOWS
    sampler2D shadow_map;
    mat4 light_matrix;
#endif
};

struct Material {
    vec3 emissive_factor;
#ifdef USE_METALLIC_MATERIAL
    vec4 base_color_factor;
    float metallic_factor;
    float roughness_factor;
#endif
};

uniform DirectionalLight directional_lights[MAX_DIRECTIONAL_LIGHTS];
uniform int n_directional_lights;
uniform Material material;
uniform mat4 V;

in vec3 frag_position;
in vec3 frag_normal;
#ifdef GOURAUD
in vec2 vertex_light;   // (max(N.L, 0), S) interpolated from the vertices
#endif

out vec4 frag_color;

#ifdef DIRECTIONAL_LIGHT_SHADOWS
// pyrender's own shadow test (mesh.frag): 3x3 PCF with its slope bias
float compare_depth(sampler2D depths, vec2 uv, float compare) {
    return compare > texture(depths, uv.xy).r ? 1.0 : 0.0;
}
float shadow_lerp(sampler2D depths, vec2 size, vec2 uv, float compare) {
    vec2 texel = vec2(1.0) / size;
    vec2 f = fract(uv * size + 0.5);
    vec2 corner = floor(uv * size + 0.5) / size;
    float lb = compare_depth(depths, corner, compare);
    float lt = compare_depth(depths, corner + texel * vec2(0.0, 1.0), compare);
    float rb = compare_depth(depths, corner + texel * vec2(1.0, 0.0), compare);
    float rt = compare_depth(depths, corner + texel * vec2(1.0, 1.0), compare);
    return mix(mix(lb, lt, f.y), mix(rb, rt, f.y), f.x);
}
float shadow_calc(mat4 light_matrix, sampler2D shadow_map, float nl) {
    vec4 proj = light_matrix * vec4(frag_position, 1.0);
    vec3 coords = proj.xyz / proj.w * 0.5 + 0.5;
    float bias = max(0.001 * (1.0 - nl), 0.0001) / proj.w;
    vec2 size = vec2(textureSize(shadow_map, 0));
    float result = 0.0;
    for (int x = -1; x <= 1; x++) {
        for (int y = -1; y <= 1; y++) {
            result += shadow_lerp(shadow_map, size, coords.xy + vec2(x, y) / size, coords.z - bias);
        }
    }
    return coords.z > 1.0 ? 0.0 : result / 9.0;
}
#endif

#include "lighting.glsl"

void main()
{
    vec4 factors = vec4(1.0, 1.0, 0.0, 0.5);
    float blinn = 0.0;
#ifdef USE_METALLIC_MATERIAL
    factors = material.base_color_factor;
    blinn = material.metallic_factor;
#endif
    float m_d = factors.x, m_s = factors.y, ambient_term = factors.z, shininess = factors.w * 128.0;
    vec3 N = normalize(frag_normal);
    // orthographic camera: the direction to the detector is the camera's +z axis
    vec3 view = normalize(vec3(V[0][2], V[1][2], V[2][2]));
    vec3 L = normalize(-directional_lights[0].direction);
    float J = directional_lights[0].intensity;
    float ndotl = dot(N, L);
#ifdef GOURAUD
    float lit = 1.0;   // the vertices' N.L already gates the light; the shadow map still applies
#else
    float lit = ndotl > 0.0 ? 1.0 : 0.0;
#endif
#ifdef DIRECTIONAL_LIGHT_SHADOWS
    if (lit > 0.0) {
        lit = 1.0 - shadow_calc(directional_lights[0].light_matrix, directional_lights[0].shadow_map, clamp(ndotl, 0.0, 1.0));
    }
#endif
#ifdef GOURAUD
    // the angular terms come from the vertices; only the shadow is per fragment
    vec3 I = lit_components(J, ambient_term, m_d, m_s, lit, vertex_light.x, lit, vertex_light.y);
#else
    float s = ndotl > 0.0 ? specular_power(N, L, view, ndotl, blinn > 0.5, shininess) : 0.0;
    vec3 I = lit_components(J, ambient_term, m_d, m_s, lit, max(ndotl, 0.0), lit, s);
#endif
    frag_color = vec4(I, 1.0);
}
