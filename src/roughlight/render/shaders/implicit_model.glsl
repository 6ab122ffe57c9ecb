// roughlight's implicit rough surface: what both stages of the implicit
// shader share (included by implicit.vert and implicit.frag through
// roughlight.gl's `#include`): the model's uniforms, the facet normals, the
// OpenGL lighting equation of one facet and the first-order correction's
// closed-form facet shares.
//
// Facets, in order: 0 top, 1 east (+x), 2 west (-x), 3 north (+y), 4 south (-y);
// with s = 2a the side facet facing h has the normal (s h, 1), normalised.
// Lighting equation: lighting.glsl (as roughlight.render.shading); shadowed: ambient only.
// With TABLE_SHARES defined (model 2, the table) the facet shares are read from a table of them over light and
// view directions (roughlight.render.implicit.table) instead of the correction's closed form.

#include "lighting.glsl"

uniform int model;                 // 0 exact form, 1 first-order correction, 2 table
uniform float truncation;          // t in [0, 1]
uniform float aspect;              // a >= 0
uniform vec3 light_dir;            // unit vector toward the light
uniform float light;               // J / 255
uniform float ambient_term;        // m_a * A
uniform float diffuse_reflectance; // m_d
uniform float specular_reflectance;// m_s
uniform float shininess;           // zeta
uniform int specular_model;        // 0 Phong, 1 Blinn-Phong
uniform int shadows;               // 1: inner shadows cast
uniform int specular_shadows;      // 1: shadows take the specular too; 0: the thesis's unshadowed specular
uniform float blend_scale;         // c of the correction's blend weight

vec3 facet_normal(int k, float s)
{
    vec3 n = vec3(0.0, 0.0, 1.0);
    if (k == 1) n = vec3(s, 0.0, 1.0);
    if (k == 2) n = vec3(-s, 0.0, 1.0);
    if (k == 3) n = vec3(0.0, s, 1.0);
    if (k == 4) n = vec3(0.0, -s, 1.0);
    return normalize(n);
}

vec3 shade(vec3 N, vec3 V, bool lit)
{
    vec3 L = light_dir;
    float ndotl = dot(N, L);
    float on = (lit && ndotl > 0.0) ? 1.0 : 0.0;
    float spec_on = (specular_shadows == 1) ? on : (ndotl > 0.0 ? 1.0 : 0.0);
    float spec = (spec_on > 0.0) ? specular_power(N, L, V, ndotl, specular_model == 1, shininess) : 0.0;
    return lit_components(light, ambient_term, diffuse_reflectance, specular_reflectance, on, max(ndotl, 0.0),
                          spec_on, spec);
}

// First-order correction: the lit and shadowed share of each facet, facets in
// the order top, east, west, north, south. With s = 2a, P_t = (1 - t)^2 and
// P_s = (1 - P_t) / 4, a side facet with outward direction h has view shear
// x = s (V.h) / V.z, unmasked share P_s max(1 + x, 0), V-groove masking
// G(x) = min(1, 2 / (1 + x)); two masked facets split the image more like
// their unmasked projections: share = a + w (b - a), a = P_s (1 + x) G(x),
// b = 4 P_s (1 + x) / sum(1 + x), w = t clamp((x_2 - 1) / c, 0, 1), x_2 the
// second-largest view shear, c = blend_scale. Lit part: share * min(1, G(x_L) / G_eff).
// (roughlight.implicit.correction_shares is the same in numpy.)
void correction_shares(vec3 V, out float lit_share[5], out float shadow_share[5])
{
    float s = 2.0 * aspect;
    float t = truncation;
    vec3 L = light_dir;
    bool light_up = L.z > 1e-9 || shadows == 0;
    for (int k = 0; k < 5; ++k) {
        lit_share[k] = 0.0;
        shadow_share[k] = 0.0;
    }
    if (s * t < 1e-9) {                             // the plate
        lit_share[0] = L.z > 0.0 ? 1.0 : 0.0;
        shadow_share[0] = 1.0 - lit_share[0];
        return;
    }
    float top = (1.0 - t) * (1.0 - t);
    float side = (1.0 - top) / 4.0;
    lit_share[0] = light_up ? top : 0.0;
    shadow_share[0] = top - lit_share[0];
    vec2 h[4] = vec2[4](vec2(1.0, 0.0), vec2(-1.0, 0.0), vec2(0.0, 1.0), vec2(0.0, -1.0));
    float x[4];
    float unmasked[4];
    float total = 0.0;
    float first = -1e30;
    float second = -1e30;
    for (int k = 0; k < 4; ++k) {
        x[k] = s * dot(V.xy, h[k]) / V.z;
        unmasked[k] = max(1.0 + x[k], 0.0);
        total += unmasked[k];
        if (x[k] > first) { second = first; first = x[k]; } else if (x[k] > second) { second = x[k]; }
    }
    float w = t * clamp((second - 1.0) / blend_scale, 0.0, 1.0);
    for (int k = 0; k < 4; ++k) {
        float xl = s * dot(L.xy, h[k]) / max(L.z, 1e-12);
        float gv = x[k] > 1.0 ? 2.0 / (1.0 + x[k]) : 1.0;
        float gl = xl > 1.0 ? 2.0 / (1.0 + xl) : 1.0;
        float a = side * unmasked[k] * gv;
        float b = 4.0 * side * unmasked[k] / total;
        float seen = a + w * (b - a);
        float g_eff = seen / max(side * unmasked[k], 1e-30);
        bool faces_light = 1.0 + xl > 0.0 && light_up;
        float lit = 0.0;
        if (faces_light) {
            lit = shadows == 1 ? seen * min(1.0, gl / max(g_eff, 1e-30)) : seen;
        }
        lit = min(lit, seen);
        lit_share[k + 1] = lit;
        shadow_share[k + 1] = seen - lit;
    }
}

#ifdef TABLE_SHARES
// The table of facet shares (roughlight.render.implicit.table): 3-D textures, x the view azimuth (nodes 360 /
// table_azimuths degrees apart from 0, repeating), y the view elevation (nodes table_elevation[], in degrees),
// z the light nodes (the incidence rows in turn, each row's own azimuths). The light is one a draw: its four nodes
// around it (two a row) are the slices table_slices, weighted table_weights. Channels: lit shares of facets 0-3
// (table_lit), lit share of facet 4 and shadowed shares of facets 0-2 (table_mixed), shadowed shares of facets 3-4 (table_shadow).
// V is the view turned with the light to the table's light azimuths (view_turn, applied by the caller), and
// light_dir is the light so turned.
// Their units are bound in the shader (units 1-3; a sweep's views are on unit 0): samplers of two types left on
// one unit fail the program's validation before any uniform can be set. The binding needs
// GL_ARB_shading_language_420pack, enabled at the top of implicit.vert and implicit.frag.
#define MAX_TABLE_ELEVATIONS 64
layout(binding = 1) uniform sampler3D table_lit;
layout(binding = 2) uniform sampler3D table_mixed;
layout(binding = 3) uniform sampler3D table_shadow;
uniform ivec4 table_slices;
uniform vec4 table_weights;
uniform int table_depth;
uniform int table_azimuths;
uniform int table_elevations;
uniform float table_elevation[MAX_TABLE_ELEVATIONS];
uniform mat3 view_turn;
uniform vec4 table_turns;          // each light node's azimuth less the light's, degrees (the view turned with it)
uniform vec4 table_rises;          // each light node's incidence less the light's, degrees
uniform float hot_spot_blend;      // the phase angle, degrees, within which the shadowed part is read turned

// The view's elevation in node units of table_elevation (clamped to the end nodes).
float elevation_node(float e)
{
    int n = table_elevations;
    if (e <= table_elevation[0]) return 0.0;
    if (e >= table_elevation[n - 1]) return float(n - 1);
    int k = 0;
    for (int j = 1; j < MAX_TABLE_ELEVATIONS; ++j) {
        if (j < n && table_elevation[j] <= e) k = j;
    }
    return float(k) + (e - table_elevation[k]) / (table_elevation[k + 1] - table_elevation[k]);
}

// The four light nodes' shares at view azimuth fractions x and elevation rows y, a node k at (x[k], y[k]).
void table_fetch(vec4 x, vec4 y, out vec4 a, out vec4 b, out vec4 c)
{
    a = vec4(0.0);
    b = vec4(0.0);
    c = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        vec3 at = vec3(x[k], y[k], (float(table_slices[k]) + 0.5) / float(table_depth));
        a += table_weights[k] * texture(table_lit, at);
        b += table_weights[k] * texture(table_mixed, at);
        c += table_weights[k] * texture(table_shadow, at);
    }
}

// Each facet's share of the image read in the lattice's frame; near the hot spot (V = L: no shadow seen, a cusp
// the light nodes smear) the part of it in shadow also read with the view turned with the light (each node k at
// its own hot spot: the view's azimuth plus table_turns[k], its elevation plus table_rises[k]), the two blended by
// 1 - phase / hot_spot_blend (roughlight.render.implicit.table.table_shares, the same in numpy).
void table_shares(vec3 V, out float lit_share[5], out float shadow_share[5])
{
    float e = degrees(asin(clamp(V.z, -1.0, 1.0)));
    float phi = degrees(atan(V.y, V.x));
    phi = phi < 0.0 ? phi + 360.0 : phi;
    float half_node = 0.5 / float(table_azimuths);
    float rows = float(table_elevations);
    vec4 a, b, c;
    table_fetch(vec4(phi / 360.0 + half_node), vec4((elevation_node(e) + 0.5) / rows), a, b, c);
    float seen[5] = float[5](a.x + b.y, a.y + b.z, a.z + b.w, a.w + c.x, b.x + c.y);
    float shadow[5] = float[5](b.y, b.z, b.w, c.x, c.y);
    float phase = degrees(acos(clamp(dot(light_dir, V), -1.0, 1.0)));
    float near = clamp(1.0 - phase / hot_spot_blend, 0.0, 1.0);
    if (near > 0.0) {
        vec4 ta, tb, tc;
        vec4 y;
        for (int k = 0; k < 4; ++k) y[k] = (elevation_node(clamp(e + table_rises[k], 0.0, 90.0)) + 0.5) / rows;
        table_fetch((vec4(phi) + table_turns) / 360.0 + half_node, y, ta, tb, tc);
        float turned_seen[5] = float[5](ta.x + tb.y, ta.y + tb.z, ta.z + tb.w, ta.w + tc.x, tb.x + tc.y);
        float turned_shadow[5] = float[5](tb.y, tb.z, tb.w, tc.x, tc.y);
        for (int f = 0; f < 5; ++f) {
            float fraction = seen[f] > 0.0 ? shadow[f] / seen[f] : 0.0;
            float turned_fraction = turned_seen[f] > 1e-9 ? turned_shadow[f] / turned_seen[f] : fraction;
            shadow[f] = seen[f] * (near * turned_fraction + (1.0 - near) * fraction);
        }
    }
    for (int f = 0; f < 5; ++f) {
        lit_share[f] = seen[f] - shadow[f];
        shadow_share[f] = shadow[f];
    }
}

vec3 model_view(vec3 V) { return view_turn * V; }
void model_shares(vec3 V, out float lit_share[5], out float shadow_share[5]) { table_shares(V, lit_share, shadow_share); }
#else
#ifdef GIVEN_SHARES
// The clipped scene (with the scene's correction): the facets' shares of this frame's one view and
// light, clipped exactly on the CPU (roughlight.render.implicit.shader.clipped_shares, the exact reference's areas)
// and given as uniforms, facets in the order top, east, west, north, south.
uniform float given_lit[5];
uniform float given_shadow[5];
vec3 model_view(vec3 V) { return V; }
void model_shares(vec3 V, out float lit_share[5], out float shadow_share[5])
{
    for (int f = 0; f < 5; ++f) {
        lit_share[f] = given_lit[f];
        shadow_share[f] = given_shadow[f];
    }
}
#else
vec3 model_view(vec3 V) { return V; }
void model_shares(vec3 V, out float lit_share[5], out float shadow_share[5]) { correction_shares(V, lit_share, shadow_share); }
#endif
#endif
