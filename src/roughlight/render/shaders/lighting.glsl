// The study's lighting equation, the one GLSL copy of it: every program includes this file (periodic.frag,
// implicit_model.glsl, naive.vert, naive.frag) and only it computes the specular power. Its numpy twin is
// roughlight.render.shading; the equation (docs/conventions.md), each term on the 0-1 scale of J = light / 255:
//   I = J (m_a A + m_d max(N.L, 0) + m_s S),
//   S = max(R.V, 0)^zeta (Phong, R = 2 (N.L) N - L) or max(N.H, 0)^zeta (Blinn-Phong, H = normalize(L + V)),
//   S = 0 where N.L <= 0; shadowed points keep the ambient term only.

// S where N.L > 0: the specular power of a facet of unit normal N toward the light L and the detector V
// (unit vectors), with ndotl = N.L and the exponent zeta (0: S = 1)
float specular_power(vec3 N, vec3 L, vec3 V, float ndotl, bool blinn, float zeta)
{
    float base = blinn ? max(dot(N, normalize(L + V)), 0.0) : max(dot(2.0 * ndotl * N - L, V), 0.0);
    return (zeta == 0.0) ? 1.0 : pow(base, zeta);
}

// (diffuse with its ambient term, specular, total): lit gates the diffuse and spec_lit the specular (1 lit,
// 0 in shadow or facing away, between for a shadow test's fraction), cosine is max(N.L, 0) (or that value
// interpolated from the vertices), S the specular power
vec3 lit_components(float J, float ambient_term, float m_d, float m_s, float lit, float cosine, float spec_lit,
                    float S)
{
    float diffuse = J * (ambient_term + lit * m_d * cosine);
    float specular = J * spec_lit * m_s * S;
    return vec3(diffuse, specular, diffuse + specular);
}
