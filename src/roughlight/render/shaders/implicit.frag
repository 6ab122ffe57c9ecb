#version 330 core
#ifdef TABLE_SHARES
#extension GL_ARB_shading_language_420pack : require
#endif
// roughlight's implicit rough surface: one flat quad that reflects like a
// periodic grid of truncated square pyramids (Slattery 2001's explicit
// surface), with truncation t and aspect a as uniforms. No mesh, no table.
//
// Surface (units of the period, the pyramid's base width):
//   h(x, y) = min(2a c(x, y), t a),  c = min(fx, 1 - fx, fy, 1 - fy),  fx = fract(x);
// within one cell the solid under h is convex (five half-spaces: the top and
// the four sides east +x, west -x, north +y, south -y).
//
// model 0, EXACT FORM: the pixel's view ray is cast through h cell by cell;
//   the first facet met is seen; a second ray toward the light decides lit or
//   shadowed. The pixel stores that facet's value of the lighting equation.
// model 1, FIRST-ORDER CORRECTION: no ray casting. The share of the image each
//   facet fills, lit and shadowed, is a closed form (README, "An implicit
//   rough surface"); the pixel shows the facet whose cumulative share its
//   dither threshold falls in, so the image mean is the facet sum.
// The lighting equation and the correction's shares are in implicit_model.glsl.
// Output: r = diffuse, g = specular, b = total, a = 1; 8-bit in the framebuffer.
//
// Sweep (field_size == 0): pixel p (linear index y * fb_width + x) is sample
//   k = p mod M of view p / M, M = `samples`; sample k is the point
//   ((k + 1/2) / M, ((k g mod M) + 1/2) / M) of one period (a Fibonacci
//   lattice, g = `generator`); the view's unit vector V comes from `views`.
// Scene (field_size > 0): the fragment is a point of the base plane of an
//   N x N field seen along `scene_view`: `field_pos` moved within the pixel's
//   footprint by the Fibonacci point of its index (stochastic anti-aliasing);
//   outside the field is discarded.
// Model 2, the table (defined TABLE_SHARES): as the correction, with the shares read from the table
//   (implicit_model.glsl, table_shares) in place of its closed form.
// Scene with the correction or the table (defined SCENE_CORRECTION): one view and one light
//   for the whole picture (a collimated detector, a directional light), so the
//   vertex stage computes the facets' shares and values once (implicit.vert)
//   and a pixel only picks one by its dither threshold
//   u = fract(x a1 + y a2) (a rank-1 lattice over the pixels, a1, a2 the R2
//   sequence's constants: equidistributed, no integer arithmetic).

#include "implicit_model.glsl"

uniform float field_size;          // N (scene), 0 (sweep)

#ifdef SCENE_CORRECTION

in vec2 field_pos;
flat in vec4 cumulative[3];        // the facets' cumulative shares (lit, shadowed; facet by facet), 9 used
flat in vec3 colours[10];          // each share's value: facet f lit at 2 f, shadowed at 2 f + 1

out vec4 frag_color;

const vec2 DITHER = vec2(0.7548776662, 0.5698402910);

void main()
{
    if (any(lessThan(field_pos, vec2(0.0))) || any(greaterThanEqual(field_pos, vec2(field_size)))) {
        discard;
    }
    // the share whose cumulative interval holds u: walk the bounds in order, static indices only
    // (llvmpipe pays for a dynamically indexed input on every pixel)
    vec4 u = vec4(fract(dot(gl_FragCoord.xy, DITHER)));
    bvec4 past0 = greaterThanEqual(u, cumulative[0]);
    bvec4 past1 = greaterThanEqual(u, cumulative[1]);
    vec3 c = colours[0];
    c = past0.x ? colours[1] : c;
    c = past0.y ? colours[2] : c;
    c = past0.z ? colours[3] : c;
    c = past0.w ? colours[4] : c;
    c = past1.x ? colours[5] : c;
    c = past1.y ? colours[6] : c;
    c = past1.z ? colours[7] : c;
    c = past1.w ? colours[8] : c;
    c = u.x >= cumulative[2].x ? colours[9] : c;
    frag_color = vec4(c, 1.0);
}

#else
#ifdef SCENE_SAMPLES

// Scene with the exact form, shares once a frame (defined SCENE_SAMPLES): one view and one light for the whole
// picture, so a first pass casts the rays of `samples` Fibonacci points of one period once (the sweep's pass, one
// view) into `frame_samples`; here a pixel only shows the sample its dither threshold picks, k = floor(u M).

in vec2 field_pos;

uniform sampler2D frame_samples;   // RGBA8: sample k's value at texel (k % samples_width, k / samples_width)
uniform int samples_width;
uniform int samples;               // M

out vec4 frag_color;

const vec2 DITHER = vec2(0.7548776662, 0.5698402910);

void main()
{
    if (any(lessThan(field_pos, vec2(0.0))) || any(greaterThanEqual(field_pos, vec2(field_size)))) {
        discard;
    }
    int k = min(int(fract(dot(gl_FragCoord.xy, DITHER)) * float(samples)), samples - 1);
    frag_color = texelFetch(frame_samples, ivec2(k % samples_width, k / samples_width), 0);
}

#else

in vec2 field_pos;


uniform int samples;               // M: pixels a view (sweep) / dither period (scene)
uniform int generator;             // g: the Fibonacci number before M
uniform int fb_width;
uniform int n_views;
uniform int views_width;
uniform sampler2D views;           // RGBA32F: xyz = V of view k at texel (k % views_width, k / views_width)

uniform vec3 scene_view;           // V (scene)

out vec4 frag_color;

const int MAX_CELLS = 1024;

// First cell-solid the ray p0 + tau d (0 <= tau <= tau_end) runs through for
// more than min_length; returns its facet (0-4) or -1, with tau and the cell.
int cast_ray(vec3 p0, vec3 d, float tau_end, ivec2 cell, float min_length,
             out float tau_hit, out ivec2 cell_hit)
{
    float s = 2.0 * aspect;
    float H = truncation * aspect;
    vec3 g[5] = vec3[5](vec3(0.0, 0.0, 1.0), vec3(s, 0.0, 1.0), vec3(-s, 0.0, 1.0),
                        vec3(0.0, s, 1.0), vec3(0.0, -s, 1.0));
    float gp[5];
    float gd[5];
    for (int k = 0; k < 5; ++k) {
        gp[k] = dot(g[k], p0);
        gd[k] = dot(g[k], d);
    }
    ivec2 stp = ivec2(d.x > 0.0 ? 1 : -1, d.y > 0.0 ? 1 : -1);
    vec2 dt = vec2(d.x != 0.0 ? abs(1.0 / d.x) : 1e30, d.y != 0.0 ? abs(1.0 / d.y) : 1e30);
    vec2 wall = vec2(d.x > 0.0 ? float(cell.x + 1) : float(cell.x),
                     d.y > 0.0 ? float(cell.y + 1) : float(cell.y)) - p0.xy;
    vec2 t_wall = vec2(d.x != 0.0 ? wall.x / d.x : 1e30, d.y != 0.0 ? wall.y / d.y : 1e30);
    float tau_in = 0.0;
    tau_hit = 0.0;
    cell_hit = cell;
    for (int it = 0; it < MAX_CELLS; ++it) {
        float cx = float(cell.x);
        float cy = float(cell.y);
        float off[5] = float[5](H, s * (cx + 1.0), -s * cx, s * (cy + 1.0), -s * cy);
        float enter = -1e30;
        int facet = 0;
        float leave = min(min(t_wall.x, t_wall.y), tau_end);
        bool never = false;
        for (int k = 0; k < 5; ++k) {
            float g0 = gp[k] - off[k];
            if (gd[k] < 0.0) {
                float c = -g0 / gd[k];
                if (c > enter) { enter = c; facet = k; }
            } else if (gd[k] > 0.0) {
                leave = min(leave, -g0 / gd[k]);
            } else if (g0 > 0.0) {
                never = true;
            }
        }
        float start = max(enter, tau_in);
        if (!never && start <= leave - min_length && start <= tau_end && (min_length == 0.0 || leave > min_length)) {
            tau_hit = start;
            cell_hit = cell;
            return facet;
        }
        if (t_wall.x <= t_wall.y) {
            tau_in = t_wall.x;
            cell.x += stp.x;
            t_wall.x += dt.x;
        } else {
            tau_in = t_wall.y;
            cell.y += stp.y;
            t_wall.y += dt.y;
        }
        if (tau_in >= tau_end) {
            return -1;
        }
    }
    return -1;
}

// Exact form: facet seen at the base-plane point q (oblique coordinates) and whether it is lit.
int exact_facet(vec2 q, vec3 V, out bool lit)
{
    float s = 2.0 * aspect;
    float H = truncation * aspect;
    vec3 L = light_dir;
    lit = true;
    if (H < 1e-9) {                       // the plate
        lit = dot(vec3(0.0, 0.0, 1.0), L) > 0.0;
        return 0;
    }
    vec3 p0 = vec3(q + H * V.xy / V.z, H);
    ivec2 base = ivec2(floor(p0.xy));
    p0.xy -= vec2(base);                  // periodic: start in cell (0, 0), small numbers
    float tau;
    ivec2 cell;
    int facet = cast_ray(p0, -V, H / V.z * 1.000001 + 1e-6, ivec2(0), 0.0, tau, cell);
    if (facet < 0) facet = 0;             // float noise at a ridge: the top is as good as any
    lit = dot(facet_normal(facet, s), L) > 0.0;
    if (lit && shadows == 1) {
        if (L.z < 1e-9) {
            lit = false;
        } else {
            // restart in cell (0, 0): plane offsets stay small, so the
            // self-shadow slack can stay small too
            vec3 p = p0 - tau * V;
            p.xy -= vec2(cell);
            // and put the point back on its facet's plane (float32 drift along a long view ray)
            float heights[5] = float[5](H, s * (1.0 - p.x), s * p.x, s * (1.0 - p.y), s * p.y);
            p.z = heights[facet];
            float tau_l;
            ivec2 cell_l;
            int blocker = cast_ray(p, L, max(H - p.z, 0.0) / L.z, ivec2(0), 1e-5, tau_l, cell_l);
            lit = blocker < 0;
        }
    }
    return facet;
}

// The facet pixel k shows, and whether lit: the dither threshold
// ((k g mod M) + 1/2) / M walks the facets' cumulative shares.
int correction_facet(vec3 V, int k, out bool lit)
{
    float lit_share[5];
    float shadow_share[5];
    model_shares(V, lit_share, shadow_share);
    float u = (float((k * generator) % samples) + 0.5) / float(samples);
    float total = 0.0;
    for (int f = 0; f < 5; ++f) total += lit_share[f] + shadow_share[f];
    u *= total;
    float acc = 0.0;
    for (int f = 0; f < 5; ++f) {
        acc += lit_share[f];
        if (u < acc) { lit = true; return f; }
        acc += shadow_share[f];
        if (u < acc) { lit = false; return f; }
    }
    lit = false;
    return 0;
}

void main()
{
    vec2 q;
    vec3 V;
    int k;
    if (field_size > 0.0) {
        if (any(lessThan(field_pos, vec2(0.0))) || any(greaterThanEqual(field_pos, vec2(field_size)))) {
            discard;
        }
        ivec2 px = ivec2(gl_FragCoord.xy);
        k = (px.y * fb_width + px.x) % samples;
        // a point of the pixel's footprint, not its centre: pixels a whole number of periods apart
        // would otherwise sample the same point of the period (aliasing once a pixel spans half a period)
        vec2 jitter = vec2((float(k) + 0.5) / float(samples),
                           (float((k * generator) % samples) + 0.5) / float(samples)) - 0.5;
        q = field_pos + jitter.x * dFdx(field_pos) + jitter.y * dFdy(field_pos);
        V = scene_view;
    } else {
        ivec2 px = ivec2(gl_FragCoord.xy);
        int linear = px.y * fb_width + px.x;
        int view = linear / samples;
        if (view >= n_views) {
            frag_color = vec4(0.0);
            return;
        }
        k = linear - view * samples;
        V = texelFetch(views, ivec2(view % views_width, view / views_width), 0).xyz;
        q = vec2((float(k) + 0.5) / float(samples), (float((k * generator) % samples) + 0.5) / float(samples));
    }
    float s = 2.0 * aspect;
    bool lit;
    int facet;
    V = model_view(V);                    // the table's turn of the view with the light; else V itself
    if (model == 0) {
        facet = exact_facet(q, V, lit);
    } else {
        facet = correction_facet(V, k, lit);
    }
    frag_color = vec4(shade(facet_normal(facet, s), V, lit), 1.0);
}

#endif
#endif
