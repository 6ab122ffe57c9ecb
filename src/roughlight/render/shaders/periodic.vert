#version 330 core
// One period of the rough surface, instanced: each instance is one lattice
// copy of the period drawn into one view's tile of the framebuffer.
//
// The projection is an oblique parallel projection along the view (or light)
// direction D onto the base plane z = 0: a point p lands at
//     cell = p.xy - p.z * (D.x / D.z, D.y / D.z),
// where the ray through p along D crosses z = 0. Seen along D, the infinite
// periodic surface is periodic in `cell` with the unit lattice, so the unit
// cell [0,1)^2 of `cell` is exactly one period of the projected image:
// its pixel mean is the mean over the infinite surface. The tile maps that
// unit cell to its pixels. Depth is the height: along a ray coming down from
// the detector the first surface hit is the highest one.
//
// Instance matrix columns (pyrender uploads poses so that inst_m[c] = pose[:, c]):
//   inst_m[0].xy : lattice offset (k, l) of this copy
//   inst_m[1].xy : shear (D.x / D.z, D.y / D.z)
//   inst_m[2].xyz: unit vector toward the detector, V
//   inst_m[3].xy : the view's tile: integer cell offset K of its slot
//   inst_m[3].z  : the view's slot number in the batch (counting passes)

layout(location = 0) in vec3 position;
layout(location = NORMAL_LOC) in vec3 normal;
layout(location = FACET_LOC) in vec2 facet;  // x: the facet's index in the period, y: its lit state
layout(location = INST_M_LOC) in mat4 inst_m;

uniform float depth_scale;   // 1 / (height range of the surface)
uniform mat2 sampling;       // cell coordinates -> window pixels
uniform vec2 surface_shift;  // sub-pixel translation of the whole surface (jitter), periods
uniform vec2 ndc_scale;      // 2 / framebuffer size

out vec3 frag_local;         // position within the period (periodic lookups)
flat out vec3 frag_vertex;   // one vertex of the facet, within the period: a point of its plane
out vec3 frag_normal;        // true face normal (never averaged)
out vec2 frag_cell;          // oblique cell coordinates: kept only inside [0,1)^2
flat out vec3 frag_view;
flat out float frag_facet;
flat out float frag_slot;       // the view's slot number in the batch
flat out float frag_lit_state;  // 0: test the shadow map, 1: the facet is wholly lit, 2: wholly in shadow

void main()
{
    vec3 p = position + vec3(inst_m[0].xy + surface_shift, 0.0);
    vec2 cell = p.xy - p.z * inst_m[1].xy;
    vec2 window = sampling * (cell + inst_m[3].xy);
    gl_Position = vec4(window * ndc_scale - 1.0, 0.9 - 1.8 * p.z * depth_scale, 1.0);
    frag_local = position;
    frag_vertex = position;
    frag_normal = normal;
    frag_cell = cell;
    frag_view = inst_m[2].xyz;
    frag_facet = facet.x;
    frag_slot = inst_m[3].z;
    frag_lit_state = facet.y;
    // clip each copy to its own tile, before rasterization
    gl_ClipDistance[0] = cell.x;
    gl_ClipDistance[1] = 1.0 - cell.x;
    gl_ClipDistance[2] = cell.y;
    gl_ClipDistance[3] = 1.0 - cell.y;
}
