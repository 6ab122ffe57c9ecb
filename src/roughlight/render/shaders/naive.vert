#version 330 core
// pyrender's mesh.vert for the naive method, plus Gouraud shading: with
// GOURAUD defined the lighting equation's two angular terms are evaluated at
// the vertices (with the mesh's averaged vertex normals) and interpolated
// across each triangle, as OpenGL's fixed function does; shadows stay per
// fragment (pyrender's shadow map). Without it, the fragment shader
// evaluates the equation per fragment with the interpolated normal: that is
// flat shading for a mesh with true face normals, Phong shading for averaged
// vertex normals.

layout(location = 0) in vec3 position;
layout(location = NORMAL_LOC) in vec3 normal;
layout(location = INST_M_LOC) in mat4 inst_m;

uniform mat4 M;
uniform mat4 V;
uniform mat4 P;

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
uniform Material material;

out vec3 frag_position;
out vec3 frag_normal;
#ifdef GOURAUD
out vec2 vertex_light;   // (max(N.L, 0), S) at this vertex
#endif

#include "lighting.glsl"

void main()
{
    gl_Position = P * V * M * inst_m * vec4(position, 1.0);
    frag_position = vec3(M * inst_m * vec4(position, 1.0));
    frag_normal = normalize(mat3(transpose(inverse(M * inst_m))) * normal);
#ifdef GOURAUD
    float shininess = 64.0;
    float blinn = 0.0;
#ifdef USE_METALLIC_MATERIAL
    shininess = material.base_color_factor.w * 128.0;
    blinn = material.metallic_factor;
#endif
    vec3 N = frag_normal;
    vec3 L = normalize(-directional_lights[0].direction);
    vec3 view = normalize(vec3(V[0][2], V[1][2], V[2][2]));
    float ndotl = dot(N, L);
    float s = ndotl > 0.0 ? specular_power(N, L, view, ndotl, blinn > 0.5, shininess) : 0.0;
    vertex_light = vec2(max(ndotl, 0.0), s);
#endif
}
